#include "body/distance_table.hpp"

#include <algorithm>
#include <cmath>
#include <stdexcept>

namespace settle::body {
namespace {

// The coarse pass evaluates every kCoarse-th node along each axis.
constexpr int kCoarse = 4;

// Trilinear interpolation of the eight values v[a + 2 b + 4 c] of a unit cube at fractions t.
double trilinear(const double (&v)[8], const Eigen::Vector3d& t) {
  const auto lerp = [](double a, double b, double s) { return a + s * (b - a); };
  const double x00 = lerp(v[0], v[1], t.x()), x10 = lerp(v[2], v[3], t.x());
  const double x01 = lerp(v[4], v[5], t.x()), x11 = lerp(v[6], v[7], t.x());
  return lerp(lerp(x00, x10, t.y()), lerp(x01, x11, t.y()), t.z());
}

}  // namespace

DistanceTable::DistanceTable(std::shared_ptr<const Shape> shape, double spacing, double margin, double band)
    : shape_(std::move(shape)), spacing_(spacing), band_(band) {
  if (!shape_) throw std::invalid_argument("DistanceTable: no shape");
  if (!(spacing > 0.0) || !(margin >= 0.0) || !(band > 0.0))
    throw std::invalid_argument("DistanceTable: spacing and band must be > 0, margin >= 0");
  const Aabb box = shape_->bounding_box();
  lower_ = box.lower - Eigen::Vector3d::Constant(margin);
  const Eigen::Vector3d extent = box.upper - box.lower + Eigen::Vector3d::Constant(2.0 * margin);
  // Node counts 1 + a multiple of kCoarse, so that the coarse nodes end on the last fine one.
  const auto counts_at = [&](double h) {
    std::array<int, 3> n{};
    for (int a = 0; a < 3; ++a) {
      const int cells = static_cast<int>(std::ceil(extent[a] / h / kCoarse)) * kCoarse;
      n[static_cast<std::size_t>(a)] = cells + 1;
    }
    return n;
  };
  const auto total = [](const std::array<int, 3>& n) {
    return static_cast<std::size_t>(n[0]) * static_cast<std::size_t>(n[1]) * static_cast<std::size_t>(n[2]);
  };
  count_ = counts_at(spacing_);
  while (total(count_) > kMaxNodes) {
    spacing_ *= 1.25;
    count_ = counts_at(spacing_);
  }
  values_.assign(total(count_), 0.0f);
  fill(band);
}

// Exact values at the coarse nodes; a fine node gets the exact value where the coarse
// interpolation puts it within band + sqrt(3) * coarse spacing of the surface (the distance is
// 1-Lipschitz and the interpolation a convex combination of values at nodes that close, so every
// node truly within `band` is among them), the coarse interpolation elsewhere.
void DistanceTable::fill(double band) {
  for (int k = 0; k < count_[2]; k += kCoarse)
    for (int j = 0; j < count_[1]; j += kCoarse)
      for (int i = 0; i < count_[0]; i += kCoarse) {
        values_[node(i, j, k)] = static_cast<float>(shape_->signed_distance(node_point(i, j, k)));
        ++exact_nodes_;
      }
  const double reach = band + std::sqrt(3.0) * kCoarse * spacing_;
  for (int k = 0; k < count_[2]; ++k)
    for (int j = 0; j < count_[1]; ++j)
      for (int i = 0; i < count_[0]; ++i) {
        if (i % kCoarse == 0 && j % kCoarse == 0 && k % kCoarse == 0) continue;
        const std::array<int, 3> c{std::min(i / kCoarse * kCoarse, count_[0] - 1 - kCoarse),
                                   std::min(j / kCoarse * kCoarse, count_[1] - 1 - kCoarse),
                                   std::min(k / kCoarse * kCoarse, count_[2] - 1 - kCoarse)};
        double v[8];
        for (int m = 0; m < 8; ++m)
          v[m] =
              values_[node(c[0] + kCoarse * (m & 1), c[1] + kCoarse * ((m >> 1) & 1), c[2] + kCoarse * ((m >> 2) & 1))];
        const Eigen::Vector3d t = Eigen::Vector3d(i - c[0], j - c[1], k - c[2]) / kCoarse;
        const double coarse = trilinear(v, t);
        if (std::abs(coarse) < reach) {
          values_[node(i, j, k)] = static_cast<float>(shape_->signed_distance(node_point(i, j, k)));
          ++exact_nodes_;
        } else {
          values_[node(i, j, k)] = static_cast<float>(coarse);
        }
      }
}

// Why the threshold settles the side. A node holds the exact distance d(n) (to 1e-4 spacings h:
// the shape's round-off and the float's 2^-24 of values of a few h), or, farther than the band from
// the surface, the coarse interpolation (fill): of the right sign there. Trilinear interpolation is
// a convex combination of the cell's eight nodes n_k with weights w_k, and d is 1-Lipschitz, so if
// all eight are exact |interpolated - d(p)| <= sum_k w_k |n_k - p| + 1e-4 h; that weighted sum is
// largest at the cell's centre, h sqrt(3) / 2 (in one dimension 2 t (1 - t) h <= h / 2; checked on
// a grid of the cell in tests/body/test_distance_table.cpp): beyond the threshold the sign is
// d(p)'s. If a node is coarse, d there is at least the band >= 2 sqrt(3) h, so d keeps its sign
// within h sqrt(3) of it: at p and at every node of the cell, whose values all share it, and so
// does the interpolation.
int DistanceTable::certain_side(const Eigen::Vector3d& p) const {
  const Eigen::Vector3d t = (p - lower_) / spacing_;
  for (int a = 0; a < 3; ++a) {
    if (!(t[a] >= 0.0 && t[a] <= count_[static_cast<std::size_t>(a)] - 1)) return 1;
  }
  if (band_ < 2.0 * std::sqrt(3.0) * spacing_) return 0;
  const double interpolated = signed_distance(p);
  if (interpolated > kCertainSpacings * spacing_) return 1;
  if (interpolated < -kCertainSpacings * spacing_) return -1;
  return 0;
}

double DistanceTable::signed_distance(const Eigen::Vector3d& p) const {
  const Eigen::Vector3d t = (p - lower_) / spacing_;
  std::array<int, 3> c{};
  for (int a = 0; a < 3; ++a) {
    const double f = std::floor(t[a]);
    if (!(f >= 0.0) || f >= count_[static_cast<std::size_t>(a)] - 1) return shape_->signed_distance(p);
    c[static_cast<std::size_t>(a)] = static_cast<int>(f);
  }
  double v[8];
  for (int m = 0; m < 8; ++m) v[m] = values_[node(c[0] + (m & 1), c[1] + ((m >> 1) & 1), c[2] + ((m >> 2) & 1))];
  return trilinear(v, t - Eigen::Vector3d(c[0], c[1], c[2]));
}

}  // namespace settle::body
