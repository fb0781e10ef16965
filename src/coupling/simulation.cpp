#include "coupling/simulation.hpp"

#include <cmath>
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

void check_setup(const SimulationSetup& s) {
  if (!s.shape) throw std::invalid_argument("Simulation: no shape");
  if (!(s.particle_density_si > 0.0)) throw InputError("particle.density: must be > 0");
  if (!(s.end_time_si > 0.0)) throw InputError("run.end_time: must be > 0");
  if (s.forcing_iterations < 1) throw InputError("numerics.forcing_iterations: must be >= 1");
  if (s.motion == body::MotionKind::free && s.body_force_si.norm() > 0.0)
    throw InputError("fluid.body_force: only for particle.motion = \"fixed\" or \"towed\" (a free particle would be "
                     "carried by the driven flow); set it to [0, 0, 0]");
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

}  // namespace

double expected_speed_si(const SimulationSetup& s) {
  const double d = s.shape->equivalent_diameter();
  const double rotation = s.initial.angular_velocity_b_si.norm() * s.shape->bounding_radius();
  switch (s.motion) {
    case body::MotionKind::towed:
      return s.initial.velocity_si.norm() + rotation;
    case body::MotionKind::fixed:
      return estimated_driven_speed_si(d, s.body_force_si.norm(), s.domain_size_si.prod(), s.fluid_density_si,
                                       s.dynamic_viscosity_si);
    case body::MotionKind::free:
      break;
  }
  return estimated_terminal_speed_si(d, s.particle_density_si, s.fluid_density_si, s.dynamic_viscosity_si,
                                     s.gravity_si.norm()) +
         s.initial.velocity_si.norm() + rotation;
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
  frame_.dx_si = units_.dx_si();
  box_radius_cells_ = shape.bounding_radius() / units_.dx_si();

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
  lbm::validate(config);

  // The body and its stencil must start inside the grid: checked before the grid is allocated.
  const Eigen::Vector3d centre = frame_.to_lattice(setup_.initial.position_si);
  window_anchor_ = centre;
  const CellBox box = box_at(centre);
  for (int a = 0; a < 3; ++a) {
    const auto i = static_cast<std::size_t>(a);
    const int n = derived_.cells[i];
    const bool periodic = setup_.boundaries[i] == lbm::Boundary::periodic;
    if ((periodic && box.extent[i] > n) || (!periodic && (box.origin[i] < 0 || box.origin[i] + box.extent[i] > n)))
      throw InputError(fmt::format(
          "particle.position: the particle (bounding radius {:.4g} m) and its forcing stencil reach outside the "
          "domain along {}; move particle.position or enlarge domain.size",
          shape.bounding_radius(), "xyz"[a]));
  }

  body::Environment environment{setup_.fluid_density_si, setup_.gravity_si};
  body_ = std::make_unique<body::RigidBody>(shape.mass_properties(setup_.particle_density_si), environment,
                                            setup_.initial, setup_.motion);
  markers_ = make_body_markers(shape, units_.dx_si(), setup_.marker_retraction_cells);
  derived_.marker_count = markers_.size();

  fluid_ = lbm::make_solver(config);
  fluid_->initialise([](int, int, int) { return lbm::CellState{}; });
  internal_before_ = internal_momentum(*fluid_, current_solid_cells(), centre);
}

CellBox Simulation::box_at(const Eigen::Vector3d& centre) const {
  // Markers lie on or inside the surface, so the kernel's half-width (rounded outwards to whole
  // cells by box_around) covers their stencils; it also covers every cell the surface cuts
  // (centre within half a diagonal, 0.87 cells, of the surface) for the volume fractions.
  return box_around(centre, box_radius_cells_, ibm::support_half_width(setup_.kernel));
}

bool Simulation::can_step() const {
  const body::Pose pose = body_->predict_pose(units_.dt_si());
  return box_fits(box_at(frame_.to_lattice(pose.position_si)), *fluid_);
}

SolidCells Simulation::current_solid_cells() const {
  const Eigen::Vector3d centre = frame_.to_lattice(body_->state().position_si);
  return solid_cells(*setup_.shape, units_.dx_si(), box_at(centre), centre, body_->body_to_inertial());
}

void Simulation::step() {
  const double dt_si = units_.dt_si();
  body::Pose pose;
  {
    ScopedTimer timer(timers_, "body_predictor");
    pose = body_->predict_pose(dt_si);
  }

  ibm::Markers markers;
  Eigen::Vector3d centre;
  Eigen::Matrix3d rotation;
  CellBox box;
  {
    ScopedTimer timer(timers_, "markers");
    centre = frame_.to_lattice(pose.position_si);
    rotation = pose.attitude.body_to_inertial();
    const auto& state = body_->state();
    const Eigen::Vector3d velocity = state.velocity_si * dt_si / units_.dx_si();
    const Eigen::Vector3d omega_n = rotation * state.angular_velocity_b_si * dt_si;
    markers = place_markers(markers_, centre, rotation, velocity, omega_n);
    box = box_at(centre);
    if (!box_fits(box, *fluid_)) throw std::logic_error("Simulation::step: the body left the grid (check can_step)");
  }

  ibm::ForcingResult forcing;
  {
    ScopedTimer timer(timers_, "forcing");
    fluid_->clear_forces();
    ibm::LocalGrid grid = gather(*fluid_, box);
    forcing = ibm::multi_direct_forcing(grid, markers, {setup_.kernel, setup_.forcing_iterations});
    scatter_forces(*fluid_, grid);
  }
  {
    ScopedTimer timer(timers_, "fluid");
    fluid_->step();
  }
  {
    ScopedTimer timer(timers_, "hydrodynamic_force");
    const SolidCells cells = solid_cells(*setup_.shape, units_.dx_si(), box, centre, rotation);
    const FluidMomentum internal_after = internal_momentum(*fluid_, cells, centre);
    const LatticeWrench reaction = marker_reaction(markers, forcing.marker_force, centre);
    const LatticeWrench w = hydrodynamic_wrench(reaction, internal_before_, internal_after);
    const auto to_si = [&](const Eigen::Vector3d& force, const Eigen::Vector3d& torque) {
      body::Wrench si;
      for (int a = 0; a < 3; ++a) {
        si.force_si[a] = units_.force_si(force[a]);
        si.torque_si[a] = units_.torque_si(torque[a]);
      }
      return si;
    };
    last_.hydrodynamic = to_si(w.force, w.torque);
    last_.marker_reaction = to_si(reaction.force, reaction.torque);
    last_.internal_rate = to_si(internal_after.linear - internal_before_.linear, internal_after.angular - internal_before_.angular);
    internal_before_ = internal_after;
    last_.slip_max_si = units_.velocity_si(forcing.slip_max_after);
    last_.slip_rms_si = units_.velocity_si(forcing.slip_rms_after);
  }
  {
    ScopedTimer timer(timers_, "body_corrector");
    body_->correct(dt_si, last_.hydrodynamic);
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
  const SolidCells cells = current_solid_cells();
  for (std::size_t n = 0; n < cells.cell.size(); ++n) {
    const auto& c = cells.cell[n];
    sum -= cells.alpha[n] * fluid_->cell_velocity(c[0], c[1], c[2]);
  }
  Eigen::Vector3d mean = sum / static_cast<double>(fluid_->cell_count());
  for (int a = 0; a < 3; ++a) mean[a] = units_.velocity_si(mean[a]);
  return mean;
}

}  // namespace settle::coupling
