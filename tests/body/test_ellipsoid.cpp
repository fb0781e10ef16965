// Spheres, spheroids and triaxial ellipsoids against closed forms.
#include <cmath>
#include <limits>
#include <numbers>
#include <random>

#include <gtest/gtest.h>
#include <ostream>

#include "body/ellipsoid.hpp"
#include "body/shape_factors.hpp"
#include "common/error.hpp"
#include "shape_test_support.hpp"

namespace settle::body {
namespace test_ellipsoid {

using std::numbers::pi;
using testing::measure_markers;
using testing::random_unit;

// Closed forms evaluated in double precision agree to a few ulp; 1e-13 relative leaves room
// for the ~10 operations in each.
constexpr double kClosedForm = 1e-13;

double relative(double value, double reference) { return std::abs(value / reference - 1.0); }

// Surface area of a spheroid with equatorial semi-axis a and polar semi-axis c, by the
// elementary formulas (independent of the Carlson integrals used by the code).
double spheroid_area(double a, double c) {
  if (c > a) {  // prolate
    const double e = std::sqrt(1.0 - a * a / (c * c));
    return 2.0 * pi * a * a * (1.0 + c / (a * e) * std::asin(e));
  }
  const double e = std::sqrt(1.0 - c * c / (a * a));  // oblate
  return 2.0 * pi * a * a * (1.0 + (1.0 - e * e) / e * std::atanh(e));
}

// Legendre form of the triaxial ellipsoid's area (a > b > c), with the standard library's
// incomplete elliptic integrals: an independent route to the same number.
double legendre_ellipsoid_area(double a, double b, double c) {
  const double phi = std::acos(c / a);
  const double k = std::sqrt(a * a * (b * b - c * c) / (b * b * (a * a - c * c)));
  const double s = std::sin(phi);
  return 2.0 * pi * c * c +
         2.0 * pi * a * b / s * (std::ellint_2(k, phi) * s * s + std::ellint_1(k, phi) * std::cos(phi) * std::cos(phi));
}

TEST(Sphere, VolumeAreaInertia) {
  const Ellipsoid sphere = Ellipsoid::sphere(2.0);
  EXPECT_EQ(sphere.kind(), "sphere");
  EXPECT_NEAR(sphere.volume(), 4.0 / 3.0 * pi, kClosedForm);
  EXPECT_NEAR(sphere.surface_area(), 4.0 * pi, kClosedForm * 4 * pi);
  EXPECT_NEAR(sphere.equivalent_diameter(), 2.0, kClosedForm);
  const MassProperties p = sphere.mass_properties(2500.0);
  EXPECT_NEAR(p.mass, 2500.0 * 4.0 / 3.0 * pi, kClosedForm * p.mass);
  EXPECT_TRUE(p.centroid.isZero(0.0));
  // I = 2/5 m r^2 on the diagonal, zero elsewhere.
  EXPECT_TRUE(p.inertia.isApprox(Eigen::Matrix3d::Identity() * 0.4 * p.mass, kClosedForm));
  EXPECT_NEAR(sphere.bounding_radius(), 1.0, 0.0);
  EXPECT_NEAR(sphere.projected_area(Eigen::Vector3d(1, 2, 3).normalized()), pi, kClosedForm * pi);
}

TEST(Sphere, SignedDistanceIsExact) {
  const Ellipsoid sphere = Ellipsoid::sphere(2.0);
  std::mt19937_64 rng(1);
  for (int i = 0; i < 100; ++i) {
    const Eigen::Vector3d p = 2.0 * testing::random_in_box(rng, Eigen::Vector3d::Ones());
    EXPECT_NEAR(sphere.signed_distance(p), p.norm() - 1.0, 1e-15);
    EXPECT_EQ(sphere.contains(p), p.norm() <= 1.0);
  }
}

TEST(Spheroid, AreaMatchesElementaryFormulas) {
  for (double aspect : {0.05, 0.25, 0.5, 0.9, 1.1, 2.0, 2.5, 10.0}) {
    const Ellipsoid s = Ellipsoid::spheroid(2.0, aspect);
    EXPECT_LT(relative(s.surface_area(), spheroid_area(1.0, aspect)), kClosedForm) << "aspect " << aspect;
    EXPECT_NEAR(s.volume(), 4.0 / 3.0 * pi * aspect, kClosedForm * aspect);
  }
}

TEST(Ellipsoid, TriaxialAreaMatchesLegendreForm) {
  // std::ellint_1/2 are accurate to ~1e-15; the Legendre combination loses a digit for
  // nearly spherical shapes, hence 1e-12.
  for (const Eigen::Vector3d& axes : {Eigen::Vector3d(3.0, 2.0, 1.0), Eigen::Vector3d(1.0, 0.6, 0.3),
                                      Eigen::Vector3d(10.0, 1.0, 0.1), Eigen::Vector3d(1.2, 1.1, 1.0)}) {
    const Ellipsoid e(axes);
    EXPECT_LT(relative(e.surface_area(), legendre_ellipsoid_area(axes.x(), axes.y(), axes.z())), 1e-12)
        << axes.transpose();
  }
}

TEST(Ellipsoid, InertiaMatchesClosedForm) {
  const Ellipsoid e(Eigen::Vector3d(3.0, 2.0, 1.0));
  const MassProperties p = e.mass_properties(7.0);
  const double m = 7.0 * 4.0 / 3.0 * pi * 6.0;
  EXPECT_NEAR(p.mass, m, kClosedForm * m);
  const Eigen::Vector3d expected(m * (4.0 + 1.0) / 5.0, m * (9.0 + 1.0) / 5.0, m * (9.0 + 4.0) / 5.0);
  EXPECT_TRUE(p.inertia.diagonal().isApprox(expected, kClosedForm));
  EXPECT_EQ(p.inertia(0, 1), 0.0);
  // Principal moments ascending: x (smallest) then y then z.
  EXPECT_TRUE(p.principal.moments.isApprox(expected, kClosedForm));
  EXPECT_TRUE(p.principal.axes.isApprox(Eigen::Matrix3d::Identity(), 0.0));
}

TEST(Ellipsoid, ProjectedAreas) {
  const double a = 1.0, c = 2.5;
  const Ellipsoid s = Ellipsoid::spheroid(2.0 * a, c / a);
  EXPECT_NEAR(s.projected_area(Eigen::Vector3d::UnitZ()), pi * a * a, kClosedForm);
  EXPECT_NEAR(s.projected_area(Eigen::Vector3d::UnitX()), pi * a * c, kClosedForm * 10);
  // Viewed at an angle theta from the symmetry axis, the shadow is an ellipse with semi-axes
  // a and sqrt(a^2 cos^2 theta + c^2 sin^2 theta).
  for (double theta : {0.1, 0.7, 1.3}) {
    const Eigen::Vector3d n(std::sin(theta), 0.0, std::cos(theta));
    const double expected =
        pi * a * std::sqrt(a * a * std::cos(theta) * std::cos(theta) + c * c * std::sin(theta) * std::sin(theta));
    EXPECT_NEAR(s.projected_area(n), expected, kClosedForm * expected);
  }
}

TEST(Ellipsoid, MeanPerpendicularProjectionMatchesQuadrature) {
  // The trapezoidal rule on a smooth periodic integrand converges geometrically: 4096 points
  // give the mean to round-off, so 1e-12 tests the elliptic-integral closed form.
  const Ellipsoid e(Eigen::Vector3d(3.0, 2.0, 1.0));
  for (const Eigen::Vector3d& axis :
       {Eigen::Vector3d(0, 0, 1), Eigen::Vector3d(1, 2, 3).normalized(), Eigen::Vector3d(1, 0, 0)}) {
    const Eigen::Vector3d u = axis.unitOrthogonal(), v = axis.cross(u);
    double sum = 0.0;
    const int n = 4096;
    for (int k = 0; k < n; ++k) sum += e.projected_area(std::cos(pi * k / n) * u + std::sin(pi * k / n) * v);
    EXPECT_LT(relative(e.mean_projected_area_perpendicular(axis), sum / n), 1e-12) << axis.transpose();
  }
}

TEST(Ellipsoid, ClosestPointSatisfiesOptimalityAndBeatsDenseSample) {
  // For a dense parametric sample of the surface, no sample may be nearer than the returned
  // distance d (up to round-off), and the nearest sample may exceed it only by the sampling:
  // the sample s nearest the true foot point q is within the grid's covering radius r of q
  // (steps pi/400 and 2 pi/800 on semi-axes <= 3: r <= 0.0167), and for a surface of curvature
  // <= kappa (a/c^2 = 12 here) |p - s|^2 <= d^2 + r^2 (1 + kappa |d|).
  const Eigen::Vector3d axes(3.0, 1.5, 0.5);
  const Ellipsoid e(axes);
  std::vector<Eigen::Vector3d> samples;
  for (int i = 0; i <= 400; ++i) {
    const double theta = pi * i / 400;
    for (int j = 0; j < 800; ++j) {
      const double phi = 2 * pi * j / 800;
      samples.push_back(axes.cwiseProduct(
          Eigen::Vector3d(std::sin(theta) * std::cos(phi), std::sin(theta) * std::sin(phi), std::cos(theta))));
    }
  }
  std::mt19937_64 rng(2);
  std::vector<Eigen::Vector3d> queries;
  for (int i = 0; i < 40; ++i) queries.push_back(testing::random_in_box(rng, 1.3 * axes));
  // Points on the symmetry planes, inside, where the nearest point leaves the plane.
  queries.push_back({0.3, 0.2, 0.0});
  queries.push_back({0.0, 0.0, 0.0});
  queries.push_back({1.0, 0.0, 0.0});
  queries.push_back({0.0, 0.4, 0.0});
  queries.push_back({2.9, 0.0, 0.0});
  queries.push_back({0.0, 0.0, 0.1});
  for (const Eigen::Vector3d& p : queries) {
    const Eigen::Vector3d q = e.closest_surface_point(p);
    const double d = e.signed_distance(p);
    EXPECT_NEAR(q.cwiseQuotient(axes).squaredNorm(), 1.0, 1e-13) << p.transpose();
    EXPECT_NEAR(std::abs(d), (q - p).norm(), 1e-13);
    EXPECT_EQ(d <= 0.0, e.contains(p));
    if ((q - p).norm() > 1e-9) {  // p - q along the normal at q
      EXPECT_NEAR(std::abs((p - q).normalized().dot(e.outward_normal(q))), 1.0, 1e-10) << p.transpose();
    }
    double nearest_sample = std::numeric_limits<double>::infinity();
    for (const auto& s : samples) nearest_sample = std::min(nearest_sample, (s - p).norm());
    EXPECT_GE(nearest_sample, std::abs(d) - 1e-12) << p.transpose();
    const double r = 0.0167, kappa = 12.0;
    EXPECT_LE(nearest_sample, std::sqrt(d * d + r * r * (1.0 + kappa * std::abs(d)))) << p.transpose();
  }
}

// The multiplier's solver on elongated and flat bodies (100:1), at points near the centre (close
// to the medial surface, where the root is steep) and far away: the foot point lies on the surface
// and p - q is along its normal. Failing either means the solver stopped short of the root. The
// foot point's coordinates r_i y_i / (s + r_i) carry the ratios r_i = (a_max / a_i)^2, up to 1e4
// here, which multiply the round-off of s: the bound is 64 ulp times the largest ratio.
TEST(Ellipsoid, ClosestPointOfNeedlesAndDisksIsOnTheSurfaceAlongTheNormal) {
  std::mt19937_64 rng(7);
  for (const Eigen::Vector3d& axes :
       {Eigen::Vector3d(100.0, 1.0, 1.0), Eigen::Vector3d(10.0, 10.0, 0.1), Eigen::Vector3d(5.0, 1.0, 0.05)}) {
    const Ellipsoid e(axes);
    const double ratio = axes.maxCoeff() / axes.minCoeff();
    const double tolerance = 64.0 * std::numeric_limits<double>::epsilon() * ratio * ratio;
    for (double scale : {1e-3, 0.3, 1.0, 1.01, 30.0}) {
      for (int i = 0; i < 300; ++i) {
        const Eigen::Vector3d p = testing::random_in_box(rng, scale * axes);
        const Eigen::Vector3d q = e.closest_surface_point(p);
        EXPECT_NEAR(q.cwiseQuotient(axes).squaredNorm(), 1.0, tolerance) << p.transpose();
        if ((q - p).norm() > 1e-9 * axes.maxCoeff()) {
          EXPECT_NEAR(std::abs((p - q).normalized().dot(e.outward_normal(q))), 1.0, tolerance) << p.transpose();
        }
      }
    }
  }
}

// Inside a prolate spheroid on its axis the nearest points form a ring; a point off the axis by
// round-off (1e-17) once gave an infinite foot point (the multiplier landed on its pole). Point
// (0, 0, -1/2) in the spheroid of semi-axes (1/2, 1/2, 1): the ring lies at z = -2/3 with radius
// sqrt(5)/6, at distance 1/sqrt(6).
TEST(Ellipsoid, PointsOffTheAxisByRoundOffFindTheRing) {
  const Ellipsoid e(Eigen::Vector3d(0.5, 0.5, 1.0), "spheroid");
  for (const Eigen::Vector3d& p : {Eigen::Vector3d(3.0601062746966847e-17, 9.6167713909546204e-19, -0.5),
                                   Eigen::Vector3d(-1e-20, 2e-17, -0.5), Eigen::Vector3d(0.0, 0.0, -0.5)}) {
    const Eigen::Vector3d q = e.closest_surface_point(p);
    ASSERT_TRUE(q.allFinite()) << p.transpose();
    EXPECT_NEAR(q.z(), -2.0 / 3.0, 1e-14);
    EXPECT_NEAR(std::hypot(q.x(), q.y()), std::sqrt(5.0) / 6.0, 1e-14);
    EXPECT_NEAR(e.signed_distance(p), -1.0 / std::sqrt(6.0), 1e-14);
  }
}

TEST(Ellipsoid, SignedDistanceIsZeroOnSurfaceAndHasUnitGradient) {
  const Eigen::Vector3d axes(1.0, 0.6, 0.3);
  const Ellipsoid e(axes);
  std::mt19937_64 rng(3);
  for (int i = 0; i < 200; ++i) {
    const Eigen::Vector3d s = axes.cwiseProduct(random_unit(rng));
    EXPECT_NEAR(e.signed_distance(s), 0.0, 1e-14);
    // Off the surface along the normal, by less than the smallest radius of curvature
    // (c^2/a = 0.09) inside: the distance is exactly the offset and the gradient is the normal.
    const Eigen::Vector3d n = e.outward_normal(s);
    for (double t : {0.5, 0.05, -0.02}) {
      const Eigen::Vector3d p = s + t * n;
      EXPECT_NEAR(e.signed_distance(p), t, 1e-12);
      // Central differences with step 1e-6: truncation ~1e-12 x curvature, round-off ~1e-10.
      const double step = 1e-6;
      Eigen::Vector3d gradient;
      for (int k = 0; k < 3; ++k) {
        const Eigen::Vector3d dk = step * Eigen::Vector3d::Unit(k);
        gradient(k) = (e.signed_distance(p + dk) - e.signed_distance(p - dk)) / (2 * step);
      }
      EXPECT_NEAR(gradient.norm(), 1.0, 1e-6);
      EXPECT_NEAR(gradient.dot(n), 1.0, 1e-6);
    }
  }
}

// The closed-form crossing of a segment with the surface agrees with the generic root-finder of
// the base class (a second method, on signed_distance) and puts the point on the surface. Segments
// are lattice links of length 1 to sqrt(3) in a body of 8-20 units, as the momentum exchange makes
// them, from just outside to just inside, some nearly tangent. Tolerances: the root-finder stops at
// a billionth of the segment; the closed form's point satisfies the surface equation to round-off.
TEST(Ellipsoid, SurfaceCrossingMatchesTheRootFinderAndLiesOnTheSurface) {
  const Eigen::Vector3d axes(10.0, 6.0, 4.0);
  const Ellipsoid e(axes);
  std::mt19937_64 rng(11);
  std::uniform_real_distribution<double> fraction(0.02, 0.98);
  int tested = 0;
  for (int i = 0; i < 400; ++i) {
    const Eigen::Vector3d s = axes.cwiseProduct(random_unit(rng));
    const Eigen::Vector3d link = random_unit(rng) * (1.0 + (std::sqrt(3.0) - 1.0) * fraction(rng));
    const Eigen::Vector3d outside = s - fraction(rng) * link, inside = outside + link;
    if (!(e.signed_distance(outside) > 0.0) || !e.contains(inside)) continue;
    ++tested;
    const double t = e.surface_crossing(outside, inside);
    EXPECT_NEAR(t, e.Shape::surface_crossing(outside, inside), 1e-8);
    EXPECT_NEAR((outside + t * link).cwiseQuotient(axes).norm(), 1.0, 1e-13);
  }
  EXPECT_GT(tested, 50);  // enough segments crossed the surface to mean something
  // Ends on the wrong side: the contract's end values.
  EXPECT_EQ(e.surface_crossing(Eigen::Vector3d::Zero(), Eigen::Vector3d(1.0, 0.0, 0.0)), 0.0);
  EXPECT_EQ(e.surface_crossing(Eigen::Vector3d(20.0, 0.0, 0.0), Eigen::Vector3d(15.0, 0.0, 0.0)), 1.0);
  // Along an axis the crossing is where the axis meets the surface.
  EXPECT_NEAR(e.surface_crossing(Eigen::Vector3d(0.0, 0.0, 4.5), Eigen::Vector3d(0.0, 0.0, 3.5)), 0.5, 1e-14);
}

TEST(Ellipsoid, SupportAndBounds) {
  const Eigen::Vector3d axes(3.0, 2.0, 1.0);
  const Ellipsoid e(axes);
  EXPECT_DOUBLE_EQ(e.bounding_radius(), 3.0);
  EXPECT_EQ(e.bounding_box().upper, axes);
  std::mt19937_64 rng(4);
  for (int i = 0; i < 50; ++i) {
    const Eigen::Vector3d n = random_unit(rng);
    // The support point of direction n is D^2 n / |D n| on the surface.
    const Eigen::Vector3d x = axes.cwiseProduct(axes).cwiseProduct(n) / axes.cwiseProduct(n).norm();
    EXPECT_NEAR(e.support(n), n.dot(x), 1e-14);
    EXPECT_NEAR(x.cwiseQuotient(axes).squaredNorm(), 1.0, 1e-14);
  }
}

TEST(Sphere, ShapeFactorsAreOne) {
  const Ellipsoid sphere = Ellipsoid::sphere(0.7);
  const ShapeFactors f = compute_shape_factors(sphere, Eigen::Vector3d(0.3, -0.2, 1.0));
  EXPECT_NEAR(f.sphericity, 1.0, kClosedForm);
  EXPECT_NEAR(f.crosswise_sphericity, 1.0, kClosedForm);
  EXPECT_NEAR(f.lengthwise_sphericity, 1.0, kClosedForm);
  EXPECT_NEAR(f.corey_shape_factor, 1.0, kClosedForm);
  EXPECT_NEAR(f.flatness, 1.0, kClosedForm);
  EXPECT_NEAR(f.elongation, 1.0, kClosedForm);
  EXPECT_TRUE(f.principal_extents.isApprox(Eigen::Vector3d::Constant(0.7), kClosedForm));
}

TEST(Spheroid, ShapeFactorsClosedForm) {
  // Prolate spheroid, aspect 2.5: extents (2.5d, d, d); oblate 0.25: (d, d, 0.25d).
  const Ellipsoid prolate = Ellipsoid::spheroid(1.0, 2.5);
  const ShapeFactors p = compute_shape_factors(prolate, Eigen::Vector3d::UnitZ());
  EXPECT_TRUE(p.principal_extents.isApprox(Eigen::Vector3d(2.5, 1.0, 1.0), kClosedForm));
  EXPECT_NEAR(p.corey_shape_factor, 1.0 / std::sqrt(2.5), kClosedForm);
  EXPECT_NEAR(p.elongation, 0.4, kClosedForm);
  EXPECT_NEAR(p.flatness, 1.0, kClosedForm);
  const double d_eq = std::cbrt(2.5);
  EXPECT_NEAR(p.sphericity, pi * d_eq * d_eq / spheroid_area(0.5, 1.25), kClosedForm);
  // Flow along the axis: the shadow is the equatorial disk, and every side view is the
  // d x 2.5d ellipse (pi/4 * 2.5).
  EXPECT_NEAR(p.crosswise_sphericity, d_eq * d_eq, kClosedForm);
  EXPECT_NEAR(p.lengthwise_sphericity, 0.25 * pi * d_eq * d_eq / (0.5 * spheroid_area(0.5, 1.25) - 0.25 * pi * 2.5),
              kClosedForm);
  const Ellipsoid oblate = Ellipsoid::spheroid(1.0, 0.25);
  const ShapeFactors o = compute_shape_factors(oblate, Eigen::Vector3d::UnitX());
  EXPECT_TRUE(o.principal_extents.isApprox(Eigen::Vector3d(1.0, 1.0, 0.25), kClosedForm));
  EXPECT_NEAR(o.flatness, 0.25, kClosedForm);
  EXPECT_NEAR(o.elongation, 1.0, kClosedForm);
  EXPECT_NEAR(o.corey_shape_factor, 0.25, kClosedForm);
}

// Marker requirements: areas sum to the exact area within 1% at h = d_eq/20; every
// marker's nearest neighbour within 1.5 h; every point of a dense random sample of the
// surface within h of a marker.
struct MarkerCase {
  const char* name;
  Eigen::Vector3d axes;
};

// Names the parameter in test listings (instead of a byte dump).
void PrintTo(const MarkerCase& b, std::ostream* os) { *os << b.name; }

class EllipsoidMarkers : public ::testing::TestWithParam<MarkerCase> {};

TEST_P(EllipsoidMarkers, MeetRequirements) {
  const Ellipsoid e(GetParam().axes);
  const double h = e.equivalent_diameter() / 20.0;
  const SurfaceMarkers markers = e.surface_markers(h);
  std::mt19937_64 rng(5);
  std::vector<Eigen::Vector3d> samples;
  for (int i = 0; i < 20000; ++i) samples.push_back(e.semi_axes().cwiseProduct(random_unit(rng)));
  const auto q = measure_markers(e, markers, samples);
  RecordProperty("count", static_cast<int>(q.count));
  std::printf(
      "%s: N=%zu area_err=%.2e nn=[%.3f, %.3f]h coverage=%.3fh area=[%.3f, %.3f]h^2 mean %.3f |sum a n|/A=%.2e\n",
      GetParam().name, q.count, q.area_error, q.min_nearest, q.max_nearest, q.max_coverage, q.min_area, q.max_area,
      q.mean_area, q.vector_area_sum);
  EXPECT_LT(std::abs(q.area_error), 0.01);
  EXPECT_LE(q.max_nearest, 1.5);
  EXPECT_LE(q.max_coverage, 1.0);
  // Markers are projected exactly onto the surface: round-off only.
  EXPECT_LT(q.max_off_surface, 1e-9);
  // The mean area per marker is h^2 by construction of the count (within the dart-throwing
  // scatter, measured 0.98-1.02).
  EXPECT_NEAR(q.mean_area, 1.0, 0.05);
  // sum a_i n_i is the marker quadrature of the closed-surface integral of n dA = 0.
  EXPECT_LT(q.vector_area_sum, 1e-2);
  for (std::size_t i = 0; i < markers.size(); ++i) {
    EXPECT_NEAR(markers.normals[i].norm(), 1.0, 1e-14);
  }
}

INSTANTIATE_TEST_SUITE_P(Shapes, EllipsoidMarkers,
                         ::testing::Values(MarkerCase{"sphere", Eigen::Vector3d(1.0, 1.0, 1.0)},
                                           MarkerCase{"prolate", Eigen::Vector3d(0.5, 0.5, 1.25)},
                                           MarkerCase{"oblate", Eigen::Vector3d(0.5, 0.5, 0.125)},
                                           MarkerCase{"triaxial", Eigen::Vector3d(1.0, 0.6, 0.3)}),
                         [](const auto& param_info) { return std::string(param_info.param.name); });

TEST(Ellipsoid, RefusesBadSemiAxes) {
  EXPECT_THROW(Ellipsoid(Eigen::Vector3d(1.0, -1.0, 1.0)), settle::InputError);
  EXPECT_THROW(Ellipsoid(Eigen::Vector3d(1.0, std::nan(""), 1.0)), settle::InputError);
  EXPECT_THROW(Ellipsoid::sphere(1.0).surface_markers(0.0), settle::InputError);
  EXPECT_THROW(Ellipsoid::sphere(1.0).surface_markers(10.0), settle::InputError);
}

}  // namespace test_ellipsoid
}  // namespace settle::body
