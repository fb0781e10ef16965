#include "io/plausibility.hpp"

#include <array>

#include <fmt/core.h>

#include "body/shape.hpp"

namespace settle::io {
namespace {

// The particle's length keys the case gives, each with its value over 1000 (mm read as m).
std::string length_keys_in_millimetres(const CaseValues& v) {
  std::string text;
  const auto add = [&text](const std::string& item) { text += (text.empty() ? "" : ", ") + item; };
  for (const char* key : {"particle.diameter", "particle.length"})
    if (v.has(key)) add(fmt::format("{} = {:g}", key, v.real(key) * 1e-3));
  for (const char* key : {"particle.semi_axes", "particle.size"})
    if (v.has(key)) {
      const std::vector<double>& r = v.reals(key);
      add(fmt::format("{} = [{:g}, {:g}, {:g}]", key, r[0] * 1e-3, r[1] * 1e-3, r[2] * 1e-3));
    }
  if (v.has("particle.file"))
    add(fmt::format("particle.scale = {:g}", (v.has("particle.scale") ? v.real("particle.scale") : 1.0) * 1e-3));
  return text;
}

}  // namespace

std::vector<std::string> plausibility_warnings(const CaseValues& v, const coupling::SimulationSetup& s) {
  std::vector<std::string> out;
  const double d_si = s.shape->equivalent_diameter();
  if (d_si > kLargestPlausibleDiameterSi) {
    const std::string meant = length_keys_in_millimetres(v);
    out.push_back(
        fmt::format("particle: a {:.4g} m particle (volume-equivalent diameter)? Lengths are in metres{}", d_si,
                    meant.empty() ? std::string() : fmt::format("; if you meant millimetres, write {}", meant)));
  }
  if (s.particle_density_si < kLightestPlausibleParticleDensitySi && s.fluid_density_si > kLiquidDensitySi)
    out.push_back(fmt::format(
        "particle.density: {:g} kg/m^3 is lighter than the fluid ({:g} kg/m^3): the particle will rise. Densities "
        "are in kg/m^3; if you meant {:g} g/cm^3, write particle.density = {:g}",
        s.particle_density_si, s.fluid_density_si, s.particle_density_si, s.particle_density_si * 1e3));
  if (s.fluid_density_si < kLightestPlausibleLiquidDensitySi && s.dynamic_viscosity_si > kLiquidViscositySi)
    out.push_back(fmt::format(
        "fluid.density: {:g} kg/m^3 is a gas's density, but fluid.dynamic_viscosity = {:g} Pa s is a liquid's. "
        "Densities are in kg/m^3; if you meant {:g} g/cm^3, write fluid.density = {:g}",
        s.fluid_density_si, s.dynamic_viscosity_si, s.fluid_density_si, s.fluid_density_si * 1e3));
  return out;
}

std::string physical_properties_text(const coupling::SimulationSetup& s) {
  const double d_si = s.shape->equivalent_diameter();
  return fmt::format(
      "fluid: rho_f = {:g} kg/m^3, mu = {:g} Pa s (nu = {:.4g} m^2/s), |g| = {:g} m/s^2; particle: {}, d_eq = {:.4g} "
      "m, "
      "rho_p = {:g} kg/m^3 (rho_p/rho_f = {:.4g}), {}",
      s.fluid_density_si, s.dynamic_viscosity_si, s.dynamic_viscosity_si / s.fluid_density_si, s.gravity_si.norm(),
      s.shape->kind(), d_si, s.particle_density_si, s.particle_density_si / s.fluid_density_si,
      s.motion == body::MotionKind::free    ? "free"
      : s.motion == body::MotionKind::towed ? "towed"
                                            : "fixed");
}

}  // namespace settle::io
