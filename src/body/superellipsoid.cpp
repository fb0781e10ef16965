#include "body/superellipsoid.hpp"

#include <algorithm>
#include <cmath>
#include <limits>
#include <numbers>
#include <vector>

#include <fmt/core.h>

#include "body/cube_sphere.hpp"
#include "body/surface_markers.hpp"
#include "body/triangle_mesh.hpp"
#include "common/error.hpp"

namespace settle::body {
namespace {

constexpr double kHalfPi = 0.5 * std::numbers::pi;
constexpr int kPolishRounds = 6;
// Resolution of the triangulation behind the distance: its chord height bounds the error of
// points the polishing cannot improve (far from the body near sharp edges), and its size sets
// the cost of the nearest-triangle search.
constexpr double kDistanceMeshCellsPerDiameter = 100.0;
// Bounds the triangulation's memory (120 to 170 bytes per triangle with its BVH, measured) and
// build time (about 1 s per million triangles): 1 : 0.8 : 0.6 takes 1.3e5 triangles and
// 1 : 0.1 : 0.1 about 1e6, while a 500:1 needle would otherwise take 2e8 triangles, 24 GB and
// 400 s before any check of the case could run (found with fuzz_case, docs/fuzzing.md).
constexpr double kMaxDistanceMeshTriangles = 1.0e6;

// ||(u, v)||_p for p in [1, inf], scaled by the larger magnitude so that nothing overflows.
double lp_norm(double u, double v, double p) {
  u = std::abs(u);
  v = std::abs(v);
  const double large = std::max(u, v), small = std::min(u, v);
  if (small == 0.0 || std::isinf(p)) return large;
  return large * std::pow(1.0 + std::pow(small / large, p), 1.0 / p);
}

// Conjugate exponent of p = 2 / e: q = 2 / (2 - e), infinite for e = 2.
double conjugate_exponent(double e) { return e >= 2.0 ? std::numeric_limits<double>::infinity() : 2.0 / (2.0 - e); }

// max over u in [0, 1] of A u^e + B (1 - u)^e for A, B > 0: concave for e < 1 with the
// stationary point u/(1 - u) = (A/B)^(1/(1 - e)); otherwise the larger end.
double max_power_blend(double a, double b, double e) {
  if (e >= 1.0) return std::max(a, b);
  const double log_ratio = (std::log(a) - std::log(b)) / (1.0 - e);
  const double u = 1.0 / (1.0 + std::exp(-log_ratio));
  const double w = 1.0 / (1.0 + std::exp(log_ratio));
  return a * std::pow(u, e) + b * std::pow(w, e);
}

// Nodes of the tanh-sinh rule on [0, length]: each node's distances to both ends (computed
// without cancellation, because the integrand is singular there) and its weight.
struct QuadratureNode {
  double from_start, from_end, weight;
};

std::vector<QuadratureNode> tanh_sinh_nodes(double length, double step) {
  // Nodes closer than this to an end are dropped: the neglected part of an integrable
  // singularity x^(e-1) with e >= 0.1 is below 10 (1e-150)^0.1 = 1e-14 of the integral, and
  // the products of such powers stay far from overflow.
  constexpr double kClosest = 1e-150;
  std::vector<QuadratureNode> nodes;
  for (int k = 0;; ++k) {
    const double t = k * step;
    const double u = kHalfPi * std::sinh(t);
    const double q = std::exp(-2.0 * u);             // for t >= 0
    const double near_end = length * q / (1.0 + q);  // length (1 - tanh u) / 2
    if (near_end < kClosest * length) break;
    const double far_end = length / (1.0 + q);  // length (1 + tanh u) / 2
    // weight = length/2 * (pi/2) cosh t / cosh^2 u, with 1/cosh^2 u = 4q / (1 + q)^2
    const double weight = step * 0.5 * length * kHalfPi * std::cosh(t) * 4.0 * q / ((1.0 + q) * (1.0 + q));
    nodes.push_back({far_end, near_end, weight});
    if (k > 0) nodes.push_back({near_end, far_end, weight});
  }
  return nodes;
}

}  // namespace

Superellipsoid::Superellipsoid(const Eigen::Vector3d& semi_axes, double e1, double e2)
    : semi_axes_(semi_axes), e1_(e1), e2_(e2) {
  for (int i = 0; i < 3; ++i) {
    if (!std::isfinite(semi_axes_(i)) || semi_axes_(i) <= 0.0) {
      throw InputError(
          fmt::format("superellipsoid: semi-axis {} must be finite and > 0, got {}", "abc"[i], semi_axes_(i)));
    }
  }
  for (const auto& [name, value] : {std::pair{"e1", e1}, std::pair{"e2", e2}}) {
    if (!(value >= kMinExponent && value <= kMaxExponent)) {
      throw InputError(fmt::format("superellipsoid: exponent {} must lie in [{}, {}] (convex shapes), got {}", name,
                                   kMinExponent, kMaxExponent, value));
    }
  }
  const double a2 = semi_axes_.x() * semi_axes_.x(), b2 = semi_axes_.y() * semi_axes_.y();
  const double c2 = semi_axes_.z() * semi_axes_.z();
  bounding_radius_ = std::sqrt(max_power_blend(max_power_blend(a2, b2, e2_), c2, e1_));
  area_ = compute_surface_area();

  const double d_eq = std::cbrt(6.0 * volume_moments().volume / std::numbers::pi);
  surface_mesh_ = cube_sphere_mesh_with_max_edge(
      semi_axes_, d_eq / kDistanceMeshCellsPerDiameter,
      [this](const Eigen::Vector3d& u) { return radial_projection(semi_axes_.cwiseProduct(u)); },
      kMaxDistanceMeshTriangles);
  bvh_ = TriangleBvh(surface_mesh_);
}

double Superellipsoid::gauge(const Eigen::Vector3d& p) const {
  const Eigen::Vector3d s = p.cwiseQuotient(semi_axes_);
  return lp_norm(lp_norm(s.x(), s.y(), 2.0 / e2_), s.z(), 2.0 / e1_);
}

Eigen::Vector3d Superellipsoid::gauge_gradient(const Eigen::Vector3d& p) const {
  const Eigen::Vector3d s = p.cwiseQuotient(semi_axes_);
  const double p1 = 2.0 / e1_, p2 = 2.0 / e2_;
  const double r = lp_norm(s.x(), s.y(), p2);
  const double n = lp_norm(r, s.z(), p1);
  if (n == 0.0) return Eigen::Vector3d::UnitZ();
  // dN/dr = (r/N)^(p1-1), dr/dX = sign(X) (|X|/r)^(p2-1): ratios <= 1, so no overflow.
  const double dn_dr = std::pow(r / n, p1 - 1.0);
  Eigen::Vector3d g;
  if (r > 0.0) {
    g.x() = dn_dr * std::copysign(std::pow(std::abs(s.x()) / r, p2 - 1.0), s.x()) / semi_axes_.x();
    g.y() = dn_dr * std::copysign(std::pow(std::abs(s.y()) / r, p2 - 1.0), s.y()) / semi_axes_.y();
  } else {
    g.x() = g.y() = 0.0;  // on the z axis the gradient has no horizontal part (p1 > 1)
  }
  g.z() = std::copysign(std::pow(std::abs(s.z()) / n, p1 - 1.0), s.z()) / semi_axes_.z();
  return g;
}

std::pair<double, Eigen::Vector3d> Superellipsoid::gauge_and_gradient(const Eigen::Vector3d& p) const {
  const Eigen::Vector3d s = p.cwiseQuotient(semi_axes_);
  const double m = s.cwiseAbs().maxCoeff();
  if (m == 0.0) return {0.0, gauge_gradient(p)};
  // N is homogeneous of degree 1 and its gradient of degree 0: evaluated at t = s / m, whose
  // largest component is 1, no power overflows. With u = |t_x|^p2, v = |t_y|^p2, w = u + v,
  // F = w^(p1/p2) + |t_z|^p1 and n = F^(1/p1): dn/dt_x = (n / F) (w^(p1/p2) / w) u / |t_x| sign t_x,
  // dn/dt_z = (n / F) |t_z|^p1 / |t_z| sign t_z (p1, p2 >= 1: these vanish with t_x, t_z).
  const Eigen::Vector3d t = s / m;
  const double p1 = 2.0 / e1_, p2 = 2.0 / e2_;
  const double u = std::pow(std::abs(t.x()), p2), v = std::pow(std::abs(t.y()), p2), w = u + v;
  const double horizontal = w > 0.0 ? std::pow(w, p1 / p2) : 0.0;
  const double vertical = std::pow(std::abs(t.z()), p1);
  const double f = horizontal + vertical;
  const double n = std::pow(f, 1.0 / p1);
  const auto slope = [](double power, double x) { return x == 0.0 ? 0.0 : std::copysign(power / std::abs(x), x); };
  const double common = n / f, across = w > 0.0 ? common * horizontal / w : 0.0;
  const Eigen::Vector3d dn_dt(across * slope(u, t.x()), across * slope(v, t.y()), common * slope(vertical, t.z()));
  return {m * n, dn_dt.cwiseQuotient(semi_axes_)};
}

Eigen::Vector3d Superellipsoid::radial_projection(const Eigen::Vector3d& p) const {
  const double n = gauge(p);
  return n > 0.0 ? Eigen::Vector3d(p / n) : Eigen::Vector3d(0.0, 0.0, semi_axes_.z());
}

bool Superellipsoid::contains(const Eigen::Vector3d& p) const { return gauge(p) <= 1.0; }

Eigen::Vector3d Superellipsoid::tangent_step(const Eigen::Vector3d& p, const Eigen::Vector3d& q) const {
  const Eigen::Vector3d n = outward_normal(q);
  return radial_projection(p - (p - q).dot(n) * n);
}

Eigen::Vector3d Superellipsoid::closest_surface_point(const Eigen::Vector3d& p) const {
  // Start from the nearest point of the inscribed triangulation moved radially onto the
  // surface, then polish. A tangent step (to the foot of p on the tangent plane at q, and back
  // onto the surface along the ray) multiplies the error of q by about -d kappa (distance times
  // curvature): it converges near smooth parts of the surface but overshoots where d kappa > 1
  // (far away, or at the sharp edges of small exponents). Two steps measure that factor, and
  // Aitken's extrapolation q0 - D1^2 / (D2 - D1) removes it for any d kappa. Every candidate
  // lies exactly on the surface, so its distance from p bounds the true distance from above:
  // the nearest candidate wins, and a failed step can only be ignored, never make things worse.
  Eigen::Vector3d q0 = radial_projection(bvh_.closest(p).point);
  Eigen::Vector3d best = q0;
  double best_distance = (p - q0).norm();
  auto offer = [&](const Eigen::Vector3d& candidate) {
    const double distance = (p - candidate).norm();
    if (distance < best_distance) best = candidate, best_distance = distance;
  };
  for (int round = 0; round < kPolishRounds; ++round) {
    const Eigen::Vector3d q1 = tangent_step(p, q0);
    offer(q1);
    if ((q1 - q0).norm() <= 1e-14 * bounding_radius_) break;  // converged
    const Eigen::Vector3d q2 = tangent_step(p, q1);
    offer(q2);
    const Eigen::Vector3d d1 = q1 - q0, d2 = q2 - q1;
    const double curvature_term = d1.dot(d2 - d1);
    if (!(std::abs(curvature_term) > 0.0)) break;
    q0 = radial_projection(q0 - d1.squaredNorm() / curvature_term * d1);
    offer(q0);
  }
  return best;
}

double Superellipsoid::signed_distance(const Eigen::Vector3d& p) const {
  const double distance = (p - closest_surface_point(p)).norm();
  return contains(p) ? -distance : distance;
}

double Superellipsoid::surface_crossing(const Eigen::Vector3d& outside, const Eigen::Vector3d& inside) const {
  // The outside end is checked by the first iteration (t = 0 is returned when it is not outside).
  if (!contains(inside)) return 1.0;
  const Eigen::Vector3d along = inside - outside;
  // A step below this ends the search: Newton's error after it is about (g'' / 2 |g'|) step^2 with
  // g = N - 1 along the segment, below 1e-12 of the segment for curvature radii down to a
  // hundredth of it (the sharpest edges at 10 cells per diameter).
  constexpr double kLastStep = 1e-7;
  constexpr int kMaxIterations = 60;
  double t = 0.0;
  for (int iteration = 0; iteration < kMaxIterations; ++iteration) {
    const auto [n, gradient] = gauge_and_gradient(outside + t * along);
    if (!(n > 1.0)) return t;  // on the surface to round-off
    const double rate = gradient.dot(along);
    // Left of the root of a convex function the slope is negative; round-off at a sharp edge
    // may break that.
    if (!(rate < 0.0)) break;
    const double step = (1.0 - n) / rate;
    if (!(t + step <= 1.0)) break;
    t += step;
    if (step < kLastStep) return t;
  }
  // Round-off at a sharp edge stopped Newton (rare): bisect the inside test from the last outside
  // point, to round-off, so that the crossing keeps Newton's accuracy there too.
  double lo = t, hi = 1.0;
  for (int iteration = 0; iteration < 64; ++iteration) {
    const double mid = 0.5 * (lo + hi);
    if (mid == lo || mid == hi) break;
    (contains(outside + mid * along) ? hi : lo) = mid;
  }
  return 0.5 * (lo + hi);
}

Eigen::Vector3d Superellipsoid::outward_normal(const Eigen::Vector3d& surface_point) const {
  return gauge_gradient(surface_point).normalized();
}

double Superellipsoid::support(const Eigen::Vector3d& n) const {
  const Eigen::Vector3d m = semi_axes_.cwiseProduct(n);
  return lp_norm(lp_norm(m.x(), m.y(), conjugate_exponent(e2_)), m.z(), conjugate_exponent(e1_));
}

VolumeMoments Superellipsoid::volume_moments() const {
  const double a = semi_axes_.x(), b = semi_axes_.y(), c = semi_axes_.z();
  const double e1 = e1_, e2 = e2_;
  const double section = e2 * std::beta(e2 / 2.0, e2 / 2.0);  // area of the unit superellipse
  VolumeMoments m;
  m.volume = a * b * c * e1 * section * std::beta(e1 / 2.0, e1 + 1.0);
  const double horizontal = 2.0 * e1 * e2 * std::beta(1.5 * e2, 0.5 * e2 + 1.0) * std::beta(0.5 * e1, 2.0 * e1 + 1.0);
  const double sxx = a * a * a * b * c * horizontal;
  const double syy = a * b * b * b * c * horizontal;
  const double szz = a * b * c * c * c * e1 * section * std::beta(1.5 * e1, e1 + 1.0);
  m.second_moment = Eigen::Vector3d(sxx, syy, szz).asDiagonal();
  return m;
}

double Superellipsoid::compute_surface_area() const {
  const double a = semi_axes_.x(), b = semi_axes_.y(), c = semi_axes_.z();
  const double e1 = e1_, e2 = e2_;
  // |X_eta x X_omega| on the first octant of Barr's parametrisation
  //   X = (a cos^e1(eta) cos^e2(w), b cos^e1(eta) sin^e2(w), c sin^e1(eta)):
  //   e1 e2 c1^e1 (c2 s2)^(e2-1) sqrt(s1^(2e1-2) c1^2 c^2 (b^2 c2^(4-2e2) + a^2 s2^(4-2e2))
  //                                   + a^2 b^2 c1^(2e1-2) s1^2)
  auto element = [&](double s1, double c1, double s2, double c2) {
    const double horizontal = c * c * (b * b * std::pow(c2, 4.0 - 2.0 * e2) + a * a * std::pow(s2, 4.0 - 2.0 * e2));
    const double radicand =
        std::pow(s1, 2.0 * e1 - 2.0) * c1 * c1 * horizontal + a * a * b * b * std::pow(c1, 2.0 * e1 - 2.0) * s1 * s1;
    return e1 * e2 * std::pow(c1, e1) * std::pow(c2 * s2, e2 - 1.0) * std::sqrt(radicand);
  };
  double previous = 0.0, estimate = 0.0;
  for (int level = 2; level <= 8; ++level) {
    const std::vector<QuadratureNode> nodes = tanh_sinh_nodes(kHalfPi, std::ldexp(1.0, -level));
    estimate = 0.0;
    for (const auto& eta : nodes) {
      const double s1 = std::sin(eta.from_start), c1 = std::sin(eta.from_end);
      double inner = 0.0;
      for (const auto& w : nodes) inner += w.weight * element(s1, c1, std::sin(w.from_start), std::sin(w.from_end));
      estimate += eta.weight * inner;
    }
    estimate *= 8.0;
    if (level > 2 && std::abs(estimate - previous) <= 1e-13 * estimate) break;
    previous = estimate;
  }
  return estimate;
}

double Superellipsoid::projected_area(const Eigen::Vector3d& n) const {
  constexpr double kAxisTolerance = 1e-14;
  const double a = semi_axes_.x(), b = semi_axes_.y(), c = semi_axes_.z();
  // The shadow along a body axis is the central section (convex and mirror-symmetric body).
  if (std::abs(n.z()) >= 1.0 - kAxisTolerance) return a * b * e2_ * std::beta(e2_ / 2.0, e2_ / 2.0);
  if (std::abs(n.x()) >= 1.0 - kAxisTolerance) return b * c * e1_ * std::beta(e1_ / 2.0, e1_ / 2.0);
  if (std::abs(n.y()) >= 1.0 - kAxisTolerance) return a * c * e1_ * std::beta(e1_ / 2.0, e1_ / 2.0);
  return convex_projected_area(surface_mesh_, n);
}

double Superellipsoid::mean_projected_area_perpendicular(const Eigen::Vector3d& axis) const {
  return convex_mean_projected_area_perpendicular(surface_mesh_, axis.normalized());
}

SurfaceMarkers Superellipsoid::surface_markers(double spacing) const {
  validate_marker_spacing(spacing, surface_area());
  // The cube is stretched to the bounding box before the radial map, so that each face's grid
  // covers a part of the surface in proportion to the body's extents.
  const TriangleMesh fine = cube_sphere_mesh_with_max_edge(
      semi_axes_, kPatchEdgeFraction * spacing,
      [this](const Eigen::Vector3d& u) { return radial_projection(semi_axes_.cwiseProduct(u)); });
  SurfaceMarkers markers =
      cluster_patches_into_markers(patches_from_mesh(fine, 2.0 * kPatchEdgeFraction * spacing), spacing,
                                   [this](const Eigen::Vector3d& p) { return radial_projection(p); });
  for (std::size_t i = 0; i < markers.size(); ++i) markers.normals[i] = outward_normal(markers.positions[i]);
  return markers;
}

}  // namespace settle::body
