// The tabulated signed distance (body::DistanceTable) against the exact one, for the default case's
// prolate spheroid (aspect ratio 2) at its 8 cells per equivalent diameter, with the coupling's
// quarter-cell spacing.
#include <cmath>
#include <memory>
#include <random>

#include <gtest/gtest.h>

#include "body/distance_table.hpp"
#include "body/ellipsoid.hpp"

namespace settle::body {
namespace test_distance_table {

constexpr double kDx = 1.26e-3 / 8.0;    // m: d_eq / 8
constexpr double kSpacing = 0.25 * kDx;  // the immersed boundary's table
constexpr double kRadiusMin = 0.25e-3;   // m: smallest radius of curvature, a^2 / c at the tips
// Stored as float: values up to a few cells carry a rounding of 2^-24 of them.
constexpr double kFloatRounding = 1e-6 * kDx;

// The signed distance to a convex body is convex (a maximum of affine functions of the point), so
// trilinear interpolation never falls below it, and exceeds it by at most h^2 / 8 times the trace of
// its Hessian, sum_i k_i / (1 + k_i phi) over the principal curvatures k_i <= 1 / R: 2 / R outside,
// 4 / R down to a depth R / 2 (a corner deeper than R / 2 - h sqrt(3) keeps its interpolation cell
// above that depth).
TEST(DistanceTable, InterpolationLiesAboveTheExactDistanceWithinTheTrilinearBound) {
  const auto shape = std::make_shared<const Ellipsoid>(Ellipsoid::spheroid(1.0e-3, 2.0));
  const DistanceTable table(shape, kSpacing, 2.5 * kDx, 2.5 * kDx);
  EXPECT_DOUBLE_EQ(table.spacing(), kSpacing);
  const double outside_bound = kSpacing * kSpacing / 8.0 * 2.0 / kRadiusMin + kFloatRounding;
  const double shallow_bound = kSpacing * kSpacing / 8.0 * 4.0 / kRadiusMin + kFloatRounding;
  std::mt19937 rng(7);
  std::uniform_real_distribution<double> unit(-1.0, 1.0);
  int outside = 0, shallow = 0;
  for (int n = 0; n < 200000; ++n) {
    const Eigen::Vector3d p(0.8e-3 * unit(rng), 0.8e-3 * unit(rng), 1.3e-3 * unit(rng));
    const double exact = shape->signed_distance(p);
    if (std::abs(exact) > std::sqrt(3.0) * kDx) continue;  // the corners of cut cells only
    const double error = table.signed_distance(p) - exact;
    ASSERT_GE(error, -kFloatRounding) << p.transpose();
    if (exact >= 0.0) {
      ++outside;
      ASSERT_LE(error, outside_bound) << p.transpose();
    } else if (-exact < 0.5 * kRadiusMin - std::sqrt(3.0) * kSpacing) {
      ++shallow;
      ASSERT_LE(error, shallow_bound) << p.transpose();
    }
  }
  EXPECT_GT(outside, 1000);
  EXPECT_GT(shallow, 1000);
}

TEST(DistanceTable, BeyondTheTableTheDistanceIsTheExactOne) {
  const auto shape = std::make_shared<const Ellipsoid>(Ellipsoid::spheroid(1.0e-3, 2.0));
  const DistanceTable table(shape, kSpacing, 2.5 * kDx, 2.5 * kDx);
  for (const Eigen::Vector3d& p : {Eigen::Vector3d(3e-3, 0.0, 0.0), Eigen::Vector3d(0.1e-3, -0.2e-3, 5e-3)})
    EXPECT_EQ(table.signed_distance(p), shape->signed_distance(p));
}

// Exact values are computed only near the surface: the band of 2.5 cells plus the coarse pass's
// reach holds most of the nodes of a box this close to the body, and a minority of a wide one.
TEST(DistanceTable, FarNodesTakeTheCoarsePassValue) {
  const auto shape = std::make_shared<const Ellipsoid>(Ellipsoid::spheroid(1.0e-3, 2.0));
  const DistanceTable near_only(shape, kSpacing, 2.5 * kDx, 2.5 * kDx);
  const DistanceTable wide(shape, kSpacing, 8.0 * kDx, 2.5 * kDx);
  EXPECT_LT(near_only.exact_node_count(), near_only.node_count());
  EXPECT_LT(static_cast<double>(wide.exact_node_count()), 0.2 * static_cast<double>(wide.node_count()));
  // A far point of the wide table: the coarse interpolation of a 1-Lipschitz function is within
  // sqrt(3) coarse spacings (4 nodes) of it.
  const Eigen::Vector3d far(1.6e-3, 1.5e-3, 0.5e-3);
  EXPECT_NEAR(wide.signed_distance(far), shape->signed_distance(far), std::sqrt(3.0) * 4.0 * wide.spacing());
}

}  // namespace test_distance_table
}  // namespace settle::body
