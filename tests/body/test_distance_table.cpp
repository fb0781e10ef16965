// The tabulated signed distance (body::DistanceTable) against the exact one, for the default case's
// prolate spheroid (aspect ratio 2) at its 8 cells per equivalent diameter, with the coupling's
// quarter-cell spacing; the side of the surface it settles (certain_side, the momentum exchange's
// inside test) against the shapes' own test.
#include <cmath>
#include <filesystem>
#include <memory>
#include <random>

#include <gtest/gtest.h>

#include "body/distance_table.hpp"
#include "body/ellipsoid.hpp"
#include "body/mesh_shape.hpp"

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

namespace settle::body {
namespace test_distance_table {

// The bound behind certain_side: trilinear interpolation of a 1-Lipschitz function errs by at most
// sum_k w_k |n_k - p| (w_k the weights, n_k the cell's corners), whose largest value over the cell
// is sqrt(3) / 2 of the spacing, at the centre (a grid of 41^3 points of the unit cell; exact at
// the centre, below it elsewhere to round-off).
TEST(DistanceTable, TheInterpolationsErrorBoundPeaksAtTheCellCentre) {
  double largest = 0.0;
  Eigen::Vector3d where = Eigen::Vector3d::Zero();
  constexpr int kSteps = 40;
  for (int i = 0; i <= kSteps; ++i)
    for (int j = 0; j <= kSteps; ++j)
      for (int k = 0; k <= kSteps; ++k) {
        const Eigen::Vector3d p = Eigen::Vector3d(i, j, k) / kSteps;
        double bound = 0.0;
        for (int corner = 0; corner < 8; ++corner) {
          const Eigen::Vector3d n(corner & 1, (corner >> 1) & 1, (corner >> 2) & 1);
          double w = 1.0;
          for (int a = 0; a < 3; ++a) w *= n[a] == 1.0 ? p[a] : 1.0 - p[a];
          bound += w * (n - p).norm();
        }
        if (bound > largest) largest = bound, where = p;
      }
  EXPECT_NEAR(largest, std::sqrt(3.0) / 2.0, 1e-15);
  EXPECT_TRUE(where.isApprox(Eigen::Vector3d::Constant(0.5)));
  EXPECT_GT(DistanceTable::kCertainSpacings, std::sqrt(3.0) / 2.0);
}

// certain_side never contradicts the shape's own inside test, on the shipped grain (a mesh: exact
// distances) and on the default case's spheroid (distances by root search, to round-off), both at
// the momentum exchange's table (a quarter cell, a band of one cell; momentum_exchange.cpp), over
// random points of the table and beyond it. It leaves open only points within twice its threshold
// of the surface (the threshold plus the interpolation's error), and settles most of the points
// within two cells of the surface.
TEST(DistanceTable, CertainSideNeverContradictsTheShape) {
  const auto grain = std::shared_ptr<const Shape>(
      load_mesh_shape(std::filesystem::path(SETTLE_SOURCE_DIR) / "cases/grain.stl"));  // d_eq = 1
  const auto spheroid = std::make_shared<const Ellipsoid>(Ellipsoid::spheroid(1.0e-3, 2.0));
  for (const auto& [shape, dx] :
       {std::pair{grain, 0.1}, std::pair<std::shared_ptr<const Shape>, double>{spheroid, kDx}}) {
    const DistanceTable table(shape, 0.25 * dx, 0.5 * dx, dx);
    const double threshold = DistanceTable::kCertainSpacings * table.spacing();
    const Aabb box = shape->bounding_box();
    const Eigen::Vector3d centre = 0.5 * (box.lower + box.upper);
    const Eigen::Vector3d half = 0.5 * (box.upper - box.lower) + Eigen::Vector3d::Constant(dx);
    std::mt19937_64 rng(8);
    std::uniform_real_distribution<double> unit(-1.0, 1.0);
    int near = 0, settled_near = 0;
    for (int n = 0; n < 40000; ++n) {
      const Eigen::Vector3d p = centre + Eigen::Vector3d(unit(rng), unit(rng), unit(rng)).cwiseProduct(half);
      const int side = table.certain_side(p);
      const double d = shape->signed_distance(p);
      if (side != 0) {
        ASSERT_EQ(side < 0, shape->contains(p)) << shape->kind() << " " << p.transpose() << " d " << d;
      } else {
        ASSERT_LE(std::abs(d), 2.0 * threshold) << shape->kind() << " " << p.transpose();
      }
      if (std::abs(d) < 2.0 * dx) {
        ++near;
        settled_near += side != 0;
      }
    }
    EXPECT_GT(near, 2000);
    EXPECT_GT(settled_near, 0.8 * near) << shape->kind();
  }
}

// A table whose band is thinner than 2 sqrt(3) spacings settles nothing within it (the argument for
// a node outside the band needs that much); beyond the bounding box and the margin, everything is
// outside.
TEST(DistanceTable, CertainSideNeedsItsBandAndCallsTheFarOutside) {
  const auto shape = std::make_shared<const Ellipsoid>(Ellipsoid::spheroid(1.0e-3, 2.0));
  const DistanceTable thin(shape, kSpacing, 2.0 * kSpacing, 3.0 * kSpacing);
  EXPECT_EQ(thin.certain_side(Eigen::Vector3d::Zero()), 0);
  EXPECT_EQ(thin.certain_side(Eigen::Vector3d(0.0, 0.0, 5.0e-3)), 1);
  const DistanceTable table(shape, kSpacing, 2.0 * kSpacing, 4.0 * kSpacing);
  EXPECT_EQ(table.certain_side(Eigen::Vector3d::Zero()), -1);
  EXPECT_EQ(table.certain_side(Eigen::Vector3d(0.0, 0.0, 5.0e-3)), 1);
}

}  // namespace test_distance_table
}  // namespace settle::body
