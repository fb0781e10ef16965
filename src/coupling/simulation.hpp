#pragma once
// The coupled simulation of one rigid particle in a lattice Boltzmann fluid, and its ONE time
// step (docs/architecture.md, "The coupled time step"). The step's sub-steps, in order, each
// timed under its name:
//
//  1. body_predictor     pose at t + dt from the current velocities (RigidBody::predict_pose)
//  2. place              the body's surface at that pose, moving with the body's current
//                        velocity (BodyCoupling::place, coupling/body_coupling.hpp): the
//                        immersed boundary's "markers", the momentum exchange's "body_mapping"
//                        (solid cells and wall links with their fractions q)
//  3. impose             imposing it on the fluid (BodyCoupling::impose): the immersed
//                        boundary's "forcing", multi-direct forcing into the force array (Luo et
//                        al. 2007; Breugem 2012); the momentum exchange's "refill" of the cells
//                        the body uncovers, and its new walls
//     fluid              collide (Guo forcing, second order) and stream; walls inside the grid
//                        closed by interpolated bounce-back
//  4. hydrodynamic_force (BodyCoupling::measure) minus the marker forces plus the rate of change
//                        of the fluid momentum inside the body (Kempe and Froehlich 2012), or the
//                        momentum the wall links exchanged (Wen et al. 2014)
//  5. body_corrector     Newton-Euler with that wrench, gravity and buoyancy (RigidBody::correct)
//                        (a free body held before its release keeps its initial velocities),
//                        stabilised for light bodies by a virtual mass and inertia (below), plus the
//                        particle-wall contact force, sub-stepped, when the body is near a wall
//                        (body::WallContact; docs/rigid-body.md)
//  6. moving_window      shift the fluid one cell when the body is a cell off its starting place
//
// With SimulationSetup::lattice_steps_per_body_step = 2 (momentum exchange only) a body step spans
// two lattice steps: sub-steps 1-2 run at the first (the pose predicted two lattice steps ahead),
// 3-4 at both (the walls held), 5-6 at the second, with the wrench of the pair (coupling/
// momentum_exchange.hpp).
//
// Sub-steps 2-4 are timed under the names the coupling gives them (BodyCoupling::sub_step_names).
//
// Coupling choices written down here: the body's surface moves with the velocities of the step's start
// (explicit in the body velocity, as Uhlmann 2005 and Breugem 2012); the wrench measured at the
// predicted pose is held constant over the step by the corrector. That explicit coupling is
// unstable when the fluid's response within one step outweighs the body's inertia (light, sharp-
// edged bodies at coarse resolution: docs/coupling.md, "Stability of light bodies"), so the
// corrector adds a virtual mass 0.5 rho_f V and a virtual inertia (rho_f / rho_p) I to both sides
// of Newton-Euler, with the previous step's accelerations on the right (Schwarz, Kempe and
// Froehlich 2015, J. Comput. Phys. 281, 591; body::VirtualInertia): an approximation that leaves
// steady motion unchanged and acts on transients only. Lattice Boltzmann has no gravity in the
// fluid: hydrostatic pressure is absent, so buoyancy enters the body explicitly
// (RigidBody's net weight), and a body force on the fluid stands for a mean pressure gradient.
// Output (step 7) is the runner's business (coupling/runner.hpp), on its own schedule.
#include <array>
#include <chrono>
#include <limits>
#include <memory>
#include <optional>
#include <string>
#include <utility>
#include <vector>

#include <Eigen/Core>

#include "body/contact.hpp"
#include "body/rigid_body.hpp"
#include "body/shape.hpp"
#include "coupling/body_coupling.hpp"
#include "coupling/case_plan.hpp"
#include "coupling/immersed_body.hpp"
#include "coupling/setup.hpp"
#include "coupling/units.hpp"
#include "ibm/delta.hpp"
#include "lbm/config.hpp"
#include "lbm/solver.hpp"
#include "parallel/communicator.hpp"

namespace settle::coupling {

/// What building the simulation adds to its plan (Simulation::plan(): units, dimensionless groups,
/// steps): the grid as allocated and the body's surface elements.
struct DerivedQuantities {
  std::array<int, 3> cells{};
  /// BodyCoupling::surface_element_count at the start: markers, or wall links
  std::size_t surface_element_count = 0;
};

/// Wall-clock seconds spent in each named sub-step, in step order.
class SubstepTimers {
 public:
  void add(const char* name, double seconds);
  const std::vector<std::pair<std::string, double>>& entries() const { return entries_; }
  double total() const;

 private:
  std::vector<std::pair<std::string, double>> entries_;
};

/// What one step measured, in SI (inertial frame; torque about the centre of mass).
struct StepObservation {
  body::Wrench hydrodynamic;  ///< the sum of the two parts below
  /// The surface's part (CouplingForces::surface): minus the sum of the marker forces (and their
  /// moments), or the momentum the wall links exchanged
  body::Wrench surface;
  body::Wrench internal_rate;  ///< rate of change of the momentum of the fluid inside the body
  double slip_max_si = 0.0;    ///< largest |U - U_body| at the markers after forcing, m/s
  double slip_rms_si = 0.0;
  /// Particle-wall contact: impulse and angular impulse of the step divided by dt (zero away from
  /// walls); the body corrector received hydrodynamic + contact.
  body::Wrench contact;
  /// Smallest gap between the body and a wall during the step's corrector, m (infinity without
  /// contact walls).
  double wall_gap_si = std::numeric_limits<double>::infinity();
};

class Simulation {
  /// coupling/checkpoint_state.cpp: gathers the private state into a checkpoint and restores it.
  friend struct CheckpointAccess;

 public:
  /// Converts units and checks the case before allocating anything (settle::InputError naming
  /// the key to change); then builds the fluid, the body and its coupling. With a communicator of
  /// more than one rank, this rank holds one block of the lattice (lbm::choose_split) and the body
  /// is coupled across the blocks (either coupling; docs/parallel.md): every rank steps
  /// together and holds the same body state.
  explicit Simulation(SimulationSetup setup, parallel::Communicator& communicator = parallel::single_process());

  /// One coupled time step (file comment).
  void step();
  /// False when the next step's forcing stencil would leave the grid (body at a wall).
  bool can_step() const;
  /// True unless a body step spanning two lattice steps (SimulationSetup::lattice_steps_per_body_step)
  /// is half done: the only states a checkpoint may hold.
  bool between_body_steps() const;
  /// The body's time step: lattice_steps_per_body_step lattice steps.
  double body_step_dt_si() const;

  const SimulationSetup& setup() const { return setup_; }
  const DerivedQuantities& derived() const { return derived_; }
  const CasePlan& plan() const { return plan_; }
  const UnitConverter& units() const { return plan_.units; }
  const body::RigidBody& body() const { return *body_; }
  /// The particle-wall contact model; empty without contact walls (setup().wall_contact off, all
  /// axes periodic, a following window, or a towed or fixed body).
  const std::optional<body::WallContact>& wall_contact() const { return contact_; }
  const lbm::Solver& fluid() const { return *fluid_; }
  lbm::Solver& fluid() { return *fluid_; }
  const SubstepTimers& timers() const { return timers_; }
  const StepObservation& last_step() const { return last_; }
  const LatticeFrame& frame() const { return frame_; }
  std::int64_t steps() const { return steps_; }
  /// True while a free body is held before its release (SimulationSetup::release_time_si): the
  /// next step moves it with its initial velocities, the fluid forms its wake around it.
  bool held() const { return steps_ < plan_.release_step; }
  /// True while the next step still sets the body's prescribed velocities: ramps them up from
  /// rest (SimulationSetup::hold_ramp_time_si; a held free body's or a towed body's), or, for a
  /// towed body with SimulationSetup::towed_velocity_si, at every step.
  bool ramping() const;

  /// Mean fluid velocity over the whole domain with the solid counted as zero (the superficial
  /// velocity of Zick and Homsy 1982), m/s. Sweeps the whole grid: for outputs, not every step.
  Eigen::Vector3d superficial_velocity_si() const;
  /// The extremes of the whole lattice's density and speed (every rank's block, cells in whole-
  /// lattice coordinates, the same on every rank): what the health check needs.
  lbm::FieldExtrema fluid_extrema() const;
  /// The ranks this simulation runs on (one, unless the lattice is split).
  parallel::Communicator& communicator() const { return communicator_; }
  /// The whole lattice's cell count (the fluid() of a split run holds one block).
  double lattice_cell_count() const { return plan_.cell_count(); }
  /// The solid cells of the body at its current pose (lattice units).
  SolidCells current_solid_cells() const;
  const BodyCoupling& coupling() const { return *coupling_; }

 private:
  CellBox box_at(const Eigen::Vector3d& centre, const Eigen::Matrix3d& body_to_inertial) const;
  LatticePose lattice_pose(const body::Pose& pose) const;
  Eigen::Vector3d lattice_velocity(const Eigen::Vector3d& velocity_si) const;
  lbm::SolverConfig fluid_config() const;
  void follow_body();
  /// Sub-steps 1-2: predicts the pose at the end of the body step and places the walls there.
  void place_body();
  /// Sub-step 5 over one body step ending at end_time_si, with the last measured wrench.
  void move_body(double end_time_si);

  SimulationSetup setup_;
  parallel::Communicator& communicator_;
  CasePlan plan_;
  DerivedQuantities derived_;
  LatticeFrame frame_;
  std::unique_ptr<lbm::Solver> fluid_;
  std::unique_ptr<body::RigidBody> body_;
  std::unique_ptr<BodyCoupling> coupling_;
  /// The particle-wall contact model, when the case has contact walls (its state between steps,
  /// the impact speeds of contacts in progress, is checkpointed).
  std::optional<body::WallContact> contact_;
  /// Where the moving window holds the body (lattice coordinates): its starting place, so the
  /// case chooses how much fluid lies ahead of the body and how much wake behind it.
  Eigen::Vector3d window_anchor_ = Eigen::Vector3d::Zero();
  /// The corrector's virtual mass and inertia (zero unless the body is free) with the last step's
  /// accelerations as the estimate for the next (docs/coupling.md, "Stability of light bodies").
  body::VirtualInertia virtual_inertia_;
  SubstepTimers timers_;
  StepObservation last_;
  std::int64_t steps_ = 0;
};

}  // namespace settle::coupling
