// Cylinders and disks against closed forms, and against fine polygonal prisms (exact convex
// polyhedra whose properties converge to the cylinder's).
#include <cmath>
#include <numbers>
#include <random>

#include <gtest/gtest.h>
#include <ostream>

#include "body/cylinder.hpp"
#include "body/shape_factors.hpp"
#include "body/triangle_mesh.hpp"
#include "common/error.hpp"
#include "shape_test_support.hpp"

namespace settle::body {
namespace test_cylinder {

using std::numbers::pi;

constexpr double kClosedForm = 1e-13;

// Regular n-gon prism inscribed in the cylinder (radius r, length l, axis z).
TriangleMesh prism(double r, double l, int n) {
  TriangleMesh mesh;
  for (int k = 0; k < n; ++k) {
    const double phi = 2 * pi * k / n;
    mesh.vertices.push_back({r * std::cos(phi), r * std::sin(phi), -0.5 * l});
    mesh.vertices.push_back({r * std::cos(phi), r * std::sin(phi), 0.5 * l});
  }
  const int bottom = static_cast<int>(mesh.vertices.size());
  mesh.vertices.push_back({0, 0, -0.5 * l});
  mesh.vertices.push_back({0, 0, 0.5 * l});
  for (int k = 0; k < n; ++k) {
    const int a = 2 * k, b = 2 * ((k + 1) % n);
    mesh.triangles.push_back({a, b, b + 1});
    mesh.triangles.push_back({a, b + 1, a + 1});
    mesh.triangles.push_back({bottom, b, a});
    mesh.triangles.push_back({bottom + 1, a + 1, b + 1});
  }
  return mesh;
}

TEST(Cylinder, VolumeAreaInertia) {
  const Cylinder c(2.0, 3.0);  // R = 1, L = 3
  EXPECT_NEAR(c.volume(), 3.0 * pi, kClosedForm * 10);
  EXPECT_NEAR(c.surface_area(), 2 * pi + 6 * pi, kClosedForm * 30);
  const MassProperties p = c.mass_properties(2.0);
  const double m = 2.0 * 3.0 * pi;
  // I_zz = m R^2 / 2, I_xx = I_yy = m (3 R^2 + L^2) / 12.
  EXPECT_NEAR(p.inertia(2, 2), m / 2.0, kClosedForm * m);
  EXPECT_NEAR(p.inertia(0, 0), m * (3.0 + 9.0) / 12.0, kClosedForm * m);
  EXPECT_NEAR(p.inertia(1, 1), p.inertia(0, 0), 0.0);
  EXPECT_TRUE(p.centroid.isZero(0.0));
  EXPECT_NEAR(c.bounding_radius(), std::hypot(1.0, 1.5), kClosedForm);
}

TEST(Cylinder, PropertiesConvergeToThoseOfInscribedPrisms) {
  // The n-gon prism's volume, area and shadows differ from the cylinder's by O(1/n^2): the
  // error must fall by ~4 when n doubles, and be small for n = 1024.
  const Cylinder c(2.0, 3.0);
  const Eigen::Vector3d oblique = Eigen::Vector3d(1.0, 0.4, 0.8).normalized();
  double previous_error = 0.0;
  for (int n : {256, 512, 1024}) {
    const TriangleMesh mesh = prism(1.0, 3.0, n);
    const double error = std::max({std::abs(polyhedron_moments(mesh).volume / c.volume() - 1.0),
                                   std::abs(convex_projected_area(mesh, oblique) / c.projected_area(oblique) - 1.0),
                                   std::abs(convex_mean_projected_area_perpendicular(mesh, oblique) /
                                                c.mean_projected_area_perpendicular(oblique) -
                                            1.0)});
    if (previous_error > 0.0) {
      EXPECT_NEAR(previous_error / error, 4.0, 0.2) << "n = " << n;
    }
    previous_error = error;
  }
  EXPECT_LT(previous_error, 2e-5);
}

TEST(Cylinder, ProjectedAreaLimits) {
  const Cylinder c(2.0, 3.0);
  EXPECT_NEAR(c.projected_area(Eigen::Vector3d::UnitZ()), pi, kClosedForm);
  EXPECT_NEAR(c.projected_area(Eigen::Vector3d::UnitY()), 6.0, kClosedForm);
  // Flow along the axis: every side view is the 2R x L rectangle.
  EXPECT_NEAR(c.mean_projected_area_perpendicular(Eigen::Vector3d::UnitZ()), 6.0, kClosedForm * 6);
}

TEST(Cylinder, SignedDistanceAgainstDenseSample) {
  // Same bounds as for the ellipsoid: no sample nearer than |d|, and the nearest sample within
  // sqrt(d^2 + r^2) (flat pieces; near the rims the sample grid is conforming, r <= 0.011).
  const Cylinder c(2.0, 3.0);
  std::vector<Eigen::Vector3d> samples;
  const int around = 600, along = 300, rings = 100;
  for (int j = 0; j < around; ++j) {
    const double phi = 2 * pi * j / around;
    for (int i = 0; i <= along; ++i) samples.push_back({std::cos(phi), std::sin(phi), -1.5 + 3.0 * i / along});
    for (int i = 0; i <= rings; ++i) {
      const double r = static_cast<double>(i) / rings;
      samples.push_back({r * std::cos(phi), r * std::sin(phi), 1.5});
      samples.push_back({r * std::cos(phi), r * std::sin(phi), -1.5});
    }
  }
  std::mt19937_64 rng(7);
  for (int i = 0; i < 60; ++i) {
    const Eigen::Vector3d p = testing::random_in_box(rng, Eigen::Vector3d(1.6, 1.6, 2.2));
    const double d = c.signed_distance(p);
    EXPECT_EQ(d <= 0.0, c.contains(p));
    const Eigen::Vector3d q = c.closest_surface_point(p);
    EXPECT_NEAR(std::abs(c.signed_distance(q)), 0.0, 1e-15);
    EXPECT_NEAR((q - p).norm(), std::abs(d), 1e-14);
    double nearest = std::numeric_limits<double>::infinity();
    for (const auto& s : samples) nearest = std::min(nearest, (s - p).norm());
    EXPECT_GE(nearest, std::abs(d) - 1e-14);
    EXPECT_LE(nearest, std::sqrt(d * d + 0.011 * 0.011));
  }
}

TEST(Cylinder, GradientOfDistanceIsUnitAwayFromRimsAndMedialSurfaces) {
  const Cylinder c(2.0, 3.0);
  std::mt19937_64 rng(8);
  int checked = 0;
  for (int i = 0; i < 400; ++i) {
    const Eigen::Vector3d p = testing::random_in_box(rng, Eigen::Vector3d(2.0, 2.0, 2.5));
    // Inside, skip points nearly equidistant from mantle and cap (the medial surface) or near
    // the axis; central differences need the distance to be smooth over the step.
    const double to_mantle = 1.0 - std::hypot(p.x(), p.y()), to_cap = 1.5 - std::abs(p.z());
    if (c.contains(p) && (std::abs(to_mantle - to_cap) < 1e-3 || to_mantle > 0.99)) continue;
    const double step = 1e-6;
    Eigen::Vector3d g;
    for (int k = 0; k < 3; ++k) {
      const Eigen::Vector3d dk = step * Eigen::Vector3d::Unit(k);
      g(k) = (c.signed_distance(p + dk) - c.signed_distance(p - dk)) / (2 * step);
    }
    // Round-off of the differences: ~1e-16 / 1e-6 = 1e-10, curvature terms ~1e-12.
    EXPECT_NEAR(g.norm(), 1.0, 1e-8) << p.transpose();
    ++checked;
  }
  EXPECT_GT(checked, 300);
}

TEST(Cylinder, ShapeFactors) {
  const ShapeFactors rod = compute_shape_factors(Cylinder(1.0, 2.0), Eigen::Vector3d::UnitZ());
  EXPECT_TRUE(rod.principal_extents.isApprox(Eigen::Vector3d(2.0, 1.0, 1.0), kClosedForm));
  EXPECT_NEAR(rod.corey_shape_factor, 1.0 / std::sqrt(2.0), kClosedForm);
  EXPECT_NEAR(rod.elongation, 0.5, kClosedForm);
  const ShapeFactors disk = compute_shape_factors(Cylinder(1.0, 0.1), Eigen::Vector3d::UnitZ());
  EXPECT_TRUE(disk.principal_extents.isApprox(Eigen::Vector3d(1.0, 1.0, 0.1), kClosedForm));
  EXPECT_NEAR(disk.flatness, 0.1, kClosedForm);
  EXPECT_NEAR(disk.corey_shape_factor, 0.1, kClosedForm);
  // Broadside flow on the disk: the shadow is the face, pi d^2 / 4.
  EXPECT_NEAR(disk.projected_area_along_flow, pi / 4, kClosedForm);
}

struct MarkerCase {
  const char* name;
  double diameter, length, spacing_fraction;  // h = d_eq * spacing_fraction
};

// Names the parameter in test listings (instead of a byte dump).
void PrintTo(const MarkerCase& b, std::ostream* os) { *os << b.name; }

class CylinderMarkers : public ::testing::TestWithParam<MarkerCase> {};

TEST_P(CylinderMarkers, MeetRequirements) {
  const auto& param = GetParam();
  const Cylinder c(param.diameter, param.length);
  const double h = c.equivalent_diameter() * param.spacing_fraction;
  const SurfaceMarkers markers = c.surface_markers(h);
  // Random surface sample, uniform in area over caps and mantle.
  std::mt19937_64 rng(9);
  std::uniform_real_distribution<double> u(0.0, 1.0);
  const double r = c.radius(), l = c.length();
  const double cap_share = 2 * pi * r * r / c.surface_area();
  std::vector<Eigen::Vector3d> samples;
  for (int i = 0; i < 20000; ++i) {
    const double phi = 2 * pi * u(rng);
    if (u(rng) < cap_share) {
      const double rho = r * std::sqrt(u(rng));
      samples.push_back({rho * std::cos(phi), rho * std::sin(phi), u(rng) < 0.5 ? -0.5 * l : 0.5 * l});
    } else {
      samples.push_back({r * std::cos(phi), r * std::sin(phi), l * (u(rng) - 0.5)});
    }
  }
  const auto q = testing::measure_markers(c, markers, samples);
  std::printf("%s: N=%zu area_err=%.2e nn=[%.3f, %.3f]h coverage=%.3fh area=[%.3f, %.3f]h^2 mean %.3f\n", param.name,
              q.count, q.area_error, q.min_nearest, q.max_nearest, q.max_coverage, q.min_area, q.max_area, q.mean_area);
  // Grid areas are exact: the sum is the closed-form area to round-off.
  EXPECT_LT(std::abs(q.area_error), 1e-12);
  EXPECT_LE(q.max_nearest, 1.5);
  EXPECT_LE(q.max_coverage, 1.0);
  EXPECT_LT(q.max_off_surface, 1e-12);
  // Grids of round(length / h) cells: each cell's sides lie within [h/1.5, 1.5 h].
  EXPECT_GT(q.min_area, 0.4);
  EXPECT_LT(q.max_area, 2.25);
  // The caps' and mantle's normals are exact, so the vector area cancels to round-off.
  EXPECT_LT(q.vector_area_sum, 1e-12);
}

INSTANTIATE_TEST_SUITE_P(Shapes, CylinderMarkers,
                         ::testing::Values(MarkerCase{"rod", 1.0, 2.0, 1.0 / 20},
                                           MarkerCase{"disk", 1.0, 0.1, 1.0 / 20},
                                           MarkerCase{"coin_thinner_than_h", 1.0, 0.02, 1.0 / 20},
                                           MarkerCase{"cube_like", 1.0, 1.0, 1.0 / 40}),
                         [](const auto& param_info) { return std::string(param_info.param.name); });

TEST(Cylinder, RefusesBadParameters) {
  EXPECT_THROW(Cylinder(0.0, 1.0), settle::InputError);
  EXPECT_THROW(Cylinder(1.0, -1.0), settle::InputError);
  EXPECT_THROW(Cylinder(1.0, std::numeric_limits<double>::infinity()), settle::InputError);
}

}  // namespace test_cylinder
}  // namespace settle::body
