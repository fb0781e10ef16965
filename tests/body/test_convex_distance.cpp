// Distance between two convex bodies (body/convex_distance.hpp): GJK for separated bodies, EPA for
// overlapping ones and the closed form for two spheres, against closed forms (two spheres,
// sphere-cuboid face, edge and corner, two ellipsoids along an axis, two cuboids face to face), the
// symmetry of swapping the bodies, and the distance's continuity through contact and optimality.
#include <algorithm>
#include <cmath>
#include <cstdio>
#include <memory>
#include <random>
#include <vector>

#include <gtest/gtest.h>
#include <Eigen/Geometry>

#include "shape_test_support.hpp"
#include "support/matrix_checks.hpp"

#include "body/convex_distance.hpp"
#include "body/cuboid.hpp"
#include "body/cylinder.hpp"
#include "body/ellipsoid.hpp"
#include "body/mesh_shape.hpp"
#include "body/superellipsoid.hpp"

namespace settle::body {
namespace test_convex_distance {

using settle::test::rotation_about;

// The iterations stop when the upper and lower bounds of the distance differ by kRelativeTolerance
// (1e-10) of the size, so the distance is within that of the closed form; 1e-9 of the size leaves a
// factor 10 for round-off of the support functions (eps times the size and the positions, ~1e-15).
// A normal off by an angle a loses R_D a^2 / 2 of the separation along it (R_D the radius of
// curvature of the Minkowski difference, the size here), so on a curved D the normal is within
// sqrt(2e-10) ~ 1.4e-5 rad: 1e-4 is allowed. The closest points combine support points and inherit
// that angle times the size: 1e-4 of the size (point_b - point_a = d n itself holds to round-off).
constexpr double kDistanceTolerance = 1e-9;
constexpr double kNormalTolerance = 1e-4;
constexpr double kPointTolerance = 1e-4;

/// Attitudes applied to a whole configuration (both bodies and the offset between them).
std::vector<Eigen::Matrix3d> configuration_rotations() {
  return {Eigen::Matrix3d::Identity(), rotation_about({1.0, 2.0, 3.0}, 0.7), rotation_about({-1.0, 0.5, 0.2}, 2.9)};
}

struct Worst {
  double distance = 0.0, normal = 0.0, point = 0.0;
  void add(const ConvexSeparation& s, double exact_distance, const Eigen::Vector3d& exact_normal, double scale) {
    distance = std::max(distance, std::abs(s.distance_si - exact_distance) / scale);
    normal = std::max(normal, (s.normal - exact_normal).norm());
    // The points must be apart by the distance along the normal.
    point = std::max(point, (s.point_b_si - s.point_a_si - s.distance_si * s.normal).norm() / scale);
  }
  void expect_within(const char* what) const {
    std::printf("[measured] %s: distance %.1e, normal %.1e, points %.1e (of the size)\n", what, distance, normal,
                point);
    EXPECT_LT(distance, kDistanceTolerance) << what;
    EXPECT_LT(normal, kNormalTolerance) << what;
    EXPECT_LT(point, kPointTolerance) << what;
  }
};

PlacedShape place(const Shape& shape, const Eigen::Vector3d& position,
                  const Eigen::Matrix3d& rotation = Eigen::Matrix3d::Identity()) {
  return {&shape, position, rotation};
}

TEST(ConvexDistance, TwoSpheresByTheClosedFormAndBySupportFunctions) {
  const double ra = 0.3, rb = 0.5;
  const Ellipsoid a = Ellipsoid::sphere(2.0 * ra), b = Ellipsoid::sphere(2.0 * rb);
  const Eigen::Vector3d centre_a(0.1, -0.2, 0.3), axis = Eigen::Vector3d(1.0, -2.0, 0.5).normalized();
  Worst closed, general;
  for (double gap : {0.2, 1e-3, 1e-7, -1e-7, -1e-3, -0.1, -0.4}) {
    const Eigen::Vector3d centre_b = centre_a + (ra + rb + gap) * axis;
    const ConvexSeparation s = convex_distance(place(a, centre_a), place(b, centre_b));
    closed.add(s, gap, axis, ra + rb);
    EXPECT_LT((s.point_a_si - (centre_a + ra * axis)).norm(), 1e-15);  // the closed form's points, to round-off
    EXPECT_EQ(s.iterations, 0);                                        // the closed form was taken
    const ConvexSeparation g = support_separation(place(a, centre_a), place(b, centre_b));
    general.add(g, gap, axis, ra + rb);
    EXPECT_LT((g.point_a_si - (centre_a + ra * axis)).norm(), kPointTolerance * (ra + rb)) << gap;
    EXPECT_LT((g.point_b_si - (centre_b - rb * axis)).norm(), kPointTolerance * (ra + rb)) << gap;
  }
  EXPECT_LT(closed.distance, 1e-15);  // the closed form: round-off
  closed.expect_within("two spheres, closed form");
  general.expect_within("two spheres, GJK/EPA");
}

TEST(ConvexDistance, SphereAgainstCuboidFaceEdgeAndCorner) {
  // A point c outside a box is at distance |c - clamp(c)| from it; a sphere of radius r centred
  // there is at that minus r, along c - clamp(c), overlapping or not, as long as its centre stays
  // outside the box (the Minkowski sum is the box rounded by r, whose boundary there is that
  // distance away).
  const Eigen::Vector3d size(1.0, 0.6, 0.4), half = 0.5 * size;
  const Cuboid box(size);
  const double r = 0.2;
  const Ellipsoid sphere = Ellipsoid::sphere(2.0 * r);
  const Eigen::Vector3d box_centre(0.3, 0.2, -0.1);
  const std::vector<std::pair<const char*, Eigen::Vector3d>> directions{
      {"face", Eigen::Vector3d::UnitX()},
      {"edge", Eigen::Vector3d(0.0, 1.0, 2.0).normalized()},
      {"corner", Eigen::Vector3d(1.0, -2.0, 1.5).normalized()}};
  const std::vector<Eigen::Vector3d> anchors{{0.5, 0.1, -0.05}, {0.2, 0.3, 0.2}, {0.5, -0.3, 0.2}};
  for (std::size_t k = 0; k < directions.size(); ++k) {
    Worst worst;
    for (const auto& rotation : configuration_rotations())
      for (double gap : {0.1, 1e-4, -1e-4, -0.05, -0.15}) {
        // Body-frame centre: off the face, edge or corner along its outward direction by r + gap.
        const Eigen::Vector3d c_b = anchors[k] + (r + gap) * directions[k].second;
        const Eigen::Vector3d nearest = c_b.cwiseMax(-half).cwiseMin(half);
        ASSERT_LT((nearest - anchors[k]).norm(), 1e-12);  // the anchor is the box point nearest the centre
        const PlacedShape placed_box = place(box, box_centre, rotation);
        const PlacedShape placed_sphere = place(sphere, box_centre + rotation * c_b);
        const ConvexSeparation s = convex_distance(placed_box, placed_sphere);
        worst.add(s, gap, rotation * directions[k].second, half.norm() + r);
        EXPECT_LT((s.point_a_si - (box_centre + rotation * anchors[k])).norm(), kPointTolerance * (half.norm() + r))
            << directions[k].first << " gap " << gap;
      }
    worst.expect_within(directions[k].first);
  }
}

TEST(ConvexDistance, ConvexMeshBoxMatchesTheCuboid) {
  // A box mesh has no closed-form support point: support_point's central differences are used,
  // which blend an edge's or a corner's two sides within 1e-4 rad of its normal cone, up to 1e-4 of
  // the size off the body (header). Against the analytic cuboid's answer, with a sphere off a face,
  // an edge and a corner, separated and overlapping, at a generic attitude.
  const Eigen::Vector3d size(1.0, 0.6, 0.4);
  const Cuboid cuboid(size);
  const MeshShape mesh(testing::box_mesh(size), "box");
  const Ellipsoid sphere = Ellipsoid::sphere(0.4);
  const Eigen::Matrix3d rotation = rotation_about({1.0, 2.0, 3.0}, 0.7);
  const double scale = cuboid.bounding_radius() + 0.2;
  double worst_distance = 0.0, worst_normal = 0.0;
  for (const Eigen::Vector3d& off : {Eigen::Vector3d(0.75, 0.1, -0.05), Eigen::Vector3d(0.2, 0.45, 0.35),
                                     Eigen::Vector3d(0.6, -0.42, 0.3), Eigen::Vector3d(0.65, 0.1, -0.05)}) {
    const PlacedShape placed_sphere = place(sphere, rotation * off);
    const ConvexSeparation exact = convex_distance(place(cuboid, Eigen::Vector3d::Zero(), rotation), placed_sphere);
    const ConvexSeparation s = convex_distance(place(mesh, Eigen::Vector3d::Zero(), rotation), placed_sphere);
    worst_distance = std::max(worst_distance, std::abs(s.distance_si - exact.distance_si) / scale);
    worst_normal = std::max(worst_normal, (s.normal - exact.normal).norm());
  }
  std::printf("[measured] box mesh against the cuboid: distance %.1e (of the size), normal %.1e\n", worst_distance,
              worst_normal);
  EXPECT_LT(worst_distance, 1e-4);
  // The normal joins the closest points: one off by 1e-4 of the size (0.56) turns it by up to that over
  // the gap or depth (0.05 here), 1.1e-3; the overlapping case's face normal alike.
  EXPECT_LT(worst_normal, 2e-3);
}

TEST(ConvexDistance, TwoEllipsoidsAlongAnAxis) {
  // Aligned ellipsoids on their common x axis touch tip to tip: d = s - a_A - a_B. In an overlap
  // the shortest separating translation is along the axis while the depth is below the Minkowski
  // difference's smallest radius of curvature at the tips (b^2/a summed: 0.08 + 0.31 = 0.39 in the
  // x-z plane here).
  const Eigen::Vector3d semi_a(0.5, 0.3, 0.2), semi_b(0.4, 0.25, 0.35);
  const Ellipsoid a(semi_a), b(semi_b);
  const double scale = semi_a.maxCoeff() + semi_b.maxCoeff();
  Worst worst;
  for (const auto& rotation : configuration_rotations())
    for (double gap : {0.1, 1e-4, -1e-4, -0.02}) {
      const Eigen::Vector3d x_a(0.1, 0.2, 0.3);
      const Eigen::Vector3d offset = rotation * Eigen::Vector3d(semi_a.x() + semi_b.x() + gap, 0.0, 0.0);
      const ConvexSeparation s = convex_distance(place(a, x_a, rotation), place(b, x_a + offset, rotation));
      worst.add(s, gap, rotation * Eigen::Vector3d::UnitX(), scale);
      const Eigen::Vector3d tip_a = x_a + rotation * Eigen::Vector3d(semi_a.x(), 0.0, 0.0);
      EXPECT_LT((s.point_a_si - tip_a).norm(), kPointTolerance * scale) << gap;
    }
  worst.expect_within("two ellipsoids tip to tip");
}

TEST(ConvexDistance, TwoCuboidsFaceToFace) {
  // Face to face along x with overlapping y-z projections: d = s - 0.5 - 0.25; an overlap this
  // shallow is resolved along x (the y and z overlaps are 0.8 and 0.75).
  const Cuboid a(Eigen::Vector3d(1.0, 1.0, 1.0)), b(Eigen::Vector3d(0.5, 0.8, 0.6));
  const double scale = a.bounding_radius() + b.bounding_radius();
  Worst worst;
  for (const auto& rotation : configuration_rotations())
    for (double gap : {0.1, 1e-4, -1e-4, -0.05}) {
      const Eigen::Vector3d offset_b(0.75 + gap, 0.1, -0.05);
      const ConvexSeparation s =
          convex_distance(place(a, Eigen::Vector3d::Zero(), rotation), place(b, rotation * offset_b, rotation));
      worst.add(s, gap, rotation * Eigen::Vector3d::UnitX(), scale);
      // The points lie on the facing faces, inside the region where they face each other.
      const Eigen::Vector3d p_a = rotation.transpose() * s.point_a_si, p_b = rotation.transpose() * s.point_b_si;
      EXPECT_NEAR(p_a.x(), 0.5, kPointTolerance * scale);
      EXPECT_NEAR(p_b.x(), 0.5 + gap, kPointTolerance * scale);
      for (const Eigen::Vector3d& p : {p_a, p_b}) {
        EXPECT_GE(p.y(), -0.3 - kPointTolerance * scale);
        EXPECT_LE(p.y(), 0.5 + kPointTolerance * scale);
        EXPECT_GE(p.z(), -0.35 - kPointTolerance * scale);
        EXPECT_LE(p.z(), 0.25 + kPointTolerance * scale);
      }
    }
  worst.expect_within("two cuboids face to face");
}

TEST(ConvexDistance, SwappingTheBodiesFlipsTheNormal) {
  const Ellipsoid spheroid(Eigen::Vector3d(0.25, 0.25, 0.6));
  const Cuboid cuboid(Eigen::Vector3d(0.4, 0.7, 0.3));
  const Cylinder cylinder(0.5, 0.8);
  const Superellipsoid superellipsoid(Eigen::Vector3d(0.3, 0.4, 0.35), 0.6, 0.8);
  const std::vector<std::pair<const Shape*, const Shape*>> pairs{
      {&spheroid, &cuboid}, {&cylinder, &superellipsoid}, {&cuboid, &cylinder}};
  double worst_distance = 0.0, worst_normal = 0.0, worst_point = 0.0;
  for (const auto& [first, second] : pairs)
    for (double along : {1.2, 0.7, 0.5}) {  // separated to overlapping
      const PlacedShape a = place(*first, {0.1, 0.0, -0.2}, rotation_about({1.0, 2.0, 3.0}, 0.7));
      const PlacedShape b = place(*second, a.position_si + along * Eigen::Vector3d(0.6, 0.7, -0.4),
                                  rotation_about({0.3, -1.0, 0.2}, 1.9));
      const ConvexSeparation ab = convex_distance(a, b), ba = convex_distance(b, a);
      const double scale = first->bounding_radius() + second->bounding_radius();
      worst_distance = std::max(worst_distance, std::abs(ab.distance_si - ba.distance_si) / scale);
      worst_normal = std::max(worst_normal, (ab.normal + ba.normal).norm());
      worst_point =
          std::max(worst_point,
                   std::max((ab.point_a_si - ba.point_b_si).norm(), (ab.point_b_si - ba.point_a_si).norm()) / scale);
    }
  std::printf("[measured] swapped bodies: distance %.1e, normal %.1e, points %.1e\n", worst_distance, worst_normal,
              worst_point);
  // Each order is within the tolerances of the exact answer, so they are within twice of each other.
  EXPECT_LT(worst_distance, 2.0 * kDistanceTolerance);
  EXPECT_LT(worst_normal, 2.0 * kNormalTolerance);
  EXPECT_LT(worst_point, 2.0 * kPointTolerance);
}

TEST(ConvexDistance, ContinuousThroughContactAndTheLargestSeparation) {
  // A tilted spheroid moves out of a tilted cuboid along a line, from 0.1 deep to 0.1 apart. The
  // signed distance is a convex and 1-Lipschitz function of the translation (the signed distance
  // of a point to the convex Minkowski difference), so successive values differ by at most the
  // step; and it is the largest separation over all directions, so no sampled direction may
  // separate the bodies by more.
  const Ellipsoid spheroid(Eigen::Vector3d(0.2, 0.2, 0.5));
  const Cuboid cuboid(Eigen::Vector3d(0.6, 0.5, 0.4));
  const PlacedShape a = place(cuboid, Eigen::Vector3d::Zero(), rotation_about({1.0, -1.0, 2.0}, 0.4));
  const Eigen::Vector3d direction = Eigen::Vector3d(0.3, -0.2, 1.0).normalized();
  const Eigen::Matrix3d spheroid_rotation = rotation_about({0.0, 1.0, 0.3}, 0.8);
  // Start where the two touch: d(t) = 0 at t0 is found from the exact separation along the line.
  const auto at = [&](double t) { return place(spheroid, t * direction, spheroid_rotation); };
  double t0 = 0.0;
  double lo = 0.0, hi = 2.0;  // overlapping with the centres together, apart 2 m away
  for (int i = 0; i < 60; ++i) {
    t0 = 0.5 * (lo + hi);
    (convex_distance(a, at(t0)).distance_si > 0.0 ? hi : lo) = t0;
  }
  std::mt19937 random(7);
  std::normal_distribution<double> gauss;
  std::vector<Eigen::Vector3d> samples(2000);
  for (auto& u : samples) u = Eigen::Vector3d(gauss(random), gauss(random), gauss(random)).normalized();
  const double scale = spheroid.bounding_radius() + cuboid.bounding_radius(), step = 1e-3;
  double previous = 0.0, worst_lipschitz = 0.0, worst_optimality = 0.0, worst_convexity = 0.0;
  std::vector<double> distances;
  for (int i = -100; i <= 100; ++i) {
    const PlacedShape b = at(t0 + i * step);
    const ConvexSeparation s = convex_distance(a, b);
    if (i > -100) worst_lipschitz = std::max(worst_lipschitz, std::abs(s.distance_si - previous) - step);
    previous = s.distance_si;
    distances.push_back(s.distance_si);
    for (const auto& u : samples)
      worst_optimality = std::max(worst_optimality, separation_along(a, b, u) - s.distance_si);
  }
  for (std::size_t i = 1; i + 1 < distances.size(); ++i)
    worst_convexity = std::max(worst_convexity, 2.0 * distances[i] - distances[i - 1] - distances[i + 1]);
  std::printf(
      "[measured] through contact: |d(t + h) - d(t)| - h <= %.1e, largest sampled separation above d %.1e, convexity "
      "defect %.1e (of the size)\n",
      worst_lipschitz / scale, worst_optimality / scale, worst_convexity / scale);
  // Each value within kDistanceTolerance of the exact one: the bounds hold to twice that (four
  // times for the second difference, whose exact value is >= 0).
  EXPECT_LT(worst_lipschitz, 2.0 * kDistanceTolerance * scale);
  EXPECT_LT(worst_optimality, kDistanceTolerance * scale);
  EXPECT_LT(worst_convexity, 4.0 * kDistanceTolerance * scale);
  EXPECT_LT(distances.front(), 0.0);  // overlapping at the start, apart at the end
  EXPECT_GT(distances.back(), 0.0);
}

TEST(ConvexDistance, RejectsAMissingShape) {
  const Cuboid cuboid(Eigen::Vector3d::Ones());
  EXPECT_THROW(convex_distance({}, place(cuboid, Eigen::Vector3d::Zero())), std::invalid_argument);
}

}  // namespace test_convex_distance
}  // namespace settle::body
