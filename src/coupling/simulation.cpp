#include "coupling/simulation.hpp"

#include <algorithm>
#include <cmath>
#include <stdexcept>

#include <fmt/core.h>

#include "common/error.hpp"
#include "coupling/lattice_view.hpp"
#include "ibm/forcing.hpp"
#include "lbm/decomposition.hpp"
#include "parallel/lattice_steps.hpp"

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

// The plan's grid as the solver's integer extents; io::preflight refuses these cases first with the
// memory they would need, this guards set-ups built in code.
std::array<int, 3> grid_cells(const CasePlan& plan, const SimulationSetup& s) {
  std::array<int, 3> n{};
  for (std::size_t a = 0; a < 3; ++a) {
    if (plan.cells[a] < 4.0)
      throw InputError(
          fmt::format("domain.size: {:.4g} m along axis {} is {} cells; at least 4 needed (raise domain.size "
                      "or numerics.cells_per_diameter)",
                      s.domain_size_si[static_cast<int>(a)], "xyz"[a], plan.cells[a]));
    n[a] = static_cast<int>(plan.cells[a]);
  }
  if (plan.cell_count() > kMaxGridCells)
    throw InputError(
        fmt::format("numerics.cells_per_diameter: the domain needs {:.3g} cells (more than {:.0e}); lower "
                    "numerics.cells_per_diameter or domain.size",
                    plan.cell_count(), kMaxGridCells));
  return n;
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

// A held body's velocities at time t: a towed body's towed_velocity_si(t) if it has one; else the
// initial ones, or during particle.hold_ramp_time that fraction of them. A body set moving at once
// (at a lattice velocity of 0.05) strikes the fluid with a pressure pulse of about 10% of its
// density; ramped up over some hundreds of steps it pushes the fluid aside as an added mass would,
// without the pulse (docs/coupling.md, "Held start").
body::RigidBodyState held_state_at(const SimulationSetup& s, body::RigidBodyState state, double t_si) {
  if (s.motion == body::MotionKind::towed && s.towed_velocity_si) {
    state.velocity_si = s.towed_velocity_si(t_si);
    return state;
  }
  const double fraction = s.hold_ramp_time_si > 0.0 ? std::min(1.0, t_si / s.hold_ramp_time_si) : 1.0;
  state.velocity_si = fraction * s.initial.velocity_si;
  state.angular_velocity_b_si = fraction * s.initial.angular_velocity_b_si;
  return state;
}

}  // namespace

bool Simulation::ramping() const {
  if (setup_.motion == body::MotionKind::towed && setup_.towed_velocity_si) return true;
  if (!(setup_.hold_ramp_time_si > 0.0)) return false;
  if (setup_.motion == body::MotionKind::towed)
    return static_cast<double>(steps_) * plan_.units.dt_si() < setup_.hold_ramp_time_si;
  return held();
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

Simulation::Simulation(SimulationSetup setup, parallel::Communicator& communicator)
    : setup_(std::move(setup)), communicator_(communicator), plan_(plan_case(setup_)) {
  const body::Shape& shape = *setup_.shape;
  derived_.cells = grid_cells(plan_, setup_);
  frame_.dx_si = plan_.units.dx_si();

  const lbm::SolverConfig config = fluid_config();
  lbm::validate(config);

  coupling_ = make_coupling(setup_.shape, plan_.units.dx_si(), coupling_options(setup_), communicator_);

  // The body and the cells its coupling works on must start inside the grid: checked before the
  // grid is allocated, by the rule the preflight applies too.
  check_body_box_in_grid(setup_, plan_.units.dx_si(), derived_.cells);
  window_anchor_ = frame_.to_lattice(setup_.initial.position_si);

  body::Environment environment{setup_.fluid_density_si, setup_.gravity_si};
  body_ = std::make_unique<body::RigidBody>(shape.mass_properties(setup_.particle_density_si), environment,
                                            ramping() ? held_state_at(setup_, setup_.initial, 0.0) : setup_.initial,
                                            setup_.motion);
  if (setup_.rotation_locked) body_->lock_rotation();
  if (setup_.motion == body::MotionKind::free) virtual_inertia_ = virtual_inertia_for(*body_, setup_.fluid_density_si);
  contact_ =
      start_wall_contact(setup_, plan_.units.dx_si(), plan_.units.dt_si(), derived_.cells, frame_.window_origin_si);

  fluid_ = lbm::make_solver(config);
  // With an inlet the fluid starts as its stream and the body appears in it at once: the
  // pressure pulse of that start is local and spreads out. A stream ramped up from rest instead
  // rings the whole column between the reflecting inlet and outlet as an acoustic mode that the
  // viscosity of a low-tau case does not damp (docs/lbm.md, "Inlets and outlets").
  const lbm::CellState start{1.0, config.inflow_velocity};
  fluid_->initialise([&start](int, int, int) { return start; });
  coupling_->start(*fluid_, lattice_pose({setup_.initial.position_si, setup_.initial.attitude}));
  derived_.surface_element_count = coupling_->surface_element_count();
}

lbm::SolverConfig Simulation::fluid_config() const {
  lbm::SolverConfig config;
  config.lattice = setup_.lattice;
  config.collision = setup_.collision;
  config.magic = setup_.trt_magic;
  config.subgrid = plan_.subgrid_model;
  config.smagorinsky_constant = setup_.smagorinsky_constant;
  config.precision = setup_.precision;
  config.nx = derived_.cells[0];
  config.ny = derived_.cells[1];
  config.nz = derived_.cells[2];
  if (communicator_.size() > 1) {
    config.split = lbm::choose_split(derived_.cells, communicator_.size(), communicator_.rank());
    const std::array<int, 3> block = config.split->extent(communicator_.rank());
    config.nx = block[0], config.ny = block[1], config.nz = block[2];
    if (setup_.coupling == CouplingKind::momentum_exchange && setup_.wall_rule == lbm::WallRule::quadratic &&
        config.split->thinnest_block() < 2)
      throw InputError(fmt::format(
          "numerics.wall_rule: \"quadratic\" reads two cells behind a link and needs blocks at least two cells thick; "
          "{} ranks split this lattice into thinner ones: run on fewer ranks or choose \"bouzidi\"",
          communicator_.size()));
  }
  config.boundaries = setup_.boundaries;
  config.tau = plan_.units.tau();
  for (int a = 0; a < 3; ++a) config.body_force[a] = plan_.units.force_density(setup_.body_force_si[a]);
  if (setup_.inflow) {
    config.open_faces.push_back({*setup_.inflow, lbm::Boundary::velocity});
    config.inflow_velocity = lattice_velocity(setup_.inflow_velocity_si);
  }
  if (setup_.outflow) config.open_faces.push_back({*setup_.outflow, lbm::Boundary::outflow});
  return config;
}

Eigen::Vector3d Simulation::lattice_velocity(const Eigen::Vector3d& velocity_si) const {
  Eigen::Vector3d u;
  for (int a = 0; a < 3; ++a) u[a] = plan_.units.velocity(velocity_si[a]);
  return u;
}

LatticePose Simulation::lattice_pose(const body::Pose& pose) const {
  const double dt_si = plan_.units.dt_si();
  const auto& state = body_->state();
  LatticePose p;
  p.centre = frame_.to_lattice(pose.position_si);
  p.body_to_inertial = pose.attitude.body_to_inertial();
  p.velocity = state.velocity_si * dt_si / plan_.units.dx_si();
  p.angular_velocity_n = p.body_to_inertial * state.angular_velocity_b_si * dt_si;
  return p;
}

CellBox Simulation::box_at(const Eigen::Vector3d& centre, const Eigen::Matrix3d& body_to_inertial) const {
  return coupling_->box_at(centre, body_to_inertial);
}

bool Simulation::can_step() const {
  // Mid-way through a body step the walls stay where its start placed them.
  if (!between_body_steps()) return true;
  const body::Pose pose = body_->predict_pose(body_step_dt_si());
  return box_fits(box_at(frame_.to_lattice(pose.position_si), pose.attitude.body_to_inertial()), *fluid_);
}

SolidCells Simulation::current_solid_cells() const {
  const Eigen::Vector3d centre = frame_.to_lattice(body_->state().position_si);
  const Eigen::Matrix3d rotation = body_->body_to_inertial();
  return solid_cells(*setup_.shape, plan_.units.dx_si(), box_at(centre, rotation), centre, rotation);
}

bool Simulation::between_body_steps() const { return steps_ % setup_.lattice_steps_per_body_step == 0; }

double Simulation::body_step_dt_si() const { return setup_.lattice_steps_per_body_step * plan_.units.dt_si(); }

void Simulation::step() {
  const double dt_si = plan_.units.dt_si();
  const bool body_step_starts = between_body_steps();
  const bool body_step_ends = (steps_ + 1) % setup_.lattice_steps_per_body_step == 0;
  const SubStepNames names = coupling_->sub_step_names();
  if (body_step_starts) place_body();
  {
    ScopedTimer timer(timers_, names.impose);
    coupling_->impose(*fluid_);
  }
  {
    ScopedTimer timer(timers_, "fluid");
    parallel::step(*fluid_, communicator_);
  }
  {
    ScopedTimer timer(timers_, names.measure);
    const CouplingForces forces = coupling_->measure(*fluid_);
    const auto to_si = [&](const LatticeWrench& w) {
      body::Wrench si;
      for (int a = 0; a < 3; ++a) {
        si.force_si[a] = plan_.units.force_si(w.force[a]);
        si.torque_si[a] = plan_.units.torque_si(w.torque[a]);
      }
      return si;
    };
    last_.hydrodynamic = to_si(forces.total);
    last_.surface = to_si(forces.surface);
    last_.internal_rate = to_si(forces.internal_rate);
    last_.slip_max_si = plan_.units.velocity_si(forces.slip_max);
    last_.slip_rms_si = plan_.units.velocity_si(forces.slip_rms);
  }
  if (body_step_ends) {
    move_body(static_cast<double>(steps_ + 1) * dt_si);
    ScopedTimer timer(timers_, "moving_window");
    if (setup_.follow_particle) follow_body();
  }
  ++steps_;
}

void Simulation::place_body() {
  body::Pose pose;
  {
    ScopedTimer timer(timers_, "body_predictor");
    pose = body_->predict_pose(body_step_dt_si());
  }
  ScopedTimer timer(timers_, coupling_->sub_step_names().place);
  const LatticePose placed = lattice_pose(pose);
  if (!box_fits(box_at(placed.centre, placed.body_to_inertial), *fluid_))
    throw std::logic_error("Simulation::step: the body left the grid (check can_step)");
  coupling_->place(*fluid_, placed);
}

void Simulation::move_body(double end_time_si) {
  ScopedTimer timer(timers_, "body_corrector");
  const double dt_si = body_step_dt_si();
  const body::RigidBodyState start = body_->state();
  const bool ramp = ramping();
  if (held()) {
    body_->hold(dt_si);
  } else if (contact_) {
    const body::ContactStep contact = contact_->advance(*body_, dt_si, last_.hydrodynamic, virtual_inertia_);
    last_.contact = contact.mean_wrench;
    last_.wall_gap_si = contact.min_gap_si;
  } else {
    body_->correct(dt_si, last_.hydrodynamic, virtual_inertia_);
  }
  if (ramp) body_->set_state(held_state_at(setup_, body_->state(), end_time_si));
  // This step's mean accelerations are the next step's estimate a_est (the previous step's
  // acceleration, as waLBerla's AddVirtualForceTorqueKernel takes it): a lag of one step, so the
  // virtual terms m_v (a_est - a) vanish whenever the acceleration is steady.
  virtual_inertia_.acceleration_si = (body_->state().velocity_si - start.velocity_si) / dt_si;
  virtual_inertia_.angular_acceleration_b_si =
      (body_->state().angular_velocity_b_si - start.angular_velocity_b_si) / dt_si;
}

void Simulation::follow_body() {
  const Eigen::Vector3d centre = frame_.to_lattice(body_->state().position_si);
  for (int a = 0; a < 3; ++a) {
    // A periodic axis is a ring: the body crosses its wrap as it is, where a shift would drop the
    // layer it leaves and refill the other face at rest, a seam in the ring the fluid wraps across.
    if (setup_.boundaries[static_cast<std::size_t>(a)] == lbm::Boundary::periodic) continue;
    const double offset = centre[a] - window_anchor_[a];
    if (std::abs(offset) < 1.0) continue;
    const int sign = offset > 0.0 ? 1 : -1;
    parallel::shift(*fluid_, a, sign, communicator_);
    frame_.window_origin_si[a] += sign * plan_.units.dx_si();
  }
}

lbm::FieldExtrema Simulation::fluid_extrema() const {
  lbm::FieldExtrema mine = fluid_->extrema();
  if (communicator_.size() == 1) return mine;
  const std::array<int, 3> o = fluid_->config().split->offset(communicator_.rank());
  std::vector<double> packed{mine.finite ? 1.0 : 0.0, mine.min_density, mine.max_density, mine.max_speed};
  for (const auto* cell : {&mine.min_density_cell, &mine.max_density_cell, &mine.max_speed_cell})
    for (std::size_t a = 0; a < 3; ++a) packed.push_back((*cell)[a] + o[a]);
  const auto cell_at = [](const std::vector<double>& p, std::size_t first) {
    return std::array<int, 3>{static_cast<int>(p[first]), static_cast<int>(p[first + 1]),
                              static_cast<int>(p[first + 2])};
  };
  // In rank order, with the rule of one block's rows.
  lbm::FieldExtrema all;
  for (const std::vector<double>& p : communicator_.gather_all(packed)) {
    lbm::FieldExtrema block;
    block.finite = p[0] != 0.0;
    block.min_density = p[1], block.max_density = p[2], block.max_speed = p[3];
    block.min_density_cell = cell_at(p, 4), block.max_density_cell = cell_at(p, 7),
    block.max_speed_cell = cell_at(p, 10);
    all.merge_later(block);
  }
  return all;
}

Eigen::Vector3d Simulation::superficial_velocity_si() const {
  const lbm::VectorField u = fluid_->velocity_field();
  Eigen::Vector3d sum = Eigen::Vector3d::Zero();
  for (std::size_t n = 0; n < u.x.size(); ++n) sum += Eigen::Vector3d(u.x[n], u.y[n], u.z[n]);
  // Solid cells of a momentum-exchange body report zero velocity already; fluid inside an
  // immersed boundary is taken out by its volume fractions.
  if (coupling_->fluid_inside()) {
    const SolidCells cells = current_solid_cells();
    const LatticeView view(*fluid_);
    for (std::size_t n = 0; n < cells.cell.size(); ++n) {
      const auto wrapped = view.wrap(cells.cell[n]);
      if (!wrapped || view.owner(*wrapped) != view.rank()) continue;  // another block's
      const auto c = view.to_block(*wrapped);
      sum -= cells.alpha[n] * fluid_->cell_velocity(c[0], c[1], c[2]);
    }
  }
  if (communicator_.size() > 1) {
    const std::vector<double> total = parallel::sum_in_rank_order(communicator_, {sum.x(), sum.y(), sum.z()});
    sum = Eigen::Vector3d(total[0], total[1], total[2]);
  }
  Eigen::Vector3d mean = sum / plan_.cell_count();
  for (int a = 0; a < 3; ++a) mean[a] = plan_.units.velocity_si(mean[a]);
  return mean;
}

}  // namespace settle::coupling
