#pragma once
// Physical values that several parts of settle fall back on when a case or a caller gives none:
// the fluid of a case that names none (water near 20 C, rounded: the IAPWS viscosity at 20 C is
// 1.0016e-3 Pa s, see io/fluid_presets.hpp for the exact preset), a particle density and the
// magnitude of gravity. The case schema (io/case_schema.cpp) declares fluid.density,
// fluid.dynamic_viscosity and fluid.gravity with these constants, so a case and the analysis's
// structs (analysis/observables.hpp, analysis/correlations.hpp) and `settle predict` without a case
// share one value; particle_density_si is the analysis's fallback only (the schema declares
// particle.density itself).
namespace settle::defaults {

inline constexpr double fluid_density_si = 998.2;       ///< kg/m^3
inline constexpr double dynamic_viscosity_si = 1.0e-3;  ///< Pa s
inline constexpr double particle_density_si = 1050.0;   ///< kg/m^3
inline constexpr double gravity_si = 9.81;              ///< m/s^2, magnitude (the schema's vector is [0, 0, -9.81])

}  // namespace settle::defaults
