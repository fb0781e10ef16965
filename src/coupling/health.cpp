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
  const std::vector<double> rho = fluid.density_field();
  const lbm::VectorField u = fluid.velocity_field();
  double min_rho = 1.0, max_rho = 1.0, max_u2 = 0.0;
  bool finite = true;
  for (std::size_t n = 0; n < rho.size(); ++n) {
    const double u2 = u.x[n] * u.x[n] + u.y[n] * u.y[n] + u.z[n] * u.z[n];
    // A NaN fails every comparison: test finiteness explicitly.
    finite = finite && std::isfinite(rho[n]) && std::isfinite(u2);
    min_rho = std::min(min_rho, rho[n]);
    max_rho = std::max(max_rho, rho[n]);
    max_u2 = std::max(max_u2, u2);
  }
  r.finite = r.finite && finite;
  r.min_density = min_rho;
  r.max_density = max_rho;
  r.max_lattice_speed = std::sqrt(max_u2);
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
    r.problem = fmt::format(
        "fluid density ranges over [{:.3f}, {:.3f}] (lattice units), beyond 1 +- {:.2f}: pressure waves too strong "
        "for the incompressible limit. Likely cause: too large a lattice velocity or an impulsive start; lower "
        "numerics.max_lattice_velocity",
        r.min_density, r.max_density, limits.max_density_deviation);
  }
  return r;
}

}  // namespace settle::coupling
