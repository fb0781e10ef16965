#pragma once
// The one interface behind which the body meets the fluid, so that the coupled step
// (coupling/simulation.hpp) has no branch on the method. Two implementations:
//  - ImmersedBoundaryCoupling (coupling/immersed_boundary_coupling.hpp): the diffuse interface,
//    surface markers with multi-direct forcing, the force from the marker reaction plus the rate
//    of change of the fluid momentum inside the body;
//  - MomentumExchangeCoupling (coupling/momentum_exchange.hpp): the sharp interface, the body's
//    cells solid, interpolated bounce-back on its true surface, the force from the momentum the
//    links exchange, and the cells the body uncovers refilled.
// Each step calls, in order: place, impose, the fluid step, measure; each coupling names the
// sub-steps its three calls are timed as (sub_step_names: the immersed boundary's "markers",
// "forcing", "hydrodynamic_force", the momentum exchange's "body_mapping", "refill",
// "hydrodynamic_force"). Lattice units throughout (docs/coupling.md, "Couplings").
#include <array>
#include <limits>
#include <memory>
#include <string>

#include <Eigen/Core>

#include "body/shape.hpp"
#include "coupling/lattice_body.hpp"
#include "ibm/delta.hpp"
#include "lbm/solver.hpp"
#include "parallel/communicator.hpp"

namespace settle::coupling {

/// Where the body is during the step and how its surface moves, lattice units: the pose at the
/// end of the step (the predictor's), the velocities of the step's start.
struct LatticePose {
  Eigen::Vector3d centre = Eigen::Vector3d::Zero();
  Eigen::Matrix3d body_to_inertial = Eigen::Matrix3d::Identity();
  Eigen::Vector3d velocity = Eigen::Vector3d::Zero();
  Eigen::Vector3d angular_velocity_n = Eigen::Vector3d::Zero();  ///< per time step, inertial frame
  /// Rigid-body velocity of the body-fixed point now at x.
  Eigen::Vector3d velocity_at(const Eigen::Vector3d& x) const {
    return velocity + angular_velocity_n.cross(x - centre);
  }
};

/// What a coupling measured over one fluid step: the fluid's force and torque on the body (about
/// its centre) and their two parts.
struct CouplingForces {
  LatticeWrench total;
  /// Immersed boundary: minus the marker forces. Momentum exchange: the sum over the links.
  LatticeWrench surface;
  /// Immersed boundary: the rate of change of the momentum of the fluid inside the body.
  /// Momentum exchange: zero (the inside is solid).
  LatticeWrench internal_rate;
  /// Immersed boundary: largest and rms no-slip error at the markers after forcing. Momentum
  /// exchange: zero (the bounce-back imposes the wall's velocity exactly).
  double slip_max = 0.0, slip_rms = 0.0;
};

/// The names under which the coupled step (Simulation::step) times a coupling's three calls: the
/// keys of summary.json's `timing`, the names of settle bench's `substeps` and of the run's closing
/// table. Each says what the call does under that coupling (docs/architecture.md, "The coupled time
/// step").
struct SubStepNames {
  const char* place;    ///< BodyCoupling::place
  const char* impose;   ///< BodyCoupling::impose
  const char* measure;  ///< BodyCoupling::measure
};
/// The names every coupling's calls were timed as before each coupling named its own (the
/// immersed boundary's words). summary.json repeats a renamed sub-step's time under its former
/// name for one release (deprecated; docs/user-guide.md, "summary.json"), and a checkpoint written
/// before the renaming has its times booked under the new names.
inline constexpr SubStepNames kFormerSubStepNames{"markers", "forcing", "hydrodynamic_force"};

/// Which coupling a case uses (numerics.coupling).
enum class CouplingKind { immersed_boundary, momentum_exchange };
/// The coupling of a case that names none; why this one: docs/coupling.md, "Couplings".
inline constexpr CouplingKind kDefaultCoupling = CouplingKind::momentum_exchange;
/// Whether the momentum exchange gives the body the angular momentum the covered cells' fluid
/// lacks (numerics.covered_cell_torque; docs/coupling.md, "The covered cells' spin").
inline constexpr bool kDefaultCoveredCellTorque = true;
std::string to_string(CouplingKind kind);
/// Throws settle::InputError naming `what` and the allowed names.
CouplingKind parse_coupling(const std::string& name, const std::string& what);

class BodyCoupling {
 public:
  virtual ~BodyCoupling() = default;
  virtual CouplingKind kind() const = 0;

  /// The box of cells the coupling reads or writes for the body at this pose; the grid must hold
  /// it (Simulation::can_step).
  virtual CellBox box_at(const Eigen::Vector3d& centre, const Eigen::Matrix3d& body_to_inertial) const = 0;
  /// Called once after the fluid is initialised, with the initial pose.
  virtual void start(lbm::Solver& fluid, const LatticePose& pose) = 0;
  /// The body's surface at this pose: markers, or solid cells and links.
  virtual void place(const lbm::Solver& fluid, const LatticePose& pose) = 0;
  /// Imposes the placed surface on the fluid for its next step.
  virtual void impose(lbm::Solver& fluid) = 0;
  /// The force and torque of the fluid step just taken.
  virtual CouplingForces measure(const lbm::Solver& fluid) = 0;

  /// True when fluid fills the body (the immersed boundary); false when its cells are solid.
  virtual bool fluid_inside() const = 0;
  /// Surface elements per step: markers, or links of the last placement.
  virtual std::size_t surface_element_count() const = 0;
  /// What surface_element_count counts, a plural noun for the console ("markers", "wall links").
  virtual const char* surface_element_name() const = 0;
  /// What the coupled step times place, impose and measure as.
  virtual SubStepNames sub_step_names() const = 0;
  /// What the coupling carries from one step to the next, for checkpoints: the immersed
  /// boundary's internal fluid momentum (linear, angular), the momentum exchange's previous link
  /// sum (force, torque).
  virtual std::array<double, 6> carried_state() const = 0;
  virtual void restore_carried_state(const std::array<double, 6>& state) = 0;
};

/// The numerical choices of a coupling, from the case: built by coupling_options (case_plan.hpp)
/// from a SimulationSetup, so the members carry no defaults of their own (coupling/setup.hpp).
struct CouplingOptions {
  CouplingKind kind{};
  // immersed boundary
  ibm::DeltaKernel kernel{};
  int forcing_iterations = 0;
  double marker_retraction_cells = std::numeric_limits<double>::quiet_NaN();
  bool interior_markers{};
  // momentum exchange
  lbm::WallRule wall_rule{};
  bool covered_cell_torque{};
  /// The body is placed once per this many lattice steps (SimulationSetup::lattice_steps_per_body_step).
  int lattice_steps_per_body_step = 0;
};

/// How far (cells) from the body's surface lie the cells the coupling `options` choose needs:
/// the delta kernel's half-width h for the immersed boundary (a marker's stencil; the markers lie
/// on or inside the surface), one cell for the momentum exchange (the fluid ends of its links). A
/// wall lies half a cell beyond the centre of the grid's last cell, so those cells stay inside the
/// grid while the body's gap to every wall is at least reach - 1/2 cells: the bound of the
/// wall-contact distance, whose default is the reach (contact_distance_cells, case_plan.hpp).
/// numerics.delta_kernel thus changes nothing under the momentum exchange.
double coupling_reach_cells(const CouplingOptions& options);

/// The box of cells the coupling `options` chooses works on for a body at `centre` (lattice units)
/// with this attitude: what its box_at returns, without building it.
CellBox coupling_box(const CouplingOptions& options, const body::Shape& shape, double dx_si,
                     const Eigen::Vector3d& centre, const Eigen::Matrix3d& body_to_inertial);

/// The coupling `options` choose. `communicator` holds the ranks of a split lattice (the momentum
/// exchange adds the blocks' parts through it; docs/parallel.md).
std::unique_ptr<BodyCoupling> make_coupling(std::shared_ptr<const body::Shape> shape, double dx_si,
                                            const CouplingOptions& options,
                                            parallel::Communicator& communicator = parallel::single_process());

}  // namespace settle::coupling
