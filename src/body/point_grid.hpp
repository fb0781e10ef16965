#pragma once
// A uniform grid over a fixed set of points for nearest-neighbour and radius queries, used to
// build and to measure surface markers. Cells are stored densely over the points' bounding box
// (compressed rows: one offset per cell), so a query costs a few array reads per cell.
#include <algorithm>
#include <cmath>
#include <cstdint>
#include <limits>
#include <vector>

#include <Eigen/Dense>

namespace settle::body {

class PointGrid {
 public:
  /// cell_size > 0; the grid is coarsened if the box would need more than ~16 million cells.
  PointGrid(const std::vector<Eigen::Vector3d>& points, double cell_size);

  /// Index of the nearest point to p accepted by `accept(index)`, excluding `exclude`; -1 if no
  /// point is accepted. Exact: the search grows shell by shell until no unsearched cell can
  /// hold a nearer point.
  template <class Accept>
  int nearest(const Eigen::Vector3d& p, Accept&& accept, int exclude = -1) const {
    if (points_.empty()) return -1;
    const Eigen::Vector3i c = cell_of(p);
    // Cells outside the grid are empty; shells beyond this one cannot reach any point.
    const int last_shell = ((c - dims_).cwiseMax(-c).cwiseMax(Eigen::Vector3i::Zero())).maxCoeff() + dims_.maxCoeff();
    int best = -1;
    double best_d2 = std::numeric_limits<double>::infinity();
    for (int shell = 0; shell <= last_shell; ++shell) {
      const Eigen::Vector3i lo = (c.array() - shell).max(0).matrix();
      const Eigen::Vector3i hi = (c.array() + shell).min((dims_.array() - 1)).matrix();
      for (int z = lo.z(); z <= hi.z(); ++z) {
        for (int y = lo.y(); y <= hi.y(); ++y) {
          // Only the cells on this shell's surface are new: in rows strictly inside the shell
          // in y and z, just the two end cells.
          const bool inner_row = std::abs(z - c.z()) < shell && std::abs(y - c.y()) < shell;
          const int step = inner_row ? 2 * shell : 1;
          for (int x = inner_row ? c.x() - shell : lo.x(); x <= hi.x(); x += step) {
            if (x < lo.x()) continue;
            const std::size_t cell = index_of(x, y, z);
            for (std::uint32_t k = start_[cell]; k < start_[cell + 1]; ++k) {
              const int i = static_cast<int>(members_[k]);
              if (i == exclude || !accept(i)) continue;
              const double d2 = (points_[i] - p).squaredNorm();
              if (d2 < best_d2) best_d2 = d2, best = i;
            }
          }
        }
      }
      // Unsearched cells lie more than shell * cell from p (p is inside the centre cell).
      if (best >= 0 && best_d2 <= (shell * cell_) * (shell * cell_)) break;
    }
    return best;
  }
  int nearest(const Eigen::Vector3d& p, int exclude = -1) const {
    return nearest(
        p, [](int) { return true; }, exclude);
  }

 private:
  Eigen::Vector3i cell_of(const Eigen::Vector3d& p) const {
    return ((p - origin_) / cell_).array().floor().cast<int>();
  }
  std::size_t index_of(int x, int y, int z) const {
    return (static_cast<std::size_t>(z) * static_cast<std::size_t>(dims_.y()) + static_cast<std::size_t>(y)) *
               static_cast<std::size_t>(dims_.x()) +
           static_cast<std::size_t>(x);
  }

  std::vector<Eigen::Vector3d> points_;
  double cell_ = 1.0;
  Eigen::Vector3d origin_ = Eigen::Vector3d::Zero();
  Eigen::Vector3i dims_ = Eigen::Vector3i::Ones();
  std::vector<std::uint32_t> start_;    ///< per cell (plus one): first entry in members_
  std::vector<std::uint32_t> members_;  ///< point indices grouped by cell
};

}  // namespace settle::body
