#pragma once
// Fluid presets of the case file ([fluid] preset = "water" | "glycerol-water", with temperature in
// degrees Celsius): density and dynamic viscosity from published correlations, written into the
// case values so that the run, `settle predict` and case.resolved.toml all use the same numbers.
// Sources and accuracy: docs/case-file.md, section "Fluid presets".
#include <string>
#include <vector>

#include "io/schema.hpp"

namespace settle::io {

/// Density and dynamic viscosity of a liquid at one temperature.
struct FluidProperties {
  double density_si = 0.0;            ///< kg/m^3
  double dynamic_viscosity_si = 0.0;  ///< Pa s
};

/// Density of air-free liquid water at 101.325 kPa, 0-100 C: Kell's formula (Kell 1975, J. Chem.
/// Eng. Data 20, 97, doi:10.1021/je60064a005) with the coefficients of Bettin and Spieweck (1990,
/// PTB-Mitteilungen 100, 195) for ITS-90 temperatures.
double water_density_si(double temperature_c);

/// Viscosity of water from the IAPWS 2008 formulation (Huber et al. 2009, J. Phys. Chem. Ref. Data
/// 38, 101, doi:10.1063/1.3088050) at absolute temperature and density, without the critical
/// enhancement (mu2 = 1, which the release allows outside the near-critical region).
double iapws2008_viscosity_si(double temperature_k, double density_si);

/// Liquid water at 101.325 kPa and `temperature_c` in [0, 100] C: the density of
/// water_density_si and the IAPWS 2008 viscosity at that density.
FluidProperties water_properties(double temperature_c);

/// A glycerol-water mixture of glycerol mass fraction in [0, 1] at `temperature_c` in [0, 100] C:
/// viscosity from Cheng (2008, Ind. Eng. Chem. Res. 47, 3285, doi:10.1021/ie071349z), density from
/// Volk and Kaehler (2018, Exp. Fluids 59, 75, doi:10.1007/s00348-018-2527-y).
FluidProperties glycerol_water_properties(double glycerol_mass_fraction, double temperature_c);

/// Applies `fluid.preset` to checked case values: sets fluid.density and fluid.dynamic_viscosity
/// from the preset unless the case (file or --set) gave them explicitly. Idempotent, so a
/// case.resolved.toml (which names the preset and the values) reads back to the same values.
/// settle::InputError naming the key when fluid.temperature or fluid.glycerol_mass_fraction is
/// given without a preset that uses it, or missing for one that needs it.
void apply_fluid_preset(CaseValues& values);

/// Messages for the user about a preset: an explicit fluid.density or fluid.dynamic_viscosity that
/// differs from the preset's value, and a glycerol-water density extrapolated outside the
/// temperatures its model was fitted to. Empty without a preset.
std::vector<std::string> fluid_preset_warnings(const CaseValues& values);

}  // namespace settle::io
