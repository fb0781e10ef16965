#include "coupling/case_plan.hpp"

#include <algorithm>
#include <cmath>
#include <stdexcept>

#include <fmt/core.h>

#include "common/error.hpp"
#include "coupling/time_control.hpp"

namespace settle::coupling {
namespace {

void check_contact_setup(const SimulationSetup& s) {
  if (!s.wall_contact) return;
  if (!(s.contact_restitution > 0.0 && s.contact_restitution <= 1.0))
    throw InputError(fmt::format("contact.restitution: must be in (0, 1], got {}", s.contact_restitution));
  if (!(s.contact_collision_steps >= 1.0 && s.contact_collision_steps <= 1.0e4))
    throw InputError(fmt::format("contact.collision_steps: must be in [1, 1e4] fluid time steps, got {}",
                                 s.contact_collision_steps));
  if (!(s.contact_wet_stokes_scale >= 0.0 && s.contact_wet_stokes_scale <= 1.0e3))
    throw InputError(fmt::format("contact.wet_stokes_scale: must be in [0, 1000] (0: dry contacts), got {}",
                                 s.contact_wet_stokes_scale));
  const double minimum = ibm::support_half_width(s.kernel) - 0.5;
  const double distance = contact_distance_cells(s);
  if (!(distance >= minimum && distance <= 1.0e3))
    throw InputError(fmt::format("contact.distance_cells: must be in [{}, 1000] cells for the {} kernel (a body resting "
                                 "closer to a wall would put its forcing stencil outside the grid), got {}",
                                 minimum, ibm::to_string(s.kernel), distance));
}

void check_setup(const SimulationSetup& s) {
  if (!s.shape) throw std::invalid_argument("plan_case: the set-up has no shape");
  if (!(s.particle_density_si > 0.0)) throw InputError("particle.density: must be > 0");
  if (!(s.end_time_si > 0.0)) throw InputError("run.end_time: must be > 0");
  if (s.forcing_iterations < 1)
    throw InputError(fmt::format("numerics.forcing_iterations: must be >= 1, got {}", s.forcing_iterations));
  if (s.motion == body::MotionKind::free && s.body_force_si.norm() > 0.0)
    throw InputError("fluid.body_force: only for particle.motion = \"fixed\" or \"towed\" (a free particle would be "
                     "carried by the driven flow); set it to [0, 0, 0]");
  check_contact_setup(s);
}

UnitConverter converter_for(const SimulationSetup& s, double expected_speed) {
  UnitInputs in;
  in.equivalent_diameter_si = s.shape->equivalent_diameter();
  in.cells_per_diameter = s.cells_per_diameter;
  in.fluid_density_si = s.fluid_density_si;
  in.dynamic_viscosity_si = s.dynamic_viscosity_si;
  in.expected_speed_si = expected_speed;
  in.max_lattice_velocity = s.max_lattice_velocity;
  in.max_tau = s.max_tau;
  in.tau = s.tau;
  return make_unit_converter(in);
}

}  // namespace

double expected_speed_si(const SimulationSetup& s) {
  const double d = s.shape->equivalent_diameter();
  const double rotation = s.initial.angular_velocity_b_si.norm() * s.shape->bounding_radius();
  // A stream through an inlet adds its speed to whatever the body's motion drives.
  const double stream = s.inflow ? s.inflow_velocity_si.norm() : 0.0;
  switch (s.motion) {
    case body::MotionKind::towed:
      return s.initial.velocity_si.norm() + rotation + stream;
    case body::MotionKind::fixed:
      return estimated_driven_speed_si(d, s.body_force_si.norm(), s.domain_size_si.prod(), s.fluid_density_si,
                                       s.dynamic_viscosity_si) +
             stream;
    case body::MotionKind::free:
      break;
  }
  // Under gravity and drag the velocity relaxes from its initial value towards the terminal one;
  // with a drag linear in the velocity it is a convex combination of the two, so its magnitude
  // stays below the larger (a body released at its terminal speed does not halve dt).
  const double terminal = estimated_terminal_speed_si(d, s.particle_density_si, s.fluid_density_si,
                                                      s.dynamic_viscosity_si, s.gravity_si.norm());
  return std::max(terminal, s.initial.velocity_si.norm()) + rotation + stream;
}

CasePlan plan_case(const SimulationSetup& s) {
  check_setup(s);
  const double expected = expected_speed_si(s);
  CasePlan plan{converter_for(s, expected)};
  const UnitConverter& units = plan.units;
  plan.expected_speed_si = expected;
  plan.equivalent_diameter_si = s.shape->equivalent_diameter();
  plan.mach = mach_number(units.velocity(expected));
  plan.reynolds = expected * plan.equivalent_diameter_si / units.kinematic_viscosity_si();
  plan.galileo = galileo_number(plan.equivalent_diameter_si, s.particle_density_si, s.fluid_density_si,
                                units.kinematic_viscosity_si(), s.gravity_si.norm());
  for (int a = 0; a < 3; ++a) plan.cells[static_cast<std::size_t>(a)] = std::round(s.domain_size_si[a] / units.dx_si());
  plan.steps = steps_to_reach(s.end_time_si, units.dt_si());
  // The first step that starts at or after the release time (a relative tolerance keeps a time
  // given as a whole number of steps from rounding up by one).
  if (s.motion == body::MotionKind::free && s.release_time_si > 0.0)
    plan.release_step = static_cast<std::int64_t>(std::ceil(s.release_time_si / units.dt_si() * (1.0 - 1e-12)));
  return plan;
}

}  // namespace settle::coupling
