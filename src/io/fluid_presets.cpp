#include "io/fluid_presets.hpp"

#include <algorithm>
#include <array>
#include <cmath>
#include <numbers>
#include <stdexcept>

#include <fmt/format.h>

#include "common/error.hpp"

namespace settle::io {
namespace {

constexpr double kCelsiusToKelvin = 273.15;

void require_in_range(double value, double lo, double hi, const char* what) {
  if (!(value >= lo && value <= hi))
    throw std::invalid_argument(fmt::format("fluid presets: {} = {} is outside [{}, {}]", what, value, lo, hi));
}

// ------------------------------------------------------------------ water

// IAPWS R12-08 (Huber et al. 2009), Table 1: coefficients H_i of the dilute-gas part mu0.
constexpr std::array<double, 4> kIapwsH0{1.67752, 2.20462, 0.6366564, -0.241605};

// IAPWS R12-08, Table 2: coefficients H_ij of the residual part mu1; row i is the power of
// (1/Tbar - 1), column j the power of (rhobar - 1).
constexpr std::array<std::array<double, 7>, 6> kIapwsH1{{
    {5.20094e-1, 2.22531e-1, -2.81378e-1, 1.61913e-1, -3.25372e-2, 0.0, 0.0},
    {8.50895e-2, 9.99115e-1, -9.06851e-1, 2.57399e-1, 0.0, 0.0, 0.0},
    {-1.08374, 1.88797, -7.72479e-1, 0.0, 0.0, 0.0, 0.0},
    {-2.89555e-1, 1.26613, -4.89837e-1, 0.0, 6.98452e-2, 0.0, -4.35673e-3},
    {0.0, 0.0, -2.57040e-1, 0.0, 0.0, 8.72102e-3, 0.0},
    {0.0, 1.20573e-1, 0.0, 0.0, 0.0, 0.0, -5.93264e-4},
}};

// ------------------------------------------------------------------ glycerol-water (Cheng 2008)

double cheng_water_viscosity_si(double t_c) {
  return 1.790e-3 * std::exp((-1230.0 - t_c) * t_c / (36100.0 + 360.0 * t_c));
}

double cheng_glycerol_viscosity_si(double t_c) {
  return 12100.0e-3 * std::exp((-1233.0 + t_c) * t_c / (9900.0 + 70.0 * t_c));
}

// Cheng's weight of the water viscosity in mu = mu_w^alpha mu_g^(1 - alpha): alpha = 1 for pure
// water, 0 for pure glycerol. a > 0.5 and b > 0 for 0-100 C, so the denominator never vanishes.
double cheng_exponent(double mass_fraction, double t_c) {
  const double a = 0.705 - 0.0017 * t_c;
  const double b = (4.9 + 0.036 * t_c) * std::pow(a, 2.5);
  const double c = mass_fraction;
  return 1.0 - c + a * b * c * (1.0 - c) / (a * c + b * (1.0 - c));
}

// ------------------------------------------------------------------ glycerol-water (Volk and Kaehler 2018)

// The model's own water and glycerol densities, not Kell's: its contraction term was fitted with them.
double volk_water_density_si(double t_c) { return 1000.0 * (1.0 - std::pow(std::abs((t_c - 3.98) / 615.0), 1.71)); }
double volk_glycerol_density_si(double t_c) { return 1273.0 - 0.612 * t_c; }

// Volume contraction kappa >= 1 of the mixture relative to ideal mixing (at most about 1.4 %).
double volk_contraction(double mass_fraction, double t_c) {
  const double amplitude = 1.78e-6 * t_c * t_c - 1.82e-4 * t_c + 1.41e-2;
  // max(0, .): sin(pi) rounds to +1e-16 at c = 1, never below zero, but pow of a negative would be NaN.
  const double shape = std::max(0.0, std::sin(std::pow(mass_fraction, 1.31) * std::numbers::pi));
  return 1.0 + amplitude * std::pow(shape, 0.81);
}

// ------------------------------------------------------------------ the case keys

constexpr double kVolkMinTemperatureC = 15.0;  // the tabulated densities the model was fitted to
constexpr double kVolkMaxTemperatureC = 30.0;

std::string shown(double value) { return to_toml(Value(value)); }

void refuse_keys_the_preset_does_not_use(const CaseValues& v, const std::string& preset) {
  if (preset == "none" && v.has("fluid.temperature"))
    throw InputError(fmt::format(
        "fluid.temperature = {}: only used with fluid.preset = \"water\" or \"glycerol-water\" (it sets the "
        "preset's temperature in degrees C); add a preset or remove fluid.temperature",
        shown(v.real("fluid.temperature"))));
  if (preset != "glycerol-water" && v.has("fluid.glycerol_mass_fraction"))
    throw InputError(fmt::format(
        "fluid.glycerol_mass_fraction = {}: only used with fluid.preset = \"glycerol-water\" (fluid.preset is "
        "\"{}\"); remove it or set fluid.preset = \"glycerol-water\"",
        shown(v.real("fluid.glycerol_mass_fraction")), preset));
}

void require_keys_the_preset_needs(const CaseValues& v, const std::string& preset) {
  if (!v.has("fluid.temperature"))
    throw InputError(fmt::format(
        "fluid.temperature: required when fluid.preset = \"{}\" (degrees C, in [0, 100], e.g. 20.0)", preset));
  if (preset == "glycerol-water" && !v.has("fluid.glycerol_mass_fraction"))
    throw InputError(
        "fluid.glycerol_mass_fraction: required when fluid.preset = \"glycerol-water\" (mass of glycerol per mass of "
        "mixture, in [0, 1], e.g. 0.5)");
}

// The preset's properties; the keys have been checked by apply_fluid_preset.
FluidProperties preset_properties(const CaseValues& v, const std::string& preset) {
  const double t_c = v.real("fluid.temperature");
  if (preset == "water") return water_properties(t_c);
  return glycerol_water_properties(v.real("fluid.glycerol_mass_fraction"), t_c);
}

std::string preset_description(const CaseValues& v, const std::string& preset) {
  std::string text = fmt::format("fluid.preset = \"{}\" at {} C", preset, shown(v.real("fluid.temperature")));
  if (preset == "glycerol-water")
    text += fmt::format(", glycerol mass fraction {}", shown(v.real("fluid.glycerol_mass_fraction")));
  return text;
}

}  // namespace

double water_density_si(double temperature_c) {
  require_in_range(temperature_c, 0.0, 100.0, "temperature (C)");
  const double t = temperature_c;
  // Horner form of 999.83952 + 16.952577 t - 7.9905127e-3 t^2 - 46.241757e-6 t^3
  //                + 105.84601e-9 t^4 - 281.03006e-12 t^5, over 1 + 16.887236e-3 t.
  const double numerator =
      999.83952 + t * (16.952577 + t * (-7.9905127e-3 + t * (-46.241757e-6 + t * (105.84601e-9 + t * -281.03006e-12))));
  return numerator / (1.0 + 16.887236e-3 * t);
}

double iapws2008_viscosity_si(double temperature_k, double density_si) {
  // Reference constants of IAPWS R12-08, Eqs. (1)-(4).
  const double t_bar = temperature_k / 647.096;
  const double rho_bar = density_si / 322.0;
  double mu0_denominator = 0.0;
  for (std::size_t i = 0; i < kIapwsH0.size(); ++i)
    mu0_denominator += kIapwsH0[i] / std::pow(t_bar, static_cast<double>(i));
  const double mu0 = 100.0 * std::sqrt(t_bar) / mu0_denominator;
  double sum = 0.0;
  double temperature_power = 1.0;  // (1/Tbar - 1)^i
  for (const auto& row : kIapwsH1) {
    double density_power = 1.0;  // (rhobar - 1)^j
    for (double h : row) {
      sum += h * temperature_power * density_power;
      density_power *= rho_bar - 1.0;
    }
    temperature_power *= 1.0 / t_bar - 1.0;
  }
  const double mu1 = std::exp(rho_bar * sum);
  return 1.0e-6 * mu0 * mu1;  // mu* = 1 micro-Pa s
}

FluidProperties water_properties(double temperature_c) {
  const double density = water_density_si(temperature_c);
  // 101.325 kPa rather than the release's 0.1 MPa: the density differs by 6e-7 relative, the
  // viscosity by less.
  return {density, iapws2008_viscosity_si(temperature_c + kCelsiusToKelvin, density)};
}

FluidProperties glycerol_water_properties(double glycerol_mass_fraction, double temperature_c) {
  require_in_range(glycerol_mass_fraction, 0.0, 1.0, "glycerol mass fraction");
  require_in_range(temperature_c, 0.0, 100.0, "temperature (C)");
  const double c = glycerol_mass_fraction, t = temperature_c;
  const double alpha = cheng_exponent(c, t);
  const double viscosity =
      std::pow(cheng_water_viscosity_si(t), alpha) * std::pow(cheng_glycerol_viscosity_si(t), 1.0 - alpha);
  const double rho_w = volk_water_density_si(t), rho_g = volk_glycerol_density_si(t);
  // Ideal mixing by volume (1/rho = c/rho_g + (1 - c)/rho_w), written without 1/c so that c = 0
  // is pure water; times the contraction.
  const double ideal = rho_g * rho_w / (c * rho_w + (1.0 - c) * rho_g);
  return {volk_contraction(c, t) * ideal, viscosity};
}

void apply_fluid_preset(CaseValues& values) {
  const std::string preset = values.string("fluid.preset");
  refuse_keys_the_preset_does_not_use(values, preset);
  if (preset == "none") return;
  require_keys_the_preset_needs(values, preset);
  const FluidProperties p = preset_properties(values, preset);
  // Marked as given: they are the values the run uses, not schema defaults, and
  // case.resolved.toml must not label them "(default)". An explicit value wins.
  if (!values.given("fluid.density")) values.set("fluid.density", Value(p.density_si), "fluid.preset");
  if (!values.given("fluid.dynamic_viscosity"))
    values.set("fluid.dynamic_viscosity", Value(p.dynamic_viscosity_si), "fluid.preset");
}

std::vector<std::string> fluid_preset_warnings(const CaseValues& values) {
  std::vector<std::string> warnings;
  const std::string preset = values.string("fluid.preset");
  if (preset == "none") return warnings;
  const FluidProperties p = preset_properties(values, preset);
  const auto compare = [&](const char* key, double preset_value, const char* unit) {
    // Exact comparison: a resolved case carries the preset's value to the last bit and must not warn.
    if (values.real(key) != preset_value)
      warnings.push_back(fmt::format("{} = {} {} replaces the value of {} ({:.6g} {})", key, shown(values.real(key)),
                                     unit, preset_description(values, preset), preset_value, unit));
  };
  compare("fluid.density", p.density_si, "kg/m^3");
  compare("fluid.dynamic_viscosity", p.dynamic_viscosity_si, "Pa s");
  const double t_c = values.real("fluid.temperature");
  if (preset == "glycerol-water" && values.real("fluid.density") == p.density_si &&
      (t_c < kVolkMinTemperatureC || t_c > kVolkMaxTemperatureC))
    warnings.push_back(fmt::format(
        "fluid.temperature = {}: the glycerol-water density (Volk and Kaehler 2018) is fitted to tabulated data at "
        "{}-{} C and extrapolated here; give fluid.density explicitly if it matters",
        shown(t_c), kVolkMinTemperatureC, kVolkMaxTemperatureC));
  return warnings;
}

}  // namespace settle::io
