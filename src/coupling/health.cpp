#include "coupling/health.hpp"

#include <algorithm>
#include <array>
#include <cmath>

#include <fmt/core.h>

namespace settle::coupling {
namespace {

bool body_finite(const Simulation& sim) {
  const auto& s = sim.body().state();
  return s.position_si.allFinite() && s.velocity_si.allFinite() && s.angular_velocity_b_si.allFinite();
}

lbm::FieldExtrema measure_fluid(const Simulation& sim, HealthReport& r) {
  const lbm::FieldExtrema e = sim.fluid_extrema();
  r.finite = r.finite && e.finite;
  r.min_density = e.min_density;
  r.max_density = e.max_density;
  r.max_lattice_speed = e.max_speed;
  return e;
}

/// Where a cell lies, in the terms a user can act on.
struct Place {
  std::array<int, 3> cell{};
  Eigen::Vector3d offset_d;  ///< from the particle's centre, equivalent diameters, inertial axes
  bool inside_particle = false;
  int cells_to_face = 0;  ///< to the nearest face of the grid
};

Place place_of(const Simulation& sim, const std::array<int, 3>& cell) {
  const Eigen::Vector3d from_centre_si =
      sim.frame().to_si(Eigen::Vector3d(cell[0], cell[1], cell[2])) - sim.body().state().position_si;
  Place p{cell, from_centre_si / sim.plan().equivalent_diameter_si,
          sim.setup().shape->contains(sim.body().body_to_inertial().transpose() * from_centre_si), 0};
  const std::array<int, 3>& n = sim.derived().cells;
  p.cells_to_face = n[0];
  for (int a = 0; a < 3; ++a) p.cells_to_face = std::min({p.cells_to_face, cell[a], n[a] - 1 - cell[a]});
  return p;
}

std::string describe(const Simulation& sim, const Place& p) {
  const std::array<int, 3>& n = sim.derived().cells;
  return fmt::format(
      "at cell ({}, {}, {}) of {}x{}x{}, ({:.2f}, {:.2f}, {:.2f}) diameters from the particle's centre{}, "
      "{} cells from the nearest face of the grid",
      p.cell[0], p.cell[1], p.cell[2], n[0], n[1], n[2], p.offset_d.x(), p.offset_d.y(), p.offset_d.z(),
      p.inside_particle ? " (inside the particle)" : "", p.cells_to_face);
}

/// Why the density left its range: the pressure held inside a body with interior markers, the
/// viscous pressure of a thin gap at large tau, or the flow's own speed.
std::string density_cause(const Simulation& sim, const Place& place) {
  // The lattice pressure is c_s^2 (rho - 1). Its inertial part scales with u^2, its viscous part
  // with (tau - 0.5) u / L: in a thin gap (a particle nearing a wall, L the gap) the viscous part
  // dominates at large tau, and lowering dt (numerics.max_tau) shrinks it as dt^2.
  const double tau = sim.units().tau();
  if (sim.setup().interior_markers && place.inside_particle)
    return "the pressure in the fluid that numerics.interior_markers holds rigid inside the particle: steady, about "
           "20 x rho U^2 / 2 (docs/coupling.md, \"Pressure inside a body with interior markers\"), a density "
           "deviation of 0.06-0.10 at lattice velocity 0.05, falling roughly as its square; lower "
           "numerics.max_lattice_velocity (0.035 about halves it) or set numerics.interior_markers = false";
  if (tau > 1.0)
    return fmt::format(
        "the viscous pressure of a thin gap (a particle nearing a wall) at tau = {:.3g}, which grows "
        "with (tau - 0.5) x lattice velocity; lower numerics.max_tau (a smaller dt), e.g. to 1.0, or "
        "numerics.max_lattice_velocity",
        tau);
  return "too large a lattice velocity or an impulsive start; lower numerics.max_lattice_velocity";
}

}  // namespace

HealthReport check_health(const Simulation& sim, const HealthLimits& limits) {
  HealthReport r;
  r.finite = body_finite(sim);
  const lbm::FieldExtrema e = measure_fluid(sim, r);
  const double design_speed = sim.setup().max_lattice_velocity;
  if (!r.finite) {
    r.problem = fmt::format(
        "NaN or infinity in the {} (the fluid diverged). Likely cause: relaxation time too close to 0.5 for the "
        "resolution (tau = {:.4f}) or a particle much faster than expected; raise numerics.cells_per_diameter, "
        "lower numerics.max_lattice_velocity, or use numerics.collision = \"recursive_regularized\"",
        body_finite(sim) ? "fluid" : "particle state", sim.units().tau());
  } else if (r.max_lattice_speed > limits.max_lattice_speed) {
    r.problem = fmt::format(
        "largest fluid speed {:.3f} in lattice units (Mach {:.2f}) exceeds {:.2f}; dt was chosen for {:.3f}; {}. "
        "Likely cause: the particle falls faster than the terminal-velocity estimate ({:.4g} m/s); lower "
        "numerics.max_lattice_velocity",
        r.max_lattice_speed, r.max_lattice_speed * std::sqrt(3.0), limits.max_lattice_speed, design_speed,
        describe(sim, place_of(sim, e.max_speed_cell)), sim.plan().expected_speed_si);
  } else if (std::max(r.max_density - 1.0, 1.0 - r.min_density) > limits.max_density_deviation) {
    const bool high = r.max_density - 1.0 >= 1.0 - r.min_density;
    const Place place = place_of(sim, high ? e.max_density_cell : e.min_density_cell);
    r.problem = fmt::format(
        "fluid density ranges over [{:.3f}, {:.3f}] (lattice units), beyond 1 +- {:.2f}: pressure too strong for the "
        "incompressible limit; the {} {}. Likely cause: {}",
        r.min_density, r.max_density, limits.max_density_deviation, high ? "largest" : "smallest", describe(sim, place),
        density_cause(sim, place));
  }
  return r;
}

}  // namespace settle::coupling
