// Cuboids against closed forms and against independent constructions (rasterised shadows of
// a box mesh, dense surface samples).
#include <cmath>
#include <numbers>
#include <random>

#include <gtest/gtest.h>

#include "body/cuboid.hpp"
#include "body/projected_area.hpp"
#include "body/shape_factors.hpp"
#include "common/error.hpp"
#include "shape_test_support.hpp"

namespace settle::body {
namespace test_cuboid {

using std::numbers::pi;

constexpr double kClosedForm = 1e-13;

TEST(Cuboid, VolumeAreaInertia) {
  const Cuboid box(Eigen::Vector3d(3.0, 2.0, 1.0));
  EXPECT_NEAR(box.volume(), 6.0, kClosedForm * 6);
  EXPECT_NEAR(box.surface_area(), 2 * (6.0 + 2.0 + 3.0), kClosedForm * 22);
  const MassProperties p = box.mass_properties(0.5);
  const double m = 3.0;
  // I_xx = m (b^2 + c^2) / 12 etc.
  EXPECT_TRUE(p.inertia.diagonal().isApprox(m / 12.0 * Eigen::Vector3d(5.0, 10.0, 13.0), kClosedForm));
  EXPECT_TRUE(p.principal.moments.isApprox(m / 12.0 * Eigen::Vector3d(5.0, 10.0, 13.0), kClosedForm));
  EXPECT_NEAR(box.bounding_radius(), 0.5 * std::sqrt(14.0), kClosedForm);
}

// The generic crossing (a root of signed_distance along the segment, the base class's) on a face
// of a box, where the closed form is the face's plane: x = 1.5 on the +x face of a 3 x 2 x 1 box.
// The root-finder stops within a billionth of the segment; the distance is linear along it, so
// the first secant step is already the root to round-off.
TEST(Cuboid, SurfaceCrossingOfALinkThroughAFaceIsOnThePlane) {
  const Cuboid box(Eigen::Vector3d(3.0, 2.0, 1.0));
  const Eigen::Vector3d outside(1.8, 0.2, -0.1), link(-0.7, 0.3, 0.2);
  const double t = box.surface_crossing(outside, outside + link);
  EXPECT_NEAR(t, 0.3 / 0.7, 1e-9);
  EXPECT_NEAR(box.signed_distance(outside + t * link), 0.0, 1e-9 * link.norm());
}

TEST(Cuboid, ProjectedAreaAgreesWithScanlinesOfBoxMesh) {
  // The scanline measure of the box mesh's silhouette (an independent construction) is second
  // order in the row height: measured ~1e-8 with 4096 rows, 1e-6 allows for unlucky kinks.
  const Eigen::Vector3d size(3.0, 2.0, 1.0);
  const Cuboid box(size);
  const TriangleMesh mesh = testing::box_mesh(size);
  std::mt19937_64 rng(10);
  for (int i = 0; i < 5; ++i) {
    const Eigen::Vector3d n = testing::random_unit(rng);
    const double scanned = scanline_projected_area(mesh, n, 4096);
    EXPECT_NEAR(box.projected_area(n) / scanned, 1.0, 1e-6) << n.transpose();
  }
}

TEST(Cuboid, MeanPerpendicularShadowMatchesQuadrature) {
  // The shadow is |cos| type in the angle, so the trapezoidal rule converges as 1/n^2:
  // with 20000 directions the quadrature itself is good to ~1e-8.
  const Cuboid box(Eigen::Vector3d(3.0, 2.0, 1.0));
  for (const Eigen::Vector3d& axis : {Eigen::Vector3d(0, 0, 1), Eigen::Vector3d(1, -2, 0.5).normalized()}) {
    const Eigen::Vector3d u = axis.unitOrthogonal(), v = axis.cross(u);
    const int n = 20000;
    double sum = 0.0;
    for (int k = 0; k < n; ++k)
      sum += box.projected_area(std::cos(pi * (k + 0.5) / n) * u + std::sin(pi * (k + 0.5) / n) * v);
    EXPECT_NEAR(box.mean_projected_area_perpendicular(axis) / (sum / n), 1.0, 1e-7) << axis.transpose();
  }
}

TEST(Cuboid, SignedDistanceAgainstDenseSample) {
  const Eigen::Vector3d size(3.0, 2.0, 1.0);
  const Cuboid box(size);
  // Grid sample of every face with step <= 0.01, edges included: covering radius 0.0071.
  std::vector<Eigen::Vector3d> samples;
  for (int k = 0; k < 3; ++k) {
    const int a = (k + 1) % 3, b = (k + 2) % 3;
    const int na = static_cast<int>(size(a) / 0.01), nb = static_cast<int>(size(b) / 0.01);
    for (double side : {-0.5, 0.5}) {
      for (int i = 0; i <= na; ++i) {
        for (int j = 0; j <= nb; ++j) {
          Eigen::Vector3d s;
          s(k) = side * size(k);
          s(a) = size(a) * (static_cast<double>(i) / na - 0.5);
          s(b) = size(b) * (static_cast<double>(j) / nb - 0.5);
          samples.push_back(s);
        }
      }
    }
  }
  std::mt19937_64 rng(11);
  for (int i = 0; i < 40; ++i) {
    const Eigen::Vector3d p = testing::random_in_box(rng, 0.8 * size);
    const double d = box.signed_distance(p);
    EXPECT_EQ(d <= 0.0, box.contains(p));
    const Eigen::Vector3d q = box.closest_surface_point(p);
    EXPECT_NEAR(box.signed_distance(q), 0.0, 1e-15);
    EXPECT_NEAR((q - p).norm(), std::abs(d), 1e-14);
    double nearest = std::numeric_limits<double>::infinity();
    for (const auto& s : samples) nearest = std::min(nearest, (s - p).norm());
    // No sample is nearer than |d|; the foot point lies on a flat face within 0.0071 of a
    // sample, so the nearest sample is within sqrt(d^2 + 0.0071^2).
    EXPECT_GE(nearest, std::abs(d) - 1e-14);
    EXPECT_LE(nearest, std::sqrt(d * d + 0.0071 * 0.0071));
  }
}

TEST(Cuboid, ShapeFactors) {
  const ShapeFactors f = compute_shape_factors(Cuboid(Eigen::Vector3d(3.0, 2.0, 1.0)), Eigen::Vector3d::UnitZ());
  EXPECT_TRUE(f.principal_extents.isApprox(Eigen::Vector3d(3.0, 2.0, 1.0), kClosedForm));
  EXPECT_NEAR(f.corey_shape_factor, 1.0 / std::sqrt(6.0), kClosedForm);
  EXPECT_NEAR(f.flatness, 0.5, kClosedForm);
  EXPECT_NEAR(f.elongation, 2.0 / 3.0, kClosedForm);
  // Cube: Wadell sphericity (pi/6)^(1/3) = 0.806; with flow along an axis the shadow is one
  // face (crosswise (pi/4)(6/pi)^(2/3)), the side views average 4 a^2 / pi.
  const ShapeFactors cube = compute_shape_factors(Cuboid(Eigen::Vector3d::Ones()), Eigen::Vector3d::UnitZ());
  const double d_eq2 = std::pow(6.0 / pi, 2.0 / 3.0);
  EXPECT_NEAR(cube.sphericity, std::cbrt(pi / 6.0), kClosedForm);
  EXPECT_NEAR(cube.crosswise_sphericity, pi / 4 * d_eq2, kClosedForm);
  EXPECT_NEAR(cube.lengthwise_sphericity, pi / 4 * d_eq2 / (3.0 - 4.0 / pi), kClosedForm);
  EXPECT_NEAR(cube.corey_shape_factor, 1.0, kClosedForm);
}

TEST(Cuboid, MarkersMeetRequirements) {
  for (const Eigen::Vector3d& size : {Eigen::Vector3d(1.0, 0.7, 0.4), Eigen::Vector3d(1.0, 1.0, 0.03)}) {
    const Cuboid box(size);
    const double h = box.equivalent_diameter() / 20.0;
    const SurfaceMarkers markers = box.surface_markers(h);
    std::mt19937_64 rng(12);
    const auto q =
        testing::measure_markers(box, markers, testing::random_points_on_mesh(testing::box_mesh(size), 20000, rng));
    std::printf("cuboid %g x %g x %g: N=%zu area_err=%.2e nn=[%.3f, %.3f]h coverage=%.3fh area=[%.3f, %.3f]h^2\n",
                size.x(), size.y(), size.z(), q.count, q.area_error, q.min_nearest, q.max_nearest, q.max_coverage,
                q.min_area, q.max_area);
    EXPECT_LT(std::abs(q.area_error), 1e-12);  // exact cell areas
    EXPECT_LE(q.max_nearest, 1.5);
    EXPECT_LE(q.max_coverage, 1.0);
    EXPECT_LT(q.max_off_surface, 1e-12);
    EXPECT_LT(q.vector_area_sum, 1e-12);
  }
}

TEST(Cuboid, RefusesBadSize) { EXPECT_THROW(Cuboid(Eigen::Vector3d(1.0, 0.0, 1.0)), settle::InputError); }

}  // namespace test_cuboid
}  // namespace settle::body
