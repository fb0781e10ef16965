#include "coupling/case_plan.hpp"

#include <algorithm>
#include <cmath>
#include <stdexcept>
#include <utility>

#include <fmt/core.h>

#include "common/error.hpp"
#include "coupling/immersed_body.hpp"
#include "coupling/time_control.hpp"

namespace settle::coupling {
namespace {

// The members of case keys io::simulation_setup assigns (coupling/setup.hpp): a set-up built
// without it must not run on whatever a member held. A programming error, not the user's.
void check_assigned(const SimulationSetup& s) {
  const std::pair<const char*, bool> numbers[] = {
      {"particle_density_si", std::isnan(s.particle_density_si)},
      {"fluid_density_si", std::isnan(s.fluid_density_si)},
      {"dynamic_viscosity_si", std::isnan(s.dynamic_viscosity_si)},
      {"gravity_si", s.gravity_si.hasNaN()},
      {"body_force_si", s.body_force_si.hasNaN()},
      {"domain_size_si", s.domain_size_si.hasNaN()},
      {"release_time_si", std::isnan(s.release_time_si)},
      {"hold_ramp_time_si", std::isnan(s.hold_ramp_time_si)},
      {"cells_per_diameter", std::isnan(s.cells_per_diameter)},
      {"trt_magic", std::isnan(s.trt_magic)},
      {"smagorinsky_constant", std::isnan(s.smagorinsky_constant)},
      {"marker_retraction_cells", std::isnan(s.marker_retraction_cells)},
      {"max_lattice_velocity", std::isnan(s.max_lattice_velocity)},
      {"max_tau", std::isnan(s.max_tau)},
      {"contact_restitution", std::isnan(s.contact_restitution)},
      {"contact_wet_stokes_scale", std::isnan(s.contact_wet_stokes_scale)},
      {"contact_collision_steps", std::isnan(s.contact_collision_steps)},
      {"end_time_si", std::isnan(s.end_time_si)},
      {"output_interval_si", std::isnan(s.output_interval_si)},
      {"forcing_iterations", s.forcing_iterations == kUnassignedCount},
      {"lattice_steps_per_body_step", s.lattice_steps_per_body_step == kUnassignedCount},
  };
  for (const auto& [member, unassigned] : numbers)
    if (unassigned)
      throw std::invalid_argument(
          fmt::format("plan_case: SimulationSetup::{} is not assigned; build the set-up with io::simulation_setup (its "
                      "default: the case schema's, tests/support/default_setup.hpp)",
                      member));
}

// The ranges of single keys are the case schema's, checked when the case was read; these are the
// rules between keys, which the schema cannot state.
void check_contact_setup(const SimulationSetup& s) {
  if (!s.wall_contact) return;
  // Closer than reach - 1/2 the cells the coupling needs would leave the grid (coupling_reach_cells).
  const double minimum = coupling_reach_cells(coupling_options(s)) - 0.5;
  const double distance = contact_distance_cells(s);
  const std::string needs = s.coupling == CouplingKind::momentum_exchange
                                ? std::string("the momentum exchange's boundary links")
                                : fmt::format("the {} kernel's forcing stencil", ibm::to_string(s.kernel));
  if (!(distance >= minimum))
    throw InputError(
        fmt::format("contact.distance_cells: must be at least {} cells with this coupling (a body resting closer "
                    "to a wall would put {} outside the grid), got {}",
                    minimum, needs, distance));
}

void check_setup(const SimulationSetup& s) {
  if (!s.shape) throw std::invalid_argument("plan_case: the set-up has no shape");
  check_assigned(s);
  if (!(s.particle_density_si > 0.0)) throw InputError("particle.density: must be > 0");
  if (s.motion == body::MotionKind::free && s.body_force_si.norm() > 0.0)
    throw InputError(
        "fluid.body_force: only for particle.motion = \"fixed\" or \"towed\" (a free particle would be "
        "carried by the driven flow); set it to [0, 0, 0]");
  // The immersed boundary forces the fluid towards the body's velocity at every lattice step; held
  // for two, its wrench would need its own averaging, which it does not have.
  if (s.lattice_steps_per_body_step == 2 && s.coupling != CouplingKind::momentum_exchange)
    throw InputError(
        "numerics.lattice_steps_per_body_step: 2 is for numerics.coupling = \"momentum_exchange\" only; set it to 1 "
        "or choose the momentum exchange");
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
  plan.cell_reynolds = expected * units.dx_si() / units.kinematic_viscosity_si();
  plan.subgrid_model = lbm::chosen_subgrid_model(s.subgrid_model, s.collision, plan.cell_reynolds);
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

CouplingOptions coupling_options(const SimulationSetup& setup) {
  CouplingOptions options;
  options.kind = setup.coupling;
  options.kernel = setup.kernel;
  options.forcing_iterations = setup.forcing_iterations;
  options.marker_retraction_cells = setup.marker_retraction_cells;
  options.interior_markers = setup.interior_markers;
  options.wall_rule = setup.wall_rule;
  options.covered_cell_torque = setup.covered_cell_torque;
  options.lattice_steps_per_body_step = setup.lattice_steps_per_body_step;
  return options;
}

double contact_distance_cells(const SimulationSetup& setup) {
  return setup.contact_distance_cells.value_or(coupling_reach_cells(coupling_options(setup)));
}

void check_body_box_in_grid(const SimulationSetup& setup, double dx_si, const std::array<int, 3>& cells) {
  static constexpr const char* kAxis = "xyz";
  const LatticeFrame start_frame{Eigen::Vector3d::Zero(), dx_si};
  const CellBox box =
      coupling_box(coupling_options(setup), *setup.shape, dx_si, start_frame.to_lattice(setup.initial.position_si),
                   setup.initial.attitude.body_to_inertial());
  const char* what = setup.coupling == CouplingKind::momentum_exchange ? "the momentum exchange's boundary links"
                                                                       : "the immersed-boundary forcing stencil";
  for (std::size_t i = 0; i < 3; ++i) {
    const int first = box.origin[i], last = box.origin[i] + box.extent[i] - 1, n = cells[i];
    if (setup.boundaries[i] == lbm::Boundary::periodic) {
      if (box.extent[i] > n)
        throw InputError(
            fmt::format("domain.size: along {} the periodic domain is {} cells, but the particle and {} "
                        "span {} cells; enlarge domain.size along {}",
                        kAxis[i], n, what, box.extent[i], kAxis[i]));
      continue;
    }
    // Cells past the wall planes at lattice -1/2 and n - 1/2: moving the body by as many whole
    // cells clears them.
    const int beyond = first < 0 ? -first : last - (n - 1);
    if (beyond <= 0) continue;
    throw InputError(fmt::format(
        "particle.position: at its initial attitude the particle and {} reach {} cell{} ({:.4g} m) past the wall at "
        "{} = {:.4g} m; move particle.position at least {:.4g} m further in, or enlarge domain.size",
        what, beyond, beyond == 1 ? "" : "s", beyond * dx_si, kAxis[i], first < 0 ? 0.0 : n * dx_si, beyond * dx_si));
  }
}

std::optional<body::WallContact> start_wall_contact(const SimulationSetup& setup, double dx_si, double dt_si,
                                                    const std::array<int, 3>& cells,
                                                    const Eigen::Vector3d& window_origin_si) {
  if (!setup.wall_contact || setup.follow_particle || setup.motion != body::MotionKind::free) return std::nullopt;
  // Half-way walls: the faces of the grid, at 0 and cells x dx from the window's corner.
  std::vector<body::WallPlane> walls;
  const auto open = [&](int axis, int side) {
    const lbm::Face face{axis, side};
    return (setup.inflow && *setup.inflow == face) || (setup.outflow && *setup.outflow == face);
  };
  for (int a = 0; a < 3; ++a) {
    const auto i = static_cast<std::size_t>(a);
    if (setup.boundaries[i] == lbm::Boundary::periodic) continue;
    const Eigen::Vector3d axis = Eigen::Vector3d::Unit(a);
    if (!open(a, 0)) walls.push_back({axis, window_origin_si[a]});
    if (!open(a, 1)) walls.push_back({-axis, -(window_origin_si[a] + cells[i] * dx_si)});
  }
  if (walls.empty()) return std::nullopt;
  body::ContactParameters parameters;
  parameters.restitution = setup.contact_restitution;
  parameters.wet_stokes_scale = setup.contact_wet_stokes_scale;
  parameters.fluid_dynamic_viscosity_si = setup.dynamic_viscosity_si;
  parameters.collision_time_si = setup.contact_collision_steps * dt_si;
  parameters.contact_distance_si = contact_distance_cells(setup) * dx_si;
  std::optional<body::WallContact> contact(std::in_place, setup.shape, std::move(walls), parameters);

  // Resting on the wall at zeta - W/k is allowed; k from the whole mass, as the model uses it.
  const double mass_si = setup.shape->mass_properties(setup.particle_density_si).mass;
  const double net_weight_si =
      std::abs((setup.particle_density_si - setup.fluid_density_si) * setup.shape->volume()) * setup.gravity_si.norm();
  const double compression_si = net_weight_si / body::spring_dashpot(mass_si, mass_si, parameters).stiffness;
  const double gap_si = contact->min_gap_si(setup.initial);
  if (gap_si < parameters.contact_distance_si - 2.0 * compression_si)
    throw InputError(fmt::format(
        "particle.position: the particle starts {:.4g} m ({:.3g} cells) from a wall, inside the "
        "wall-contact distance of {:.3g} cells (contact.distance_cells); its contact spring "
        "would throw it off. Move it at least {:.4g} m from the walls, lower "
        "contact.distance_cells, or set contact.enabled = false",
        gap_si, gap_si / dx_si, contact_distance_cells(setup), parameters.contact_distance_si - compression_si));
  return contact;
}

}  // namespace settle::coupling
