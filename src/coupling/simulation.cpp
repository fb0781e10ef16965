#include "coupling/simulation.hpp"

#include <algorithm>
#include <cmath>
#include <numbers>
#include <stdexcept>

#include <fmt/core.h>

#include "common/error.hpp"
#include "ibm/forcing.hpp"

namespace settle::coupling {
namespace {

using Clock = std::chrono::steady_clock;

// Times one sub-step into the timers on scope exit.
class ScopedTimer {
 public:
  ScopedTimer(SubstepTimers& timers, const char* name) : timers_(timers), name_(name), start_(Clock::now()) {}
  ~ScopedTimer() { timers_.add(name_, std::chrono::duration<double>(Clock::now() - start_).count()); }
  ScopedTimer(const ScopedTimer&) = delete;
  ScopedTimer& operator=(const ScopedTimer&) = delete;

 private:
  SubstepTimers& timers_;
  const char* name_;
  Clock::time_point start_;
};

// Largest cell count we allocate without asking: 2^31 cells is ~300 GB of D3Q19 doubles.
constexpr double kMaxCells = 2.0e9;

// Default contact distance: the kernel's half-width. The stencil of a point at lattice coordinate
// x starts at cell floor(x - h) + 1 (ibm::axis_stencil), which stays >= 0 for a point at least
// h - 1/2 cells above the wall plane at -1/2; the extra half cell takes the overlap of impacts.
double contact_distance_cells(const SimulationSetup& s) {
  return s.contact_distance_cells.value_or(ibm::support_half_width(s.kernel));
}

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
  if (!s.shape) throw std::invalid_argument("Simulation: no shape");
  if (!(s.particle_density_si > 0.0)) throw InputError("particle.density: must be > 0");
  if (!(s.end_time_si > 0.0)) throw InputError("run.end_time: must be > 0");
  if (s.forcing_iterations < 1) throw InputError("numerics.forcing_iterations: must be >= 1");
  if (s.motion == body::MotionKind::free && s.body_force_si.norm() > 0.0)
    throw InputError("fluid.body_force: only for particle.motion = \"fixed\" or \"towed\" (a free particle would be "
                     "carried by the driven flow); set it to [0, 0, 0]");
  check_contact_setup(s);
}

std::array<int, 3> grid_cells(const SimulationSetup& s, double dx_si) {
  std::array<int, 3> n{};
  double total = 1.0;
  for (int a = 0; a < 3; ++a) {
    const double cells = std::round(s.domain_size_si[a] / dx_si);
    if (cells < 4.0)
      throw InputError(fmt::format("domain.size: {:.4g} m along axis {} is {} cells; at least 4 needed (raise domain.size "
                                   "or numerics.cells_per_diameter)",
                                   s.domain_size_si[a], "xyz"[a], cells));
    total *= cells;
    n[static_cast<std::size_t>(a)] = static_cast<int>(cells);
  }
  if (total > kMaxCells)
    throw InputError(fmt::format("numerics.cells_per_diameter: the domain needs {:.3g} cells (more than {:.0e}); lower "
                                 "numerics.cells_per_diameter or domain.size",
                                 total, kMaxCells));
  return n;
}

UnitConverter converter_for(const SimulationSetup& s) {
  check_setup(s);
  UnitInputs in;
  in.equivalent_diameter_si = s.shape->equivalent_diameter();
  in.cells_per_diameter = s.cells_per_diameter;
  in.fluid_density_si = s.fluid_density_si;
  in.dynamic_viscosity_si = s.dynamic_viscosity_si;
  in.expected_speed_si = expected_speed_si(s);
  in.max_lattice_velocity = s.max_lattice_velocity;
  in.max_tau = s.max_tau;
  in.tau = s.tau;
  return make_unit_converter(in);
}

// Virtual mass and inertia of the corrector, in units of the displaced fluid's mass rho_f V and
// rigid-body inertia (rho_f / rho_p) I. Values and their derivation: docs/coupling.md, "Stability
// of light bodies".
constexpr double kVirtualMassCoefficient = 0.5;
constexpr double kVirtualInertiaCoefficient = 1.0;

body::VirtualInertia virtual_inertia_for(const body::RigidBody& body, double fluid_density_si) {
  const body::MassProperties& m = body.mass_properties();
  body::VirtualInertia v;
  v.mass_si = kVirtualMassCoefficient * fluid_density_si * m.volume;
  v.inertia_b_si = kVirtualInertiaCoefficient * (fluid_density_si * m.volume / m.mass) * m.inertia;
  return v;
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

double default_inflow_ramp_time_si(const SimulationSetup& s) {
  const double speed = s.inflow_velocity_si.norm();
  return speed > 0.0 ? 2.0 * s.shape->equivalent_diameter() / speed : 0.0;
}

Eigen::Vector3d inflow_velocity_at_si(const SimulationSetup& s, double t_si) {
  const double ramp = s.inflow_ramp_time_si.value_or(default_inflow_ramp_time_si(s));
  if (!(t_si < ramp)) return s.inflow_velocity_si;
  const double phase = std::sin(0.5 * std::numbers::pi * t_si / ramp);
  return s.inflow_velocity_si * phase * phase;
}

void SubstepTimers::add(const char* name, double seconds) {
  for (auto& [entry_name, total] : entries_)
    if (entry_name == name) {
      total += seconds;
      return;
    }
  entries_.emplace_back(name, seconds);
}

double SubstepTimers::total() const {
  double sum = 0.0;
  for (const auto& entry : entries_) sum += entry.second;
  return sum;
}

Simulation::Simulation(SimulationSetup setup) : setup_(std::move(setup)), units_(converter_for(setup_)) {
  const body::Shape& shape = *setup_.shape;
  derived_.equivalent_diameter_si = shape.equivalent_diameter();
  derived_.dx_si = units_.dx_si();
  derived_.dt_si = units_.dt_si();
  derived_.tau = units_.tau();
  derived_.expected_speed_si = expected_speed_si(setup_);
  derived_.mach = mach_number(units_.velocity(derived_.expected_speed_si));
  derived_.reynolds = derived_.expected_speed_si * derived_.equivalent_diameter_si / units_.kinematic_viscosity_si();
  derived_.galileo = galileo_number(derived_.equivalent_diameter_si, setup_.particle_density_si, setup_.fluid_density_si,
                                    units_.kinematic_viscosity_si(), setup_.gravity_si.norm());
  derived_.cells = grid_cells(setup_, units_.dx_si());
  // The first step that starts at or after the release time (a relative tolerance keeps a time
  // given as a whole number of steps from rounding up by one).
  if (setup_.motion == body::MotionKind::free && setup_.release_time_si > 0.0)
    derived_.release_step = static_cast<std::int64_t>(std::ceil(setup_.release_time_si / units_.dt_si() * (1.0 - 1e-12)));
  frame_.dx_si = units_.dx_si();

  const lbm::SolverConfig config = fluid_config();
  lbm::validate(config);

  CouplingOptions options;
  options.kind = setup_.coupling;
  options.kernel = setup_.kernel;
  options.forcing_iterations = setup_.forcing_iterations;
  options.marker_retraction_cells = setup_.marker_retraction_cells;
  options.interior_markers = setup_.interior_markers;
  options.wall_rule = setup_.wall_rule;
  coupling_ = make_coupling(setup_.shape, units_.dx_si(), options);

  // The body and its stencil must start inside the grid: checked before the grid is allocated.
  const Eigen::Vector3d centre = frame_.to_lattice(setup_.initial.position_si);
  window_anchor_ = centre;
  const CellBox box = box_at(centre, setup_.initial.attitude.body_to_inertial());
  for (int a = 0; a < 3; ++a) {
    const auto i = static_cast<std::size_t>(a);
    const int n = derived_.cells[i];
    const bool periodic = setup_.boundaries[i] == lbm::Boundary::periodic;
    if ((periodic && box.extent[i] > n) || (!periodic && (box.origin[i] < 0 || box.origin[i] + box.extent[i] > n)))
      throw InputError(fmt::format(
          "particle.position: the particle (width {:.4g} m along {} at its initial orientation) and its forcing "
          "stencil reach outside the domain; move particle.position or enlarge domain.size",
          shape.width(setup_.initial.attitude.body_to_inertial().row(a).transpose()), "xyz"[a]));
  }

  body::Environment environment{setup_.fluid_density_si, setup_.gravity_si};
  body_ = std::make_unique<body::RigidBody>(shape.mass_properties(setup_.particle_density_si), environment,
                                            setup_.initial, setup_.motion);
  if (setup_.motion == body::MotionKind::free) virtual_inertia_ = virtual_inertia_for(*body_, setup_.fluid_density_si);
  make_wall_contact();

  fluid_ = lbm::make_solver(config);
  fluid_->initialise([](int, int, int) { return lbm::CellState{}; });
  ramp_inflow();
  coupling_->start(*fluid_, lattice_pose({setup_.initial.position_si, setup_.initial.attitude}));
  derived_.marker_count = coupling_->surface_element_count();
}

lbm::SolverConfig Simulation::fluid_config() const {
  lbm::SolverConfig config;
  config.lattice = setup_.lattice;
  config.collision = setup_.collision;
  config.precision = setup_.precision;
  config.nx = derived_.cells[0];
  config.ny = derived_.cells[1];
  config.nz = derived_.cells[2];
  config.boundaries = setup_.boundaries;
  config.tau = units_.tau();
  for (int a = 0; a < 3; ++a) config.body_force[a] = units_.force_density(setup_.body_force_si[a]);
  if (setup_.inflow) {
    config.open_faces.push_back({*setup_.inflow, lbm::Boundary::velocity});
    config.inflow_velocity = lattice_velocity(setup_.inflow_velocity_si);
  }
  if (setup_.outflow) config.open_faces.push_back({*setup_.outflow, lbm::Boundary::outflow});
  return config;
}

Eigen::Vector3d Simulation::lattice_velocity(const Eigen::Vector3d& velocity_si) const {
  Eigen::Vector3d u;
  for (int a = 0; a < 3; ++a) u[a] = units_.velocity(velocity_si[a]);
  return u;
}

void Simulation::ramp_inflow() {
  if (!setup_.inflow) return;
  // The velocity of the coming step's streaming, at its end time.
  const double t_si = static_cast<double>(steps_ + 1) * units_.dt_si();
  fluid_->set_inflow_velocity(lattice_velocity(inflow_velocity_at_si(setup_, t_si)));
}

LatticePose Simulation::lattice_pose(const body::Pose& pose) const {
  const double dt_si = units_.dt_si();
  const auto& state = body_->state();
  LatticePose p;
  p.centre = frame_.to_lattice(pose.position_si);
  p.body_to_inertial = pose.attitude.body_to_inertial();
  p.velocity = state.velocity_si * dt_si / units_.dx_si();
  p.angular_velocity_n = p.body_to_inertial * state.angular_velocity_b_si * dt_si;
  return p;
}

CellBox Simulation::box_at(const Eigen::Vector3d& centre, const Eigen::Matrix3d& body_to_inertial) const {
  return coupling_->box_at(centre, body_to_inertial);
}

void Simulation::make_wall_contact() {
  if (!setup_.wall_contact || setup_.follow_particle || setup_.motion != body::MotionKind::free) return;
  // Half-way walls: the faces of the grid, at 0 and cells x dx from the window's corner.
  std::vector<body::WallPlane> walls;
  const auto open = [&](int axis, int side) {
    const lbm::Face face{axis, side};
    return (setup_.inflow && *setup_.inflow == face) || (setup_.outflow && *setup_.outflow == face);
  };
  for (int a = 0; a < 3; ++a) {
    const auto i = static_cast<std::size_t>(a);
    if (setup_.boundaries[i] == lbm::Boundary::periodic) continue;
    const Eigen::Vector3d axis = Eigen::Vector3d::Unit(a);
    if (!open(a, 0)) walls.push_back({axis, frame_.window_origin_si[a]});
    if (!open(a, 1)) walls.push_back({-axis, -(frame_.window_origin_si[a] + derived_.cells[i] * units_.dx_si())});
  }
  if (walls.empty()) return;
  body::ContactParameters parameters;
  parameters.restitution = setup_.contact_restitution;
  parameters.wet_stokes_scale = setup_.contact_wet_stokes_scale;
  parameters.fluid_dynamic_viscosity_si = setup_.dynamic_viscosity_si;
  parameters.collision_time_si = setup_.contact_collision_steps * units_.dt_si();
  parameters.contact_distance_si = contact_distance_cells(setup_) * units_.dx_si();
  contact_.emplace(setup_.shape, std::move(walls), parameters);

  // A body starting deeper in the spring than its own weight would press it (twice the static
  // compression) would be thrown off the wall by the stored energy: refused. Resting on the wall at
  // zeta - W/k is allowed.
  const double mass = body_->mass_properties().mass;
  const double compression = body_->net_weight_si().norm() / body::spring_dashpot(mass, mass, parameters).stiffness;
  const double gap = contact_->min_gap_si(body_->state());
  if (gap < parameters.contact_distance_si - 2.0 * compression)
    throw InputError(fmt::format("particle.position: the particle starts {:.4g} m ({:.3g} cells) from a wall, inside the "
                                 "wall-contact distance of {:.3g} cells (contact.distance_cells); its contact spring would "
                                 "throw it off. Move it at least {:.4g} m from the walls",
                                 gap, gap / units_.dx_si(), contact_distance_cells(setup_),
                                 parameters.contact_distance_si - compression));
}

bool Simulation::can_step() const {
  const body::Pose pose = body_->predict_pose(units_.dt_si());
  return box_fits(box_at(frame_.to_lattice(pose.position_si), pose.attitude.body_to_inertial()), *fluid_);
}

SolidCells Simulation::current_solid_cells() const {
  const Eigen::Vector3d centre = frame_.to_lattice(body_->state().position_si);
  const Eigen::Matrix3d rotation = body_->body_to_inertial();
  return solid_cells(*setup_.shape, units_.dx_si(), box_at(centre, rotation), centre, rotation);
}

void Simulation::step() {
  const double dt_si = units_.dt_si();
  body::Pose pose;
  {
    ScopedTimer timer(timers_, "body_predictor");
    pose = body_->predict_pose(dt_si);
  }

  {
    ScopedTimer timer(timers_, "markers");
    const LatticePose placed = lattice_pose(pose);
    if (!box_fits(box_at(placed.centre, placed.body_to_inertial), *fluid_))
      throw std::logic_error("Simulation::step: the body left the grid (check can_step)");
    coupling_->place(*fluid_, placed);
  }
  {
    ScopedTimer timer(timers_, "forcing");
    coupling_->impose(*fluid_);
  }
  {
    ScopedTimer timer(timers_, "fluid");
    ramp_inflow();
    fluid_->step();
  }
  {
    ScopedTimer timer(timers_, "hydrodynamic_force");
    const CouplingForces forces = coupling_->measure(*fluid_);
    const auto to_si = [&](const LatticeWrench& w) {
      body::Wrench si;
      for (int a = 0; a < 3; ++a) {
        si.force_si[a] = units_.force_si(w.force[a]);
        si.torque_si[a] = units_.torque_si(w.torque[a]);
      }
      return si;
    };
    last_.hydrodynamic = to_si(forces.total);
    last_.marker_reaction = to_si(forces.surface);
    last_.internal_rate = to_si(forces.internal_rate);
    last_.slip_max_si = units_.velocity_si(forces.slip_max);
    last_.slip_rms_si = units_.velocity_si(forces.slip_rms);
  }
  {
    ScopedTimer timer(timers_, "body_corrector");
    const body::RigidBodyState start = body_->state();
    if (held()) {
      body_->hold(dt_si);
    } else if (contact_) {
      const body::ContactStep contact = contact_->advance(*body_, dt_si, last_.hydrodynamic, virtual_inertia_);
      last_.contact = contact.mean_wrench;
      last_.wall_gap_si = contact.min_gap_si;
    } else {
      body_->correct(dt_si, last_.hydrodynamic, virtual_inertia_);
    }
    // This step's mean accelerations are the next step's estimate a_est (the previous step's
    // acceleration, as waLBerla's AddVirtualForceTorqueKernel takes it): a lag of one step, so the
    // virtual terms m_v (a_est - a) vanish whenever the acceleration is steady.
    virtual_inertia_.acceleration_si = (body_->state().velocity_si - start.velocity_si) / dt_si;
    virtual_inertia_.angular_acceleration_b_si =
        (body_->state().angular_velocity_b_si - start.angular_velocity_b_si) / dt_si;
  }
  {
    ScopedTimer timer(timers_, "moving_window");
    if (setup_.follow_particle) follow_body();
  }
  ++steps_;
}

void Simulation::follow_body() {
  const Eigen::Vector3d centre = frame_.to_lattice(body_->state().position_si);
  for (int a = 0; a < 3; ++a) {
    const double offset = centre[a] - window_anchor_[a];
    if (std::abs(offset) < 1.0) continue;
    const int sign = offset > 0.0 ? 1 : -1;
    fluid_->shift(a, sign);
    frame_.window_origin_si[a] += sign * units_.dx_si();
  }
}

Eigen::Vector3d Simulation::superficial_velocity_si() const {
  const lbm::VectorField u = fluid_->velocity_field();
  Eigen::Vector3d sum = Eigen::Vector3d::Zero();
  for (std::size_t n = 0; n < u.x.size(); ++n) sum += Eigen::Vector3d(u.x[n], u.y[n], u.z[n]);
  // Solid cells of a momentum-exchange body report zero velocity already; fluid inside an
  // immersed boundary is taken out by its volume fractions.
  if (coupling_->fluid_inside()) {
    const SolidCells cells = current_solid_cells();
    for (std::size_t n = 0; n < cells.cell.size(); ++n) {
      const auto& c = cells.cell[n];
      sum -= cells.alpha[n] * fluid_->cell_velocity(c[0], c[1], c[2]);
    }
  }
  Eigen::Vector3d mean = sum / static_cast<double>(fluid_->cell_count());
  for (int a = 0; a < 3; ++a) mean[a] = units_.velocity_si(mean[a]);
  return mean;
}

}  // namespace settle::coupling
