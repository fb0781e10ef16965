#pragma once
// A shape's signed distance tabulated once on a body-fixed grid and interpolated trilinearly: what
// the immersed boundary's volume fractions need at the corners of every cell the surface cuts, at
// every step, for a fraction of the cost of the exact distance (the closest point of an ellipsoid
// is a root search, of a mesh a tree walk). docs/coupling.md, "Volume fractions", states the error.
// The momentum exchange asks it which side of a mesh's surface a cell lies on (certain_side).
#include <array>
#include <memory>
#include <numbers>
#include <vector>

#include <Eigen/Dense>

#include "body/shape.hpp"

namespace settle::body {

class DistanceTable {
 public:
  /// Tabulates `shape` at spacing `spacing` (a fraction of a lattice cell) over its bounding box
  /// widened by `margin` on every side; the spacing grows where the box would need more than
  /// kMaxNodes nodes. Exact values are computed only at nodes within `band` of the surface (a
  /// coarse pass finds them); farther nodes hold the coarse pass's value, and queries there are
  /// not what the table is for.
  DistanceTable(std::shared_ptr<const Shape> shape, double spacing, double margin, double band);

  /// Signed distance (negative inside) at a body-frame point: interpolated inside the table, exact
  /// beyond it.
  double signed_distance(const Eigen::Vector3d& p) const;
  /// The side of the surface a body-frame point lies on, where the table alone settles it: -1
  /// inside, +1 outside, 0 too near the surface to tell (ask the shape). Beyond the table (the
  /// bounding box and the margin) outside. Settled where the interpolated distance exceeds
  /// kCertainSpacings spacings, the interpolation's worst error sqrt(3) / 2 (.cpp); exact for shapes whose
  /// signed distance is exact to 1e-4 spacings (a mesh: to round-off), in a table whose band is at
  /// least 2 sqrt(3) spacings (otherwise always 0).
  int certain_side(const Eigen::Vector3d& p) const;
  static constexpr double kCertainSpacings = 0.5 * std::numbers::sqrt3 + 1e-4;  // and the nodes' error

  const Shape& shape() const { return *shape_; }
  double spacing() const { return spacing_; }
  std::size_t node_count() const { return values_.size(); }
  /// Nodes whose exact distance was computed (the coarse pass and the band).
  std::size_t exact_node_count() const { return exact_nodes_; }

  static constexpr std::size_t kMaxNodes = std::size_t{1} << 24;  // 64 MiB of float

 private:
  std::size_t node(int i, int j, int k) const {
    return static_cast<std::size_t>(i) +
           static_cast<std::size_t>(count_[0]) *
               (static_cast<std::size_t>(j) + static_cast<std::size_t>(count_[1]) * static_cast<std::size_t>(k));
  }
  Eigen::Vector3d node_point(int i, int j, int k) const { return lower_ + spacing_ * Eigen::Vector3d(i, j, k); }
  void fill(double band);

  std::shared_ptr<const Shape> shape_;
  double spacing_ = 0.0;
  Eigen::Vector3d lower_ = Eigen::Vector3d::Zero();
  std::array<int, 3> count_{};
  std::vector<float> values_;
  std::size_t exact_nodes_ = 0;
  double band_ = 0.0;
};

}  // namespace settle::body
