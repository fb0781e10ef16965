// Superellipsoids: the Beta-function moments and the quadrature area against closed forms
// (e = 1: ellipsoid, e = 2: octahedron) and against inscribed polyhedra that converge to the
// surface at second order; the distance against exact distances of offset points.
#include <algorithm>
#include <cmath>
#include <numbers>
#include <random>

#include <gtest/gtest.h>
#include <ostream>

#include "body/cube_sphere.hpp"
#include "body/ellipsoid.hpp"
#include "body/shape_factors.hpp"
#include "body/superellipsoid.hpp"
#include "common/error.hpp"
#include "shape_test_support.hpp"

namespace settle::body {
namespace test_superellipsoid {

using std::numbers::pi;

constexpr double kClosedForm = 1e-13;

double relative(double value, double reference) { return std::abs(value / reference - 1.0); }

// Random points on the surface: random directions sent radially onto it, plus (unless
// random_only) the 6 axis extremes and the 8 points on the box diagonals (the vertices and
// corners of the extreme exponents, which random directions would only approach).
std::vector<Eigen::Vector3d> surface_samples(const Superellipsoid& s, int count, std::uint64_t seed,
                                             bool random_only = false) {
  std::mt19937_64 rng(seed);
  std::vector<Eigen::Vector3d> points;
  for (int k = 0; k < 3 && !random_only; ++k) {
    points.push_back(s.semi_axes()(k) * Eigen::Vector3d::Unit(k));
    points.push_back(-s.semi_axes()(k) * Eigen::Vector3d::Unit(k));
  }
  for (int corner = 0; corner < 8 && !random_only; ++corner) {
    const Eigen::Vector3d u = s.semi_axes().cwiseProduct(
        Eigen::Vector3d(corner & 1 ? 1.0 : -1.0, corner & 2 ? 1.0 : -1.0, corner & 4 ? 1.0 : -1.0));
    points.push_back(u / s.gauge(u));
  }
  for (int i = 0; i < count; ++i) {
    const Eigen::Vector3d u = s.semi_axes().cwiseProduct(testing::random_unit(rng));
    points.push_back(u / s.gauge(u));
  }
  return points;
}

TEST(Superellipsoid, UnitExponentsGiveTheEllipsoid) {
  const Eigen::Vector3d axes(1.0, 0.8, 0.6);
  const Superellipsoid s(axes, 1.0, 1.0);
  const Ellipsoid e(axes);
  EXPECT_LT(relative(s.volume(), e.volume()), kClosedForm);
  EXPECT_TRUE(s.volume_moments().second_moment.isApprox(e.volume_moments().second_moment, kClosedForm));
  // The quadrature is refined to 1e-13 between levels.
  EXPECT_LT(relative(s.surface_area(), e.surface_area()), 1e-12);
  EXPECT_NEAR(s.bounding_radius(), 1.0, kClosedForm);
  std::mt19937_64 rng(20);
  for (int i = 0; i < 20; ++i) {
    const Eigen::Vector3d n = testing::random_unit(rng);
    EXPECT_NEAR(s.support(n), e.support(n), kClosedForm);
    EXPECT_NEAR(s.gauge(n), n.cwiseQuotient(axes).norm(), kClosedForm);
  }
  EXPECT_NEAR(s.projected_area(Eigen::Vector3d::UnitZ()), e.projected_area(Eigen::Vector3d::UnitZ()), kClosedForm);
  EXPECT_NEAR(s.projected_area(-Eigen::Vector3d::UnitX()), e.projected_area(Eigen::Vector3d::UnitX()), kClosedForm);
  // Off the axes the triangulation's Cauchy formula is used: chord error ~1e-5 relative.
  const Eigen::Vector3d n = Eigen::Vector3d(1, 2, 3).normalized();
  EXPECT_LT(relative(s.projected_area(n), e.projected_area(n)), 1e-4);
  EXPECT_LT(relative(s.mean_projected_area_perpendicular(n), e.mean_projected_area_perpendicular(n)), 1e-4);
}

// With unit exponents the crossing is the ellipsoid's closed form (a quadratic's root): to 1e-13 of
// the link over the cosine of its angle to the normal, the round-off of the Newton steps' powers.
TEST(Superellipsoid, UnitExponentsCrossLinksWhereTheEllipsoidDoes) {
  const Eigen::Vector3d axes(10.0, 6.0, 4.0);
  const Superellipsoid s(axes, 1.0, 1.0);
  const Ellipsoid e(axes);
  std::mt19937_64 rng(28);
  std::uniform_real_distribution<double> fraction(0.02, 0.98);
  int tested = 0;
  for (int i = 0; i < 400; ++i) {
    const Eigen::Vector3d x = axes.cwiseProduct(testing::random_unit(rng));
    const Eigen::Vector3d link = testing::random_unit(rng) * (1.0 + (std::sqrt(2.0) - 1.0) * fraction(rng));
    const Eigen::Vector3d outside = x - fraction(rng) * link, inside = outside + link;
    if (e.contains(outside) || !e.contains(inside)) continue;
    const double t = e.surface_crossing(outside, inside);
    const double cosine = std::abs(link.normalized().dot(e.outward_normal(outside + t * link)));
    if (cosine < 1e-2) continue;  // nearly tangent: an error e in N moves the root by e / cos
    ++tested;
    EXPECT_NEAR(s.surface_crossing(outside, inside), t, 1e-13 / cosine);
  }
  EXPECT_GT(tested, 50);
}

TEST(Superellipsoid, ExponentTwoGivesTheOctahedron) {
  // |x/a| + |y/b| + |z/c| <= 1: V = 4/3 abc, area = 4 sqrt(a^2 b^2 + b^2 c^2 + c^2 a^2), and
  // int x^2 dV = 8 a^3 b c int_simplex X^2 = 2/15 a^3 b c.
  const double a = 1.0, b = 0.8, c = 0.6;
  const Superellipsoid s(Eigen::Vector3d(a, b, c), 2.0, 2.0);
  EXPECT_LT(relative(s.volume(), 4.0 / 3.0 * a * b * c), kClosedForm);
  EXPECT_LT(relative(s.surface_area(), 4.0 * std::sqrt(a * a * b * b + b * b * c * c + c * c * a * a)), 1e-12);
  const Eigen::Matrix3d second = s.volume_moments().second_moment;
  EXPECT_LT(relative(second(0, 0), 2.0 / 15.0 * a * a * a * b * c), kClosedForm);
  EXPECT_LT(relative(second(2, 2), 2.0 / 15.0 * a * b * c * c * c), kClosedForm);
  EXPECT_NEAR(s.bounding_radius(), 1.0, kClosedForm);
  const Eigen::Vector3d n = Eigen::Vector3d(0.3, -0.5, 0.8).normalized();
  EXPECT_NEAR(s.support(n), std::max({a * 0.3, b * 0.5, c * 0.8}) / Eigen::Vector3d(0.3, -0.5, 0.8).norm(),
              kClosedForm);
  // Shadow along z: the rhombus of diagonals 2a and 2b.
  EXPECT_NEAR(s.projected_area(Eigen::Vector3d::UnitZ()), 2.0 * a * b, kClosedForm);
}

struct ExponentCase {
  const char* name;
  double e1, e2;
};

// Names the parameter in test listings (instead of a byte dump).
void PrintTo(const ExponentCase& b, std::ostream* os) { *os << b.name; }

class SuperellipsoidExponents : public ::testing::TestWithParam<ExponentCase> {};

TEST_P(SuperellipsoidExponents, MomentsAndAreaMatchInscribedPolyhedra) {
  // Cubed-sphere triangulations with their vertices on the surface: their volume moments and
  // area converge to the body's at second order in the edge length. Halving the edge must cut
  // the error by about 4, and the finest must agree to the stated level.
  const auto& param = GetParam();
  const Eigen::Vector3d axes(1.0, 0.8, 0.6);
  const Superellipsoid s(axes, param.e1, param.e2);
  const VolumeMoments exact = s.volume_moments();
  auto radial = [&](const Eigen::Vector3d& u) {
    const Eigen::Vector3d x = axes.cwiseProduct(u);
    return Eigen::Vector3d(x / s.gauge(x));
  };
  std::vector<double> errors;
  for (int cells : {64, 128, 256}) {
    const TriangleMesh mesh = cube_sphere_mesh({cells, cells, cells}, radial);
    const VolumeMoments m = polyhedron_moments(mesh);
    const double error =
        std::max({relative(m.volume, exact.volume), relative(m.second_moment(0, 0), exact.second_moment(0, 0)),
                  relative(m.second_moment(1, 1), exact.second_moment(1, 1)),
                  relative(m.second_moment(2, 2), exact.second_moment(2, 2)),
                  relative(mesh_surface_area(mesh), s.surface_area())});
    EXPECT_LT(m.centroid.norm(), 1e-14);
    errors.push_back(error);
  }
  std::printf("%s: polyhedron errors %.2e %.2e %.2e\n", param.name, errors[0], errors[1], errors[2]);
  if (param.e1 == 2.0 && param.e2 == 2.0) {
    // The octahedron's faces are planes: the inscribed triangulation is the body itself.
    EXPECT_LT(errors[2], 1e-12);
    return;
  }
  // Second-order convergence (ratio 4 per halving; 3 allows pre-asymptotic corners).
  EXPECT_GT(errors[0] / errors[1], 3.0);
  EXPECT_GT(errors[1] / errors[2], 3.0);
  EXPECT_LT(errors[2], 2e-4);
}

TEST_P(SuperellipsoidExponents, SupportAndBoundingRadiusBoundDenseSamples) {
  // Exact support and radius: no sample exceeds them, and the best of 200000 samples reaches
  // them to within the sampling resolution (~1e-3 relative).
  const auto& param = GetParam();
  const Superellipsoid s(Eigen::Vector3d(1.0, 0.8, 0.6), param.e1, param.e2);
  const auto samples = surface_samples(s, 200000, 21);
  double radius = 0.0;
  for (const auto& x : samples) radius = std::max(radius, x.norm());
  EXPECT_LE(radius, s.bounding_radius() * (1 + 1e-14));
  EXPECT_GT(radius, s.bounding_radius() * (1 - 2e-3));
  std::mt19937_64 rng(22);
  for (int i = 0; i < 10; ++i) {
    const Eigen::Vector3d n = testing::random_unit(rng);
    double best = -1e300;
    for (const auto& x : samples) best = std::max(best, n.dot(x));
    EXPECT_LE(best, s.support(n) * (1 + 1e-14));
    EXPECT_GT(best, s.support(n) * (1 - 2e-3));
  }
}

TEST_P(SuperellipsoidExponents, SignedDistanceOfOffsetPoints) {
  // For a convex body the point s + t n(s) (t > 0, n the outward normal at the surface point
  // s) is exactly at distance t: a reference independent of how the distance is computed.
  // Every candidate foot point lies on the surface, so the result can only err upwards.
  // Near the surface (t <= 0.01 d_eq, where the immersed boundary needs it) the polishing
  // converges: measured <= 3.2e-9 d_eq (pointed poles of e1 = 1.5), round-off for e >= 0.3;
  // bound 1e-8 d_eq. Farther out near sharp features the error is at most the chord height of
  // the d_eq/100 triangulation: measured 2.8e-4 d_eq (e = 0.1); bound 5e-4 d_eq.
  const auto& param = GetParam();
  const Superellipsoid s(Eigen::Vector3d(1.0, 0.8, 0.6), param.e1, param.e2);
  const double d_eq = s.equivalent_diameter();
  double worst_near = 0.0, worst_far = 0.0;
  for (const auto& x : surface_samples(s, 3000, 23)) {
    const Eigen::Vector3d n = s.outward_normal(x);
    EXPECT_TRUE(s.contains(x * (1 - 1e-12)));
    EXPECT_FALSE(s.contains(x * (1 + 1e-12)));
    worst_near = std::max(worst_near, std::abs(s.signed_distance(x)));
    for (double t : {0.001, 0.01, 0.1, 0.5}) {
      const double d = s.signed_distance(x + t * d_eq * n);
      EXPECT_GE(d, t * d_eq - 1e-12);
      (t <= 0.01 ? worst_near : worst_far) = std::max(t <= 0.01 ? worst_near : worst_far, d - t * d_eq);
    }
  }
  std::printf("%s: distance error <= %.2e d_eq near, %.2e d_eq far\n", param.name, worst_near / d_eq, worst_far / d_eq);
  EXPECT_LT(worst_near, 1e-8 * d_eq);
  EXPECT_LT(worst_far, 5e-4 * d_eq);
}

TEST_P(SuperellipsoidExponents, NormalIsTheGaugeGradient) {
  const auto& param = GetParam();
  const Superellipsoid s(Eigen::Vector3d(1.0, 0.8, 0.6), param.e1, param.e2);
  // Random points only: at the octahedron's vertices and edges the gradient jumps.
  for (const auto& x : surface_samples(s, 200, 24, true)) {
    // Central differences of the gauge, step 1e-7: truncation ~1e-14 x curvature; where the
    // gauge's curvature is large (e near 0.1 close to edges) the check is skipped.
    Eigen::Vector3d g;
    const double step = 1e-7;
    for (int k = 0; k < 3; ++k) {
      const Eigen::Vector3d dk = step * Eigen::Vector3d::Unit(k);
      g(k) = (s.gauge(x + dk) - s.gauge(x - dk)) / (2 * step);
    }
    const Eigen::Vector3d n = s.outward_normal(x);
    EXPECT_NEAR(n.norm(), 1.0, 1e-14);
    if (g.norm() < 1e3) {
      EXPECT_GT(n.dot(g.normalized()), 1.0 - 1e-6) << x.transpose();
    }
  }
}

// The root of N(outside + t (inside - outside)) = 1 by bisection to the last bit: the reference
// for surface_crossing, independent of its Newton steps.
double bisected_crossing(const Superellipsoid& s, const Eigen::Vector3d& outside, const Eigen::Vector3d& inside) {
  double lo = 0.0, hi = 1.0;
  for (int i = 0; i < 200; ++i) {
    const double mid = 0.5 * (lo + hi);
    if (mid == lo || mid == hi) break;
    (s.contains(outside + mid * (inside - outside)) ? hi : lo) = mid;
  }
  return 0.5 * (lo + hi);
}

// Lattice links (12 cells per d_eq, 1 to sqrt(2) cells long, as D3Q19's) from just outside to
// just inside, some nearly tangent: the Newton crossing is the bisected root to 1e-12 of the link
// where the link meets the surface at more than half a degree (nearer tangent the root itself is
// ill-conditioned: an error e in N moves it by e / cos); the base class's root finder, which the
// momentum exchange used before, agrees to its own tolerance, 1e-9 / cos.
TEST_P(SuperellipsoidExponents, SurfaceCrossingIsTheRootOfTheGauge) {
  const auto& param = GetParam();
  const Superellipsoid s(Eigen::Vector3d(1.0, 0.8, 0.6), param.e1, param.e2);
  const double cell = s.equivalent_diameter() / 12.0;
  std::mt19937_64 rng(26);
  std::uniform_real_distribution<double> fraction(0.02, 0.98);
  int tested = 0;
  double worst = 0.0;
  for (const auto& x : surface_samples(s, 600, 27)) {
    const Eigen::Vector3d link = cell * (1.0 + (std::sqrt(2.0) - 1.0) * fraction(rng)) * testing::random_unit(rng);
    const Eigen::Vector3d outside = x - fraction(rng) * link, inside = outside + link;
    if (s.contains(outside) || !s.contains(inside)) continue;
    const double t = s.surface_crossing(outside, inside);
    const Eigen::Vector3d wall = outside + t * link;
    const double cosine = std::abs(link.normalized().dot(s.outward_normal(wall)));
    if (cosine < 1e-2) continue;
    ++tested;
    worst = std::max(worst, std::abs(t - bisected_crossing(s, outside, inside)) * cosine);
    EXPECT_NEAR(t, bisected_crossing(s, outside, inside), 1e-12 / cosine) << x.transpose();
    // The base class stops where |signed distance| < 1e-9 of the link: in t that is 1e-9 over the
    // distance's slope along the link, which near an edge or a vertex follows the nearer face, not
    // `cosine`, and differs on the two sides of the root (the smaller one bounds it).
    const double h = 1e-6, d0 = s.signed_distance(outside + t * link);
    const double slope = std::min(std::abs(s.signed_distance(outside + (t + h) * link) - d0),
                                  std::abs(d0 - s.signed_distance(outside + (t - h) * link))) /
                         (h * link.norm());
    EXPECT_NEAR(t, s.Shape::surface_crossing(outside, inside), 1e-9 / std::min(slope, cosine) + 1e-12) << x.transpose();
  }
  std::printf("%s: %d links, |t - bisected| cos <= %.1e\n", param.name, tested, worst);
  EXPECT_GT(tested, 150);
  // The contract's ends: 0 from an inside point, 1 to an outside one.
  EXPECT_EQ(s.surface_crossing(Eigen::Vector3d::Zero(), Eigen::Vector3d(0.5, 0.0, 0.0)), 0.0);
  EXPECT_EQ(s.surface_crossing(Eigen::Vector3d(3.0, 0.0, 0.0), Eigen::Vector3d(2.0, 0.0, 0.0)), 1.0);
}

TEST_P(SuperellipsoidExponents, MarkersMeetRequirements) {
  const auto& param = GetParam();
  const Superellipsoid s(Eigen::Vector3d(1.0, 0.8, 0.6), param.e1, param.e2);
  const double h = s.equivalent_diameter() / 20.0;
  const SurfaceMarkers markers = s.surface_markers(h);
  const auto q = testing::measure_markers(s, markers, surface_samples(s, 20000, 25));
  std::printf("%s: N=%zu area_err=%.2e nn=[%.3f, %.3f]h coverage=%.3fh area=[%.3f, %.3f]h^2 mean %.3f\n", param.name,
              q.count, q.area_error, q.min_nearest, q.max_nearest, q.max_coverage, q.min_area, q.max_area, q.mean_area);
  EXPECT_LT(std::abs(q.area_error), 0.01);
  EXPECT_LE(q.max_nearest, 1.5);
  EXPECT_LE(q.max_coverage, 1.0);
  // Markers are moved exactly onto the surface, where the distance is converged (above).
  EXPECT_LT(q.max_off_surface, 1e-6);
  EXPECT_NEAR(q.mean_area, 1.0, 0.05);
}

INSTANTIATE_TEST_SUITE_P(Shapes, SuperellipsoidExponents,
                         ::testing::Values(ExponentCase{"rounded_box", 0.5, 0.3}, ExponentCase{"near_box", 0.1, 0.1},
                                           ExponentCase{"pinched", 1.5, 0.7}, ExponentCase{"octahedron", 2.0, 2.0},
                                           ExponentCase{"ellipsoid", 1.0, 1.0}),
                         [](const auto& param_info) { return std::string(param_info.param.name); });

TEST(Superellipsoid, ShapeFactorsUseExtents) {
  const ShapeFactors f =
      compute_shape_factors(Superellipsoid(Eigen::Vector3d(1.0, 0.8, 0.6), 0.5, 0.3), Eigen::Vector3d::UnitZ());
  EXPECT_TRUE(f.principal_extents.isApprox(Eigen::Vector3d(2.0, 1.6, 1.2), kClosedForm));
  EXPECT_NEAR(f.corey_shape_factor, 1.2 / std::sqrt(2.0 * 1.6), kClosedForm);
}

TEST(Superellipsoid, RefusesExponentsOutsideTheConvexRange) {
  EXPECT_THROW(Superellipsoid(Eigen::Vector3d::Ones(), 0.05, 1.0), settle::InputError);
  EXPECT_THROW(Superellipsoid(Eigen::Vector3d::Ones(), 1.0, 2.5), settle::InputError);
  EXPECT_THROW(Superellipsoid(Eigen::Vector3d(1.0, 0.0, 1.0), 1.0, 1.0), settle::InputError);
}

}  // namespace test_superellipsoid
}  // namespace settle::body
