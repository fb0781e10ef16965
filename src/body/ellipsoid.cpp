#include "body/ellipsoid.hpp"

#include <algorithm>
#include <array>
#include <cmath>
#include <numbers>
#include <utility>

#include <fmt/core.h>

#include "body/carlson.hpp"
#include "body/cube_sphere.hpp"
#include "body/surface_markers.hpp"
#include "common/bisection.hpp"
#include "common/error.hpp"

namespace settle::body {
namespace {

// Root s of g(s) = sum_i (r_i z_i / (s + r_i))^2 - 1 in [lower, upper], g(lower) >= 0 >= g(upper).
// Newton's method runs on phi(s) = (g(s) + 1)^(-1/2) = 1 instead of on g: phi is the power mean
// of order -2 of the (s + r_i) / (r_i z_i), linear in s, hence concave and increasing, and exactly
// linear where one axis dominates. From any start its tangent lands at or below the root, and from
// there Newton climbs to it without overshooting, quadratically near it. On g itself (convex with
// a pole at -r_i) a start near the pole only gains a factor 1.5 per step: about 9 steps on average
// at the default case's cut cells against 3 here (bench: BM_SpheroidSolidCells). The bracket
// [lo, hi] is kept throughout: a trial point outside it, or where g is not finite (lower can
// round onto the pole when z_i is below 1e-16), is replaced by the bracket's midpoint; after 40
// trial points the rest is bisected until the midpoint equals an end.
template <int N>
double solve_multiplier(const std::array<double, N>& r, const std::array<double, N>& z, double lower, double upper) {
  // Converged when a Newton step moves s by less than this fraction of s + 1 (the distance to the
  // nearest pole, -r_i >= -1): the foot point then moves by about as little, relative to the axes.
  constexpr double kConverged = 0x1p-50;
  const auto g_and_slope = [&](double s) {
    double g = -1.0, slope = 0.0;
    for (int i = 0; i < N; ++i) {
      const double ratio = r[i] * z[i] / (s + r[i]);
      g += ratio * ratio;
      slope -= 2.0 * ratio * ratio / (s + r[i]);
    }
    return std::pair{g, slope};
  };
  double lo = lower, hi = upper;
  double s = lower < 0.0 && upper > 0.0 ? 0.0 : lower;  // a point near the surface has its root near 0
  for (int step = 0; step < 40; ++step) {
    const auto [g, slope] = g_and_slope(s);
    if (g == 0.0) return s;
    if (g > 0.0) {
      lo = s;
    } else {
      hi = s;
    }
    if (std::isfinite(g) && slope < 0.0 && std::isfinite(slope)) {
      const double sum = g + 1.0;  // phi = sum^(-1/2), dphi/ds = -slope / (2 sum^(3/2))
      const double delta = 2.0 * (1.0 - 1.0 / std::sqrt(sum)) * sum * std::sqrt(sum) / (-slope);
      const double next = s + delta;
      if (std::abs(delta) <= kConverged * (s + 1.0)) return std::clamp(next, lo, hi);
      if (next > lo && next < hi) {
        s = next;
        continue;
      }
    }
    const double mid = arithmetic_midpoint(lo, hi);
    if (mid == lo || mid == hi) return mid;
    s = mid;
  }
  const auto side = [&](double t) {
    const double g = g_and_slope(t).first;
    if (g > 0.0) return BisectionSide::below;
    return g < 0.0 ? BisectionSide::above : BisectionSide::at_root;
  };
  const auto midpoint_is_an_end = [](double a, double b) {
    const double mid = arithmetic_midpoint(a, b);
    return mid == a || mid == b;
  };
  return bisect({lo, hi}, side, midpoint_is_an_end, 1200).middle();
}

// Closest point on the ellipse (x/e0)^2 + (y/e1)^2 = 1, e0 >= e1 > 0, to (y0, y1) >= 0.
std::array<double, 2> closest_on_ellipse(double e0, double e1, double y0, double y1) {
  if (y1 > 0.0) {
    if (y0 <= 0.0) return {0.0, e1};
    const double z0 = y0 / e0, z1 = y1 / e1;
    const double g = z0 * z0 + z1 * z1 - 1.0;
    if (g == 0.0) return {y0, y1};
    const double r0 = (e0 / e1) * (e0 / e1);
    const double lower = z1 - 1.0;  // there the z1 term alone equals 1
    const double upper = g < 0.0 ? 0.0 : std::hypot(r0 * z0, z1) - 1.0;
    const double s = solve_multiplier<2>({r0, 1.0}, {z0, z1}, lower, upper);
    return {r0 * y0 / (s + r0), y1 / (s + 1.0)};
  }
  // On the major axis: inside, close to the centre, the nearest point leaves the axis.
  const double denominator = e0 * e0 - e1 * e1;
  if (e0 * y0 < denominator) {
    const double u = e0 * y0 / denominator;
    return {e0 * u, e1 * std::sqrt(std::max(0.0, 1.0 - u * u))};
  }
  return {e0, 0.0};
}

// Closest point on the ellipsoid with e0 >= e1 >= e2 > 0 to y >= 0 (componentwise).
Eigen::Vector3d closest_on_ellipsoid(const Eigen::Vector3d& e, const Eigen::Vector3d& y) {
  if (y(2) > 0.0) {
    if (y(1) > 0.0) {
      if (y(0) > 0.0) {
        const Eigen::Vector3d z = y.cwiseQuotient(e);
        const double g = z.squaredNorm() - 1.0;
        if (g == 0.0) return y;
        const double r0 = (e(0) / e(2)) * (e(0) / e(2)), r1 = (e(1) / e(2)) * (e(1) / e(2));
        const double lower = z(2) - 1.0;
        const double upper = g < 0.0 ? 0.0 : Eigen::Vector3d(r0 * z(0), r1 * z(1), z(2)).norm() - 1.0;
        const double s = solve_multiplier<3>({r0, r1, 1.0}, {z(0), z(1), z(2)}, lower, upper);
        return {r0 * y(0) / (s + r0), r1 * y(1) / (s + r1), y(2) / (s + 1.0)};
      }
      const auto x = closest_on_ellipse(e(1), e(2), y(1), y(2));
      return {0.0, x[0], x[1]};
    }
    if (y(0) > 0.0) {
      const auto x = closest_on_ellipse(e(0), e(2), y(0), y(2));
      return {x[0], 0.0, x[1]};
    }
    return {0.0, 0.0, e(2)};
  }
  // On the plane of the two largest axes: inside and near the centre the nearest point may
  // leave the plane towards the smallest axis.
  const double d0 = e(0) * e(0) - e(2) * e(2), d1 = e(1) * e(1) - e(2) * e(2);
  if (e(0) * y(0) < d0 && e(1) * y(1) < d1) {
    const double u0 = e(0) * y(0) / d0, u1 = e(1) * y(1) / d1;
    const double discriminant = 1.0 - u0 * u0 - u1 * u1;
    if (discriminant > 0.0) return {e(0) * u0, e(1) * u1, e(2) * std::sqrt(discriminant)};
  }
  const auto x = closest_on_ellipse(e(0), e(1), y(0), y(1));
  return {x[0], x[1], 0.0};
}

}  // namespace

Ellipsoid::Ellipsoid(const Eigen::Vector3d& semi_axes, std::string kind)
    : semi_axes_(semi_axes), kind_(std::move(kind)) {
  for (int i = 0; i < 3; ++i) {
    if (!std::isfinite(semi_axes_(i)) || semi_axes_(i) <= 0.0) {
      throw InputError(fmt::format("{}: semi-axis {} must be finite and > 0, got {}", kind_, "abc"[i], semi_axes_(i)));
    }
  }
}

Ellipsoid Ellipsoid::sphere(double diameter) { return Ellipsoid(Eigen::Vector3d::Constant(0.5 * diameter), "sphere"); }

Ellipsoid Ellipsoid::spheroid(double diameter, double aspect_ratio) {
  return Ellipsoid(Eigen::Vector3d(0.5 * diameter, 0.5 * diameter, 0.5 * diameter * aspect_ratio), "spheroid");
}

bool Ellipsoid::contains(const Eigen::Vector3d& p) const { return p.cwiseQuotient(semi_axes_).squaredNorm() <= 1.0; }

Eigen::Vector3d Ellipsoid::closest_surface_point(const Eigen::Vector3d& p) const {
  if (is_sphere()) {
    const double r = p.norm();
    return r > 0.0 ? Eigen::Vector3d(p * (semi_axes_.x() / r)) : Eigen::Vector3d(0.0, 0.0, semi_axes_.z());
  }
  // Reflect into the first octant and order the axes by decreasing length.
  // Three insertion steps, stable as std::stable_sort (which allocates a buffer on every call).
  std::array<int, 3> order{0, 1, 2};
  const auto longer = [&](int i, int j) { return semi_axes_(i) > semi_axes_(j); };
  if (longer(order[1], order[0])) std::swap(order[0], order[1]);
  if (longer(order[2], order[1])) {
    std::swap(order[1], order[2]);
    if (longer(order[1], order[0])) std::swap(order[0], order[1]);
  }
  Eigen::Vector3d e, y;
  for (int k = 0; k < 3; ++k) {
    e(k) = semi_axes_(order[k]);
    y(k) = std::abs(p(order[k]));
    // A coordinate below 1e-15 of its semi-axis is a rotation's round-off (a lattice point on an
    // axis of a turned body). Near a medial axis its root would need s + r_k below the spacing of
    // doubles (x_k = y_k / 0); as zero it takes the symmetry plane's branch, which moves the foot
    // point by less than 1e-15 of the axis.
    if (y(k) < 1e-15 * e(k)) y(k) = 0.0;
  }
  const Eigen::Vector3d x = closest_on_ellipsoid(e, y);
  Eigen::Vector3d result;
  for (int k = 0; k < 3; ++k) result(order[k]) = std::copysign(x(k), p(order[k]));
  return result;
}

double Ellipsoid::signed_distance(const Eigen::Vector3d& p) const {
  if (is_sphere()) return p.norm() - semi_axes_.x();
  const double distance = (closest_surface_point(p) - p).norm();
  return contains(p) ? -distance : distance;
}

// In coordinates scaled by the semi-axes the surface is the unit sphere and the segment
// a + t (b - a) meets it where |A + t V|^2 = 1, a quadratic in t. With a outside and b inside,
// the crossing is its smaller root, written as c / q (c = |A|^2 - 1, q the larger root times |V|^2)
// so that it keeps its precision when a lies next to the surface.
double Ellipsoid::surface_crossing(const Eigen::Vector3d& outside, const Eigen::Vector3d& inside) const {
  const Eigen::Vector3d a = outside.cwiseQuotient(semi_axes_);
  const Eigen::Vector3d v = (inside - outside).cwiseQuotient(semi_axes_);
  const double c = a.squaredNorm() - 1.0;
  if (!(c > 0.0)) return 0.0;
  if (!contains(inside)) return 1.0;
  const double half_b = a.dot(v);
  const double discriminant = std::max(0.0, half_b * half_b - v.squaredNorm() * c);
  return std::clamp(c / (std::sqrt(discriminant) - half_b), 0.0, 1.0);
}

Eigen::Vector3d Ellipsoid::outward_normal(const Eigen::Vector3d& surface_point) const {
  return surface_point.cwiseQuotient(semi_axes_.cwiseProduct(semi_axes_)).normalized();
}

double Ellipsoid::support(const Eigen::Vector3d& direction) const { return semi_axes_.cwiseProduct(direction).norm(); }

VolumeMoments Ellipsoid::volume_moments() const {
  const double volume = 4.0 / 3.0 * std::numbers::pi * semi_axes_.prod();
  VolumeMoments m;
  m.volume = volume;
  m.second_moment = (volume / 5.0 * semi_axes_.cwiseProduct(semi_axes_)).asDiagonal();
  return m;
}

double Ellipsoid::surface_area() const {
  const Eigen::Vector3d inverse_squares = semi_axes_.cwiseProduct(semi_axes_).cwiseInverse();
  return 4.0 * std::numbers::pi * semi_axes_.prod() *
         carlson_rg(inverse_squares.x(), inverse_squares.y(), inverse_squares.z());
}

double Ellipsoid::projected_area(const Eigen::Vector3d& direction) const {
  return std::numbers::pi * semi_axes_.prod() * direction.cwiseQuotient(semi_axes_).norm();
}

double Ellipsoid::mean_projected_area_perpendicular(const Eigen::Vector3d& axis) const {
  const Eigen::Vector3d axis_unit = axis.normalized();
  Eigen::Vector3d u = axis_unit.unitOrthogonal();
  const Eigen::Vector3d v = axis_unit.cross(u);
  const Eigen::Vector3d w = semi_axes_.cwiseInverse();
  const Eigen::Vector3d wu = w.cwiseProduct(u), wv = w.cwiseProduct(v);
  Eigen::Matrix2d q;
  q << wu.dot(wu), wu.dot(wv), wu.dot(wv), wv.dot(wv);
  // The 2 x 2 closed form (the iterative solver's AVX-512 code draws GCC 12's false
  // -Wmaybe-uninitialized, GCC bug 105593).
  Eigen::SelfAdjointEigenSolver<Eigen::Matrix2d> solver;
  const Eigen::Vector2d eigenvalues = solver.computeDirect(q, Eigen::EigenvaluesOnly).eigenvalues();
  const double largest = eigenvalues(1), smallest = std::max(0.0, eigenvalues(0));
  const double k = std::sqrt(std::max(0.0, 1.0 - smallest / largest));
  return std::numbers::pi * semi_axes_.prod() * 2.0 / std::numbers::pi * std::sqrt(largest) * complete_elliptic_e(k);
}

SurfaceMarkers Ellipsoid::surface_markers(double spacing) const {
  validate_marker_spacing(spacing, surface_area());
  if (is_sphere()) return fibonacci_sphere_markers(semi_axes_.x(), spacing);
  const Eigen::Vector3d axes = semi_axes_;
  const TriangleMesh fine = cube_sphere_mesh_with_max_edge(
      axes, kPatchEdgeFraction * spacing,
      [axes](const Eigen::Vector3d& u) { return Eigen::Vector3d(axes.cwiseProduct(u.normalized())); });
  SurfaceMarkers markers =
      cluster_patches_into_markers(patches_from_mesh(fine, 2.0 * kPatchEdgeFraction * spacing), spacing,
                                   [this](const Eigen::Vector3d& p) { return closest_surface_point(p); });
  for (std::size_t i = 0; i < markers.size(); ++i) markers.normals[i] = outward_normal(markers.positions[i]);
  return markers;
}

}  // namespace settle::body
