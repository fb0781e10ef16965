#include "coupling/health.hpp"

#include <algorithm>
#include <cmath>

#include <fmt/core.h>

namespace settle::coupling {
namespace {

bool body_finite(const Simulation& sim) {
  const auto& s = sim.body().state();
  return s.position_si.allFinite() && s.velocity_si.allFinite() && s.angular_velocity_b_si.allFinite();
}

void measure_fluid(const lbm::Solver& fluid, HealthReport& r) {
  const lbm::FieldExtrema e = fluid.extrema();
  r.finite = r.finite && e.finite;
  r.min_density = e.min_density;
  r.max_density = e.max_density;
  r.max_lattice_speed = e.max_speed;
}

}  // namespace

HealthReport check_health(const Simulation& sim, const HealthLimits& limits) {
  HealthReport r;
  r.finite = body_finite(sim);
  measure_fluid(sim.fluid(), r);
  const double design_speed = sim.setup().max_lattice_velocity;
  if (!r.finite) {
    r.problem = fmt::format(
        "NaN or infinity in the {} (the fluid diverged). Likely cause: relaxation time too close to 0.5 for the "
        "resolution (tau = {:.4f}) or a particle much faster than expected; raise numerics.cells_per_diameter, "
        "lower numerics.max_lattice_velocity, or use numerics.collision = \"recursive_regularized\"",
        body_finite(sim) ? "fluid" : "particle state", sim.derived().tau);
  } else if (r.max_lattice_speed > limits.max_lattice_speed) {
    r.problem = fmt::format(
        "largest fluid speed {:.3f} in lattice units (Mach {:.2f}) exceeds {:.2f}; dt was chosen for {:.3f}. Likely "
        "cause: the particle falls faster than the terminal-velocity estimate ({:.4g} m/s); lower "
        "numerics.max_lattice_velocity",
        r.max_lattice_speed, r.max_lattice_speed * std::sqrt(3.0), limits.max_lattice_speed, design_speed,
        sim.derived().expected_speed_si);
  } else if (std::max(r.max_density - 1.0, 1.0 - r.min_density) > limits.max_density_deviation) {
    // The lattice pressure is c_s^2 (rho - 1). Its inertial part scales with u^2, its viscous part
    // with (tau - 0.5) u / L: in a thin gap (a particle nearing a wall, L the gap) the viscous part
    // dominates at large tau, and lowering dt (numerics.max_tau) shrinks it as dt^2.
    const double tau = sim.derived().tau;
    const std::string cause =
        tau > 1.0 ? fmt::format("the viscous pressure of a thin gap (a particle nearing a wall) at tau = {:.3g}, which "
                                "grows with (tau - 0.5) x lattice velocity; lower numerics.max_tau (a smaller dt), e.g. "
                                "to 1.0, or numerics.max_lattice_velocity",
                                tau)
                  : std::string("too large a lattice velocity or an impulsive start; lower "
                                "numerics.max_lattice_velocity");
    r.problem = fmt::format(
        "fluid density ranges over [{:.3f}, {:.3f}] (lattice units), beyond 1 +- {:.2f}: pressure too strong for the "
        "incompressible limit. Likely cause: {}",
        r.min_density, r.max_density, limits.max_density_deviation, cause);
  }
  return r;
}

}  // namespace settle::coupling
