#include "coupling/immersed_boundary_coupling.hpp"

#include <cmath>
#include <utility>

namespace settle::coupling {

ImmersedBoundaryCoupling::ImmersedBoundaryCoupling(std::shared_ptr<const body::Shape> shape, double dx_si,
                                                   const CouplingOptions& options, parallel::Communicator& communicator)
    : shape_(std::move(shape)),
      dx_si_(dx_si),
      options_(options),
      communicator_(communicator),
      body_markers_(make_body_markers(*shape_, dx_si_, options.marker_retraction_cells, options.interior_markers)) {
  // A quarter cell: the trilinear interpolation then errs by at most (3/8) (dx/4)^2 times the
  // largest curvature of the distance's level sets, 0.03 cells where the surface curves with a
  // radius of 1.6 cells (docs/coupling.md, "Volume fractions"). Exact within 2.5 cells of the
  // surface: the corners of cut cells lie within sqrt(3) cells of it and their interpolation
  // nodes within another sqrt(3)/4; the margin keeps every such corner inside the table.
  if (!shape_->signed_distance_is_closed_form())
    distance_table_.emplace(shape_, 0.25 * dx_si_, 2.5 * dx_si_, 2.5 * dx_si_);
}

SolidCells ImmersedBoundaryCoupling::solid_cells_at(const LatticePose& pose, const CellBox& box) const {
  if (distance_table_) return solid_cells(*distance_table_, dx_si_, box, pose.centre, pose.body_to_inertial);
  return solid_cells(*shape_, dx_si_, box, pose.centre, pose.body_to_inertial);
}

CellBox immersed_boundary_box(const body::Shape& shape, double dx_si, ibm::DeltaKernel kernel,
                              const Eigen::Vector3d& centre, const Eigen::Matrix3d& body_to_inertial) {
  // The body's extent along each grid axis at this attitude (support function, lattice units),
  // widened to every cell that the delta kernel of a point within that extent touches (first cell
  // floor(x - h) + 1, `width` cells: ibm::axis_stencil). Markers lie on or inside the surface, so
  // this holds their stencils, and every cell the body overlaps (the volume fractions). Tighter than
  // the bounding sphere, so a tilted or flat body can come as close to a wall as its stencils allow.
  const double h = ibm::support_half_width(kernel);
  const int width = ibm::stencil_width(kernel);
  CellBox box;
  for (int a = 0; a < 3; ++a) {
    const Eigen::Vector3d axis_b = body_to_inertial.row(a).transpose();
    const double lower = centre[a] - shape.support(-axis_b) / dx_si;
    const double upper = centre[a] + shape.support(axis_b) / dx_si;
    const int first = static_cast<int>(std::floor(lower - h)) + 1;
    const int last = static_cast<int>(std::floor(upper - h)) + width;
    box.origin[static_cast<std::size_t>(a)] = first;
    box.extent[static_cast<std::size_t>(a)] = last - first + 1;
  }
  return box;
}

CellBox ImmersedBoundaryCoupling::box_at(const Eigen::Vector3d& centre, const Eigen::Matrix3d& body_to_inertial) const {
  return immersed_boundary_box(*shape_, dx_si_, options_.kernel, centre, body_to_inertial);
}

FluidMomentum ImmersedBoundaryCoupling::internal_momentum_at(const lbm::Solver& fluid, const LatticePose& pose) const {
  const CellBox box = box_at(pose.centre, pose.body_to_inertial);
  return internal_momentum(fluid, solid_cells_at(pose, box), pose.centre, communicator_);
}

void ImmersedBoundaryCoupling::start(lbm::Solver& fluid, const LatticePose& pose) {
  internal_before_ = internal_momentum_at(fluid, pose);
}

void ImmersedBoundaryCoupling::place(const lbm::Solver&, const LatticePose& pose) {
  pose_ = pose;
  markers_ = place_markers(body_markers_, pose.centre, pose.body_to_inertial, pose.velocity, pose.angular_velocity_n);
  box_ = box_at(pose.centre, pose.body_to_inertial);
}

void ImmersedBoundaryCoupling::impose(lbm::Solver& fluid) {
  fluid.clear_forces();
  ibm::LocalGrid grid = gather(fluid, box_, communicator_);
  forcing_ = ibm::multi_direct_forcing(grid, markers_, {options_.kernel, options_.forcing_iterations});
  scatter_forces(fluid, grid);
}

CouplingForces ImmersedBoundaryCoupling::measure(const lbm::Solver& fluid) {
  const FluidMomentum internal_after =
      internal_momentum(fluid, solid_cells_at(pose_, box_), pose_.centre, communicator_);
  CouplingForces f;
  f.surface = marker_reaction(markers_, forcing_.marker_force, pose_.centre);
  f.total = hydrodynamic_wrench(f.surface, internal_before_, internal_after);
  f.internal_rate = {internal_after.linear - internal_before_.linear,
                     internal_after.angular - internal_before_.angular};
  f.slip_max = forcing_.slip_max_after;
  f.slip_rms = forcing_.slip_rms_after;
  internal_before_ = internal_after;
  return f;
}

std::array<double, 6> ImmersedBoundaryCoupling::carried_state() const {
  const auto& p = internal_before_;
  return {p.linear.x(), p.linear.y(), p.linear.z(), p.angular.x(), p.angular.y(), p.angular.z()};
}

void ImmersedBoundaryCoupling::restore_carried_state(const std::array<double, 6>& s) {
  internal_before_.linear = Eigen::Vector3d(s[0], s[1], s[2]);
  internal_before_.angular = Eigen::Vector3d(s[3], s[4], s[5]);
}

}  // namespace settle::coupling
