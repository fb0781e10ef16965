#pragma once
// The immersed-boundary side of one body, in lattice units (dx = dt = 1, fluid density 1):
// its surface markers at a pose, the transfer of a box of cells to and from the fluid solver,
// the solid volume fraction of each cell, and the two terms of the hydrodynamic force and torque.
//
// Lattice coordinates and the box of cells: coupling/lattice_body.hpp (cell (i, j, k) centred at
// the integer point (i, j, k), as ibm/forcing.hpp has it). The body frame is the shape's own
// (body/shape.hpp), mapped to the inertial frame by C_b^n.
//
// Hydrodynamic force and torque (Uhlmann 2005, J. Comput. Phys. 209, 448,
// doi:10.1016/j.jcp.2005.03.017; Kempe and Froehlich 2012, J. Comput. Phys. 231, 3663,
// doi:10.1016/j.jcp.2012.01.021, eqs. 16-17 and 29):
//   F_h = - sum_l f_l dV_l + d/dt sum_cells alpha rho u dV
//   T_h = - sum_l (X_l - X_c) x f_l dV_l + d/dt sum_cells alpha (x - X_c) x rho u dV
// where f_l is the force density the marker exerts on the fluid, dV_l its volume and alpha the
// solid volume fraction of a cell. The second terms are the rate of change of the momentum of
// the fluid inside the body; they replace the rigid-body approximation (which assumes that
// fluid moves rigidly with the body and fails below a density ratio of about 1.2).
#include <array>
#include <vector>

#include <Eigen/Core>

#include "body/distance_table.hpp"
#include "body/shape.hpp"
#include "coupling/lattice_body.hpp"
#include "ibm/forcing.hpp"
#include "lbm/solver.hpp"
#include "parallel/communicator.hpp"

namespace settle::coupling {

/// The body's markers in its own frame, lattice units: offsets from the centroid and volumes
/// (area times one cell). Built once; placed at every pose by place_markers().
struct BodyMarkers {
  std::vector<Eigen::Vector3d> offset_b;
  std::vector<double> volume;
  std::size_t size() const { return offset_b.size(); }
};

/// Markers of nominal spacing one cell from the shape (SI) moved inwards along their normals by
/// `retraction_cells` (Breugem 2012, J. Comput. Phys. 231, 4469, doi:10.1016/j.jcp.2012.02.026:
/// r_d = 0.3 dx makes the diffuse interface's effective size match the nominal one). The
/// marker areas are scaled by (1 - r_d / R_eq)^2 with R_eq the volume-equivalent radius in cells,
/// so that they tile the retracted surface; exact for a sphere, an approximation of the local
/// curvature for other shapes.
/// With `interior`, also a body-fixed lattice of one-cell spacing inside the body (volume one cell
/// each), at least one cell below the surface markers: it holds the enclosed fluid to the rigid
/// motion (docs/coupling.md, Interior markers).
BodyMarkers make_body_markers(const body::Shape& shape, double dx_si, double retraction_cells, bool interior = false);

/// The retraction r_d (cells) calibrated on the Stokes drag of a periodic sphere array at 16 cells
/// per diameter (Zick-Homsy / Sangani-Acrivos, tests/coupling/test_periodic_sphere.cpp): 0.4 with
/// surface markers only (K +0.14%), 0.5 with interior markers (+0.26%), whose rigid interior widens
/// the diffuse body by about a tenth of a cell more (docs/coupling.md, Interior markers).
constexpr double calibrated_marker_retraction_cells(bool interior) { return interior ? 0.5 : 0.4; }

/// Depth (cells below the surface) from which the interior lattice fills the body: one cell below
/// the retracted surface markers; nearer, the sheet's and the lattice's kernels would overlap so
/// much that a Jacobi sweep overshoots. Shared with the preflight's marker estimate.
constexpr double interior_lattice_depth_cells(double retraction_cells) { return retraction_cells + 1.0; }

/// Markers at a pose (lattice units): X_l = X_c + C_b^n p_l, target velocity v + omega_n x (X_l - X_c).
ibm::Markers place_markers(const BodyMarkers& markers, const Eigen::Vector3d& centre,
                           const Eigen::Matrix3d& body_to_inertial, const Eigen::Vector3d& velocity,
                           const Eigen::Vector3d& angular_velocity_n);

/// Density and velocity (with every force present in the solver, Guo half-step included) of
/// `cells` (whole-lattice coordinates; periodic axes wrap), in list order. On a split lattice every
/// rank calls it with the same list: each reads the cells of its block, and all receive all
/// (docs/parallel.md, "The immersed boundary across ranks"), so every rank holds the same values
/// as one process would.
std::vector<lbm::CellState> cell_states(const lbm::Solver& solver, const std::vector<std::array<int, 3>>& cells,
                                        parallel::Communicator& ranks = parallel::single_process());
/// The box's cells in box order (x fastest), whole-lattice coordinates, unwrapped.
std::vector<std::array<int, 3>> cells_of(const CellBox& box);
/// Copies the box's cells out of the solver (cell_states): the whole box on every rank.
ibm::LocalGrid gather(const lbm::Solver& solver, const CellBox& box,
                      parallel::Communicator& ranks = parallel::single_process());
/// Writes the box's non-zero force density into the solver (set_force; call clear_forces first);
/// a block of a split lattice takes its own cells' forces.
void scatter_forces(lbm::Solver& solver, const ibm::LocalGrid& grid);

/// Solid volume fraction of the cells of a box, for the shape at a pose (lattice units), from
/// the signed distance at the eight corners of each cell (Kempe and Froehlich 2012, eq. 29).
/// Only the corners of cells the surface cuts get a signed distance; the others need only the
/// inside test. Cells are listed in box order (deterministic).
struct SolidCells {
  std::vector<std::array<int, 3>> cell;  ///< grid cell (unwrapped) of each entry
  std::vector<double> alpha;             ///< in (0, 1]
  double volume() const;                 ///< sum of alpha, cells
};
SolidCells solid_cells(const body::Shape& shape, double dx_si, const CellBox& box, const Eigen::Vector3d& centre,
                       const Eigen::Matrix3d& body_to_inertial);
/// The same with the corners' signed distances interpolated from a table of the shape (the
/// inside test stays exact, and gives each corner's sign).
SolidCells solid_cells(const body::DistanceTable& table, double dx_si, const CellBox& box,
                       const Eigen::Vector3d& centre, const Eigen::Matrix3d& body_to_inertial);

/// Momentum and angular momentum (about `centre`) of the fluid inside the body, lattice units:
/// sum alpha rho u and sum alpha (x - X_c) x rho u over the solid cells.
struct FluidMomentum {
  Eigen::Vector3d linear = Eigen::Vector3d::Zero();
  Eigen::Vector3d angular = Eigen::Vector3d::Zero();
};
FluidMomentum internal_momentum(const lbm::Solver& solver, const SolidCells& cells, const Eigen::Vector3d& centre,
                                parallel::Communicator& ranks = parallel::single_process());

/// Force and torque (about `centre`) that the fluid exerts on the markers, lattice units: minus
/// the sum of the marker forces on the fluid.
LatticeWrench marker_reaction(const ibm::Markers& markers, const std::vector<Eigen::Vector3d>& marker_force,
                              const Eigen::Vector3d& centre);

/// The hydrodynamic wrench of the file comment: marker reaction plus the rate of change of the
/// internal momentum over one step (dt = 1).
LatticeWrench hydrodynamic_wrench(const LatticeWrench& marker_reaction, const FluidMomentum& before,
                                  const FluidMomentum& after);

}  // namespace settle::coupling
