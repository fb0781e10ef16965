#pragma once
// Plausibility of a case's physical inputs: values that the schema accepts (every key is SI) but
// that look like a unit slip, said before the preflight judges the grid, so that a particle of
// "2 m" is recognised as 2 mm written in the wrong unit rather than reported as a resolution to
// raise. Warnings, not refusals: each can be meant (a 20 cm body, a particle lighter than air).
#include <string>
#include <vector>

#include "coupling/setup.hpp"
#include "io/schema.hpp"

namespace settle::io {

/// The thresholds, chosen far from the particles settle is made for (sediment grains, ash,
/// microplastics, beads: 10 um to 2 cm, 50 to 20000 kg/m^3) and near the value a slip by a factor
/// 1000 gives for them.
inline constexpr double kLargestPlausibleDiameterSi = 0.1;           ///< d_eq above 10 cm: mm written as m?
inline constexpr double kLightestPlausibleParticleDensitySi = 50.0;  ///< below: g/cm^3 written as kg/m^3?
inline constexpr double kLiquidDensitySi = 500.0;                    ///< a fluid denser is a liquid
/// A fluid this light is a gas; with a liquid's viscosity (above kLiquidViscositySi) it is a slip.
inline constexpr double kLightestPlausibleLiquidDensitySi = 5.0;
inline constexpr double kLiquidViscositySi = 5.0e-4;  ///< Pa s: water's is 1e-3, air's 1.8e-5

/// One message per likely slip, naming the key, the value and the value likely meant.
std::vector<std::string> plausibility_warnings(const CaseValues& values, const coupling::SimulationSetup& setup);

/// "fluid: rho_f = 998.2 kg/m^3, mu = 0.001 Pa s (nu = 1.002e-06 m^2/s), |g| = 9.81 m/s^2; particle:
/// spheroid, d_eq = 1.26 mm, rho_p = 1100 kg/m^3 (rho_p/rho_f = 1.102), free": the physical
/// inputs, printed at the start of a run.
std::string physical_properties_text(const coupling::SimulationSetup& setup);

}  // namespace settle::io
