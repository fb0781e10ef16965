#include "coupling/health.hpp"

#include <algorithm>
#include <array>
#include <cmath>

#include <fmt/core.h>

#include "lbm/config.hpp"

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

/// The flow's scale now: the body's speed against the one dt was chosen for, and the cell
/// Reynolds number of the faster of the two, the figure that decides whether the wake is resolved.
struct FlowScale {
  double body_speed_si = 0.0;
  double expected_speed_si = 0.0;
  double cell_reynolds = 0.0;
};

// A body this much faster than the speed dt was chosen for has raised the lattice velocity by as
// much; below it the speed is not what broke the run.
constexpr double kFasterThanPlanned = 1.2;
// Beyond this the body's speed is a product of the divergence, not its cause: the terminal-speed
// estimate errs by tens of percent for irregular shapes, not by a factor of three.
constexpr double kPlausiblyFaster = 3.0;

FlowScale flow_scale(const Simulation& sim) {
  const UnitConverter& units = sim.plan().units;
  FlowScale f{sim.body().state().velocity_si.norm(), sim.plan().expected_speed_si, 0.0};
  const bool plausible = f.body_speed_si <= kPlausiblyFaster * f.expected_speed_si;
  const double speed = plausible ? std::max(f.body_speed_si, f.expected_speed_si) : f.expected_speed_si;
  f.cell_reynolds = speed * units.dx_si() / units.kinematic_viscosity_si();
  return f;
}

bool outran_plan(const FlowScale& f) {
  return f.body_speed_si > kFasterThanPlanned * f.expected_speed_si &&
         f.body_speed_si <= kPlausiblyFaster * f.expected_speed_si;
}

/// The likely cause of a fluid that left its bounds, from the flow's scale and the numerics, with
/// the change that addresses it. Each branch names a change that moves the figure it blames:
/// lowering the lattice velocity moves tau towards 1/2 but leaves the cell Reynolds number as it
/// is, so it is advised only where the body outran its plan.
std::string flow_cause(const Simulation& sim) {
  const FlowScale f = flow_scale(sim);
  const double tau = sim.units().tau();
  const double design = sim.setup().max_lattice_velocity;
  if (outran_plan(f))
    return fmt::format(
        "the particle moves at {:.4g} m/s, faster than the {:.4g} m/s dt was chosen for, so the lattice velocity "
        "reached {:.3f}; lower numerics.max_lattice_velocity to {:.3g}",
        f.body_speed_si, f.expected_speed_si, design * f.body_speed_si / f.expected_speed_si,
        design * f.expected_speed_si / f.body_speed_si);
  const double cells_needed = std::ceil(sim.setup().cells_per_diameter * f.cell_reynolds / lbm::kTrtStableCellReynolds);
  const std::string scale = fmt::format(
      "a wake under-resolved at the cell Reynolds number U dx / nu = {:.1f} (tau {:.4f})", f.cell_reynolds, tau);
  const lbm::SubgridModel subgrid = sim.plan().subgrid_model;
  if (sim.setup().collision == lbm::CollisionKind::trt && subgrid == lbm::SubgridModel::none &&
      f.cell_reynolds > lbm::kTrtStableCellReynolds)
    return fmt::format(
        "{}, above {:g}, where TRT without a subgrid model diverged on settling spheres (docs/lbm.md); set "
        "numerics.subgrid_model = \"auto\" (Smagorinsky's model there), or raise numerics.cells_per_diameter to "
        "{:.0f}; "
        "a lower numerics.max_lattice_velocity does not help (it leaves the cell Reynolds number unchanged)",
        scale, lbm::kTrtStableCellReynolds, cells_needed);
  if (f.cell_reynolds > lbm::kTrtStableCellReynolds)
    return fmt::format("{}; raise numerics.cells_per_diameter (to {:.0f} for a cell Reynolds number of {:g})", scale,
                       cells_needed, lbm::kTrtStableCellReynolds);
  return fmt::format(
      "an impulsive start or a local jet at lattice velocity {:.3f} (planned for {:.4g} m/s, cell Reynolds number "
      "{:.1f}); lower numerics.max_lattice_velocity, e.g. to {:.3g}, or raise numerics.cells_per_diameter",
      design, f.expected_speed_si, f.cell_reynolds, 0.6 * design);
}

/// Why the density left its range: the pressure held inside a body with interior markers, the
/// viscous pressure of a thin gap at large tau, or the flow's own scale.
std::string density_cause(const Simulation& sim, const Place& place) {
  // The lattice pressure is c_s^2 (rho - 1). Its inertial part scales with u^2, its viscous part
  // with (tau - 0.5) u / L: in a thin gap (a particle nearing a wall, L the gap) the viscous part
  // dominates at large tau, and lowering dt (numerics.max_tau) shrinks it as dt^2.
  const double tau = sim.units().tau();
  // numerics.interior_markers is read by the immersed boundary alone (the momentum exchange's inside is solid).
  if (sim.coupling().fluid_inside() && sim.setup().interior_markers && place.inside_particle)
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
  return flow_cause(sim);
}

}  // namespace

HealthReport check_health(const Simulation& sim, const HealthLimits& limits) {
  HealthReport r;
  r.finite = body_finite(sim);
  const lbm::FieldExtrema e = measure_fluid(sim, r);
  const double design_speed = sim.setup().max_lattice_velocity;
  if (!r.finite) {
    r.problem = fmt::format("NaN or infinity in the {} (the fluid diverged). Likely cause: {}",
                            body_finite(sim) ? "fluid" : "particle state", flow_cause(sim));
  } else if (r.max_lattice_speed > limits.max_lattice_speed) {
    r.problem = fmt::format(
        "largest fluid speed {:.3f} in lattice units (Mach {:.2f}) exceeds {:.2f}; dt was chosen for {:.3f}; {}. "
        "Likely cause: {}",
        r.max_lattice_speed, r.max_lattice_speed * std::sqrt(3.0), limits.max_lattice_speed, design_speed,
        describe(sim, place_of(sim, e.max_speed_cell)), flow_cause(sim));
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
