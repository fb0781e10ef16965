#pragma once
// Multi-direct forcing of the immersed boundary on a box of cells around the body.
//
// Method: Luo, Wang, Fan and Cen 2007, Phys. Rev. E 76, 066709, doi:10.1103/PhysRevE.76.066709
// (multi-direct forcing in the lattice Boltzmann method) and Breugem 2012, J. Comput. Phys. 231,
// 4469-4498, doi:10.1016/j.jcp.2012.02.026 (the iteration as used here). Lattice units throughout
// (dx = dt = 1); points are in lattice coordinates with cell centres at integers.
//
// With Guo's second-order forcing the fluid velocity of a cell is u = (sum_i f_i c_i + F/2) / rho,
// so a force density F added to a cell changes its velocity by F / (2 rho) in the same step. The
// iteration below therefore corrects the velocity interpolated at the markers with
// dF = 2 rho (U_body - U) and updates the cell velocities by F / (2 rho) after each spreading.
#include <array>
#include <vector>

#include <Eigen/Core>

#include "ibm/delta.hpp"

namespace settle::ibm {

/// A block of cells copied out of the fluid grid: density, velocity before the immersed-boundary
/// force (but including every other force's half-step) and the accumulated force density.
/// Cell (i, j, k) of the box is grid cell origin + (i, j, k); the caller maps that to storage
/// (periodic wrap included) when it gathers and scatters.
class LocalGrid {
 public:
  LocalGrid(std::array<int, 3> origin, std::array<int, 3> extent);

  const std::array<int, 3>& origin() const { return origin_; }
  const std::array<int, 3>& extent() const { return extent_; }
  std::size_t cell_count() const { return rho.size(); }
  /// Linear index of box cell (i, j, k), i fastest.
  std::size_t index(int i, int j, int k) const {
    return static_cast<std::size_t>(i) + static_cast<std::size_t>(extent_[0]) *
                                             (static_cast<std::size_t>(j) + static_cast<std::size_t>(extent_[1]) * k);
  }
  /// True when the stencil lies completely inside the box.
  bool contains(const Stencil& stencil) const;

  std::vector<double> rho;
  std::array<std::vector<double>, 3> velocity;  ///< without the immersed-boundary force
  std::array<std::vector<double>, 3> force;     ///< immersed-boundary force density

 private:
  std::array<int, 3> origin_;
  std::array<int, 3> extent_;
};

/// Lagrangian markers in lattice units: position, the body's velocity there, and the marker's
/// volume (its surface area times one cell width, Uhlmann 2005 / Breugem 2012).
struct Markers {
  std::vector<Eigen::Vector3d> position;
  std::vector<Eigen::Vector3d> target_velocity;
  std::vector<double> volume;
  std::size_t size() const { return position.size(); }
};

struct ForcingOptions {
  DeltaKernel kernel = DeltaKernel::Roma3;
  int iterations = 3;  ///< multi-direct forcing sweeps; Breugem 2012 found 2-3 sufficient
};

/// What the forcing did, for the body's force balance and for reporting.
struct ForcingResult {
  /// Force density on the fluid at each marker (sum over iterations); the force the markers exert
  /// on the fluid is force[l] * volume[l].
  std::vector<Eigen::Vector3d> marker_force;
  /// Slip |U - U_body| at the markers, before the first and after the last sweep (max and rms).
  double slip_max_before = 0.0, slip_rms_before = 0.0;
  double slip_max_after = 0.0, slip_rms_after = 0.0;
};

/// Runs the multi-direct forcing sweeps: interpolates the velocity to the markers, adds the
/// force that would cancel the slip, spreads it and updates the box's velocity, `iterations`
/// times. The box's force field holds the total on return (it is added to, not cleared).
/// Every marker's stencil must lie inside the box (checked; throws std::logic_error).
ForcingResult multi_direct_forcing(LocalGrid& grid, const Markers& markers, const ForcingOptions& options);

/// Interpolates the current velocity u = u_before + F / (2 rho) of the box to a point.
Eigen::Vector3d interpolate_velocity(const LocalGrid& grid, const Stencil& stencil);

/// Adds force density `f` carried by a marker of volume `volume` to the box (force and
/// velocity), weighted by the stencil.
void spread_force(LocalGrid& grid, const Stencil& stencil, const Eigen::Vector3d& f, double volume);

}  // namespace settle::ibm
