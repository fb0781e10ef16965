#pragma once
// The diffuse coupling behind BodyCoupling (coupling/body_coupling.hpp): surface markers (and,
// as an option, a lattice of interior markers) placed at the predicted pose with the velocities
// of the step's start; multi-direct forcing (Luo et al. 2007; Breugem 2012) spread into the
// fluid's force array; the hydrodynamic force as minus the marker forces plus the rate of change
// of the momentum of the fluid inside the body (Kempe and Froehlich 2012), immersed_body.hpp.
#include <memory>
#include <optional>

#include "coupling/body_coupling.hpp"
#include "coupling/immersed_body.hpp"
#include "ibm/forcing.hpp"
#include "parallel/communicator.hpp"

namespace settle::coupling {

/// The cells the immersed boundary works on for a body at `centre` (lattice units) with this
/// attitude: the body's extent along each grid axis widened to every cell the delta kernel of a point
/// in it touches (ImmersedBoundaryCoupling::box_at, computed without building the coupling).
CellBox immersed_boundary_box(const body::Shape& shape, double dx_si, ibm::DeltaKernel kernel,
                              const Eigen::Vector3d& centre, const Eigen::Matrix3d& body_to_inertial);

class ImmersedBoundaryCoupling final : public BodyCoupling {
 public:
  /// On a split lattice every rank holds the same markers and forcing: each reads its block's part
  /// of the box, all receive the whole box (cell_states), run the same forcing on it and write
  /// the forces of their own cells (docs/parallel.md, "The immersed boundary across ranks").
  ImmersedBoundaryCoupling(std::shared_ptr<const body::Shape> shape, double dx_si, const CouplingOptions& options,
                           parallel::Communicator& communicator = parallel::single_process());

  CouplingKind kind() const override { return CouplingKind::immersed_boundary; }
  CellBox box_at(const Eigen::Vector3d& centre, const Eigen::Matrix3d& body_to_inertial) const override;
  void start(lbm::Solver& fluid, const LatticePose& pose) override;
  void place(const lbm::Solver& fluid, const LatticePose& pose) override;
  void impose(lbm::Solver& fluid) override;
  CouplingForces measure(const lbm::Solver& fluid) override;
  bool fluid_inside() const override { return true; }
  std::size_t surface_element_count() const override { return body_markers_.size(); }
  const char* surface_element_name() const override { return "markers"; }
  /// Placing the markers, multi-direct forcing, the marker reaction plus the inside's momentum.
  SubStepNames sub_step_names() const override { return {"markers", "forcing", "hydrodynamic_force"}; }
  std::array<double, 6> carried_state() const override;
  void restore_carried_state(const std::array<double, 6>& state) override;

 private:
  FluidMomentum internal_momentum_at(const lbm::Solver& fluid, const LatticePose& pose) const;
  SolidCells solid_cells_at(const LatticePose& pose, const CellBox& box) const;

  std::shared_ptr<const body::Shape> shape_;
  double dx_si_;
  CouplingOptions options_;
  parallel::Communicator& communicator_;
  BodyMarkers body_markers_;
  /// The shape's signed distance for the volume fractions, tabulated unless it is a closed form.
  std::optional<body::DistanceTable> distance_table_;
  // The step in progress: its pose, markers, box and forcing.
  LatticePose pose_;
  ibm::Markers markers_;
  CellBox box_;
  ibm::ForcingResult forcing_;
  /// The fluid momentum inside the body at the end of the previous step.
  FluidMomentum internal_before_;
};

}  // namespace settle::coupling
