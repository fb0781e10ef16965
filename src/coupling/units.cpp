#include "coupling/units.hpp"

#include <algorithm>
#include <cmath>
#include <numbers>

#include <fmt/core.h>

#include "common/bisection.hpp"
#include "common/error.hpp"
#include "common/require.hpp"
#include "lbm/config.hpp"

namespace settle::coupling {
namespace {

constexpr double kSoundSpeed = 0.57735026918962576;  // 1/sqrt(3), lattice units

// Smallest U in (0, hi] with residual(U) >= 0 for a residual increasing in U (bisection to
// relative 1e-10; the drag force grows monotonically with speed). The bracket's upper end doubles
// from 1 m/s until the residual turns non-negative, up to 1e6 m/s.
template <class Residual>
double solve_increasing(const Residual& residual) {
  double high = 1.0;
  while (residual(high) < 0.0 && high < 1e6) high *= 2.0;
  const auto side = [&](double u) { return residual(u) < 0.0 ? BisectionSide::below : BisectionSide::above; };
  const auto converged = [](double low, double up) { return !(up - low > 1e-10 * up); };
  return bisect({0.0, high}, side, converged, 200).middle();
}

// Drag (N) on a sphere of diameter d at speed U with Schiller-Naumann.
double sphere_drag_si(double u_si, double d_si, double rho_si, double mu_si) {
  if (u_si <= 0.0) return 0.0;
  const double re = rho_si * u_si * d_si / mu_si;
  return schiller_naumann_drag_coefficient(re) * 0.5 * rho_si * u_si * u_si * std::numbers::pi * d_si * d_si / 4.0;
}

}  // namespace

UnitConverter::UnitConverter(double dx_si, double dt_si, double fluid_density_si, double kinematic_viscosity_si)
    : dx_si_(dx_si), dt_si_(dt_si), rho_si_(fluid_density_si), nu_si_(kinematic_viscosity_si) {}

double UnitConverter::viscosity() const { return nu_si_ * dt_si_ / (dx_si_ * dx_si_); }
double UnitConverter::tau() const { return lbm::tau_from_viscosity(viscosity()); }

double mach_number(double lattice_velocity) { return lattice_velocity / kSoundSpeed; }

UnitConverter make_unit_converter(const UnitInputs& in) {
  require_positive(in.equivalent_diameter_si, "particle size (equivalent diameter)");
  require_positive(in.cells_per_diameter, "numerics.cells_per_diameter");
  require_positive(in.fluid_density_si, "fluid.density");
  require_positive(in.dynamic_viscosity_si, "fluid.dynamic_viscosity");
  require_positive(in.max_lattice_velocity, "numerics.max_lattice_velocity");
  require_positive(in.max_tau, "numerics.max_tau");
  if (!(std::isfinite(in.expected_speed_si) && in.expected_speed_si >= 0.0))
    throw InputError(fmt::format("expected speed: must be finite and >= 0, got {}", in.expected_speed_si));

  const double dx_si = in.equivalent_diameter_si / in.cells_per_diameter;
  const double nu_si = in.dynamic_viscosity_si / in.fluid_density_si;
  // The lattice viscosity of tau is nu_si dt / dx^2.
  const auto dt_for_tau = [&](double tau) { return lbm::viscosity_from_tau(tau) * dx_si * dx_si / nu_si; };

  double dt_si = 0.0;
  if (in.tau) {
    const double tau = *in.tau;
    if (!(tau > in.min_tau && tau <= in.max_tau))
      throw InputError(fmt::format("numerics.tau: must be in ({}, {}], got {}", in.min_tau, in.max_tau, tau));
    dt_si = dt_for_tau(tau);
    const double u = in.expected_speed_si * dt_si / dx_si;
    if (u > in.max_lattice_velocity)
      throw InputError(fmt::format(
          "numerics.tau: with tau = {} the expected speed {:.4g} m/s is {:.4g} in lattice units (Mach {:.3g}), above "
          "numerics.max_lattice_velocity = {}; lower numerics.tau or numerics.cells_per_diameter",
          tau, in.expected_speed_si, u, mach_number(u), in.max_lattice_velocity));
  } else {
    dt_si = dt_for_tau(in.max_tau);
    if (in.expected_speed_si > 0.0) dt_si = std::min(dt_si, in.max_lattice_velocity * dx_si / in.expected_speed_si);
  }

  const UnitConverter units(dx_si, dt_si, in.fluid_density_si, nu_si);
  if (units.tau() < in.min_tau) {
    const double reynolds = in.expected_speed_si * in.equivalent_diameter_si / nu_si;
    // tau - 1/2 below 1e-16 rounds away (tau == 0.5): no grid resolves such a flow, and the cells
    // the message below would ask for come out infinite. The fluid's numbers are the likely fault.
    if (!(units.tau() > 0.5))
      throw InputError(fmt::format(
          "fluid.dynamic_viscosity, fluid.density: the expected Reynolds number {:.4g} (kinematic viscosity {:.4g} "
          "m^2/s) is beyond any grid: tau rounds to 0.5 in double precision; check fluid.dynamic_viscosity and "
          "fluid.density",
          reynolds, nu_si));
    throw InputError(fmt::format(
        "numerics.cells_per_diameter: {} cells per diameter under-resolve the flow (expected Re = {:.4g}): the "
        "Mach bound numerics.max_lattice_velocity = {} forces tau = {:.6f} below the safe minimum {}; raise "
        "numerics.cells_per_diameter to at least {:.0f}",
        in.cells_per_diameter, reynolds, in.max_lattice_velocity, units.tau(), in.min_tau,
        std::ceil(in.cells_per_diameter * (in.min_tau - 0.5) / (units.tau() - 0.5))));
  }
  return units;
}

double schiller_naumann_drag_coefficient(double reynolds) {
  return 24.0 / reynolds * (1.0 + 0.15 * std::pow(reynolds, 0.687));
}

double estimated_terminal_speed_si(double d_si, double particle_density_si, double fluid_density_si,
                                   double dynamic_viscosity_si, double gravity_si) {
  const double volume = std::numbers::pi * d_si * d_si * d_si / 6.0;
  const double net_weight = std::abs(particle_density_si - fluid_density_si) * gravity_si * volume;
  if (net_weight <= 0.0) return 0.0;
  return solve_increasing(
      [&](double u) { return sphere_drag_si(u, d_si, fluid_density_si, dynamic_viscosity_si) - net_weight; });
}

double estimated_driven_speed_si(double d_si, double force_density_si, double box_volume_si, double fluid_density_si,
                                 double dynamic_viscosity_si) {
  const double driving = std::abs(force_density_si) * box_volume_si;
  if (driving <= 0.0) return 0.0;
  return solve_increasing(
      [&](double u) { return sphere_drag_si(u, d_si, fluid_density_si, dynamic_viscosity_si) - driving; });
}

double galileo_number(double d_si, double particle_density_si, double fluid_density_si, double kinematic_viscosity_si,
                      double gravity_si) {
  return std::sqrt(std::abs(particle_density_si / fluid_density_si - 1.0) * gravity_si * d_si * d_si * d_si) /
         kinematic_viscosity_si;
}

}  // namespace settle::coupling
