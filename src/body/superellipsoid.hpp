#pragma once
// Superellipsoid in Barr's convention (Barr 1981, IEEE Comput. Graph. Appl. 1(1) 11-23,
// doi:10.1109/MCG.1981.1673799), semi-axes a, b, c along body x, y, z and exponents e1, e2:
//   (|x/a|^(2/e2) + |y/b|^(2/e2))^(e2/e1) + |z/c|^(2/e1) <= 1.
// e2 shapes the horizontal (x-y) cross-sections, e1 the profile along z: e = 1 is elliptic,
// e -> 0 squares the section off (a box in the limit), e = 2 makes it a diamond. Exponents are
// restricted to [0.1, 2]: within this range the body is convex (the formulas below for the
// support function, projected areas and the distance rely on that), and below 0.1 the corners
// are so sharp that the surface triangulation behind the distance would need impractically
// many triangles to keep its documented accuracy.
#include <memory>
#include <utility>

#include "body/shape.hpp"
#include "body/triangle_bvh.hpp"

namespace settle::body {

class Superellipsoid final : public Shape {
 public:
  static constexpr double kMinExponent = 0.1;
  static constexpr double kMaxExponent = 2.0;

  /// semi_axes > 0 and exponents in [kMinExponent, kMaxExponent] (settle::InputError otherwise).
  Superellipsoid(const Eigen::Vector3d& semi_axes, double e1, double e2);

  const Eigen::Vector3d& semi_axes() const { return semi_axes_; }
  double e1() const { return e1_; }
  double e2() const { return e2_; }

  /// The gauge N(x) = F(x)^(e1/2) of the body (a norm, homogeneous of degree 1): the body is
  /// N <= 1 and x / N(x) is the surface point on the ray through x.
  double gauge(const Eigen::Vector3d& p) const;

  std::string kind() const override { return "superellipsoid"; }
  /// Exact (F <= 1).
  bool contains(const Eigen::Vector3d& p) const override;
  bool contains_is_closed_form() const override { return true; }
  /// Sign exact (from F). Magnitude: the nearest point of a fixed triangulation of the surface
  /// (cubed sphere with all vertices on the surface, grid edges <= d_eq/100 but at most 1e6
  /// triangles, which bodies more elongated or flatter than about 10:1 reach, with a coarser
  /// grid; searched through a BVH), moved onto the exact surface and polished by tangent-plane steps with Aitken
  /// extrapolation (closest_surface_point). Every candidate lies on the exact surface, so the
  /// result never underestimates |d|. Measured (tests/body/test_superellipsoid.cpp, offsets
  /// along the normal, whose distance is exact): <= 1e-8 d_eq within 0.01 d_eq of the surface
  /// for all tested exponents (round-off for e >= 0.3); farther out, near the sharp edges of
  /// e = 0.1 or the pointed poles of e1 = 1.5, up to 3e-4 d_eq, the triangulation's chord
  /// height. About 6 microseconds per call.
  double signed_distance(const Eigen::Vector3d& p) const override;
  /// See signed_distance.
  Eigen::Vector3d closest_surface_point(const Eigen::Vector3d& p) const override;
  /// Normalised gradient of the gauge.
  Eigen::Vector3d outward_normal(const Eigen::Vector3d& surface_point) const override;
  /// Newton's method on N - 1 along the segment from `outside`: N is convex (a norm), so along a
  /// line it is a convex function of t, and from the outside end its iterates rise monotonically to
  /// the one crossing without leaving the segment (no bracket needed). Stops after a step below
  /// 1e-7 of the segment (quadratic convergence: the error is then below 1e-12 of it, against the
  /// base class's 1e-9); falls back to the base class's root finder where round-off stalls it.
  /// 3 to 4 evaluations of 5 powers each, against the base class's 5 to 10 signed distances.
  double surface_crossing(const Eigen::Vector3d& outside, const Eigen::Vector3d& inside) const override;
  /// Exact: the squared distance a^2 cos^2e1(eta) cos^2e2(w) + ... separates into two
  /// one-dimensional maxima of A u^e + B (1 - u)^e, which have closed forms.
  double bounding_radius() const override { return bounding_radius_; }
  Aabb bounding_box() const override { return {-semi_axes_, semi_axes_}; }
  /// Exact: the dual norm, ||(||(a n_x, b n_y)||_q2, c n_z)||_q1 with q = 2 / (2 - e).
  double support(const Eigen::Vector3d& direction) const override;

  /// Exact, by Beta functions (the approach of Jaklic, Leonardis and Solina 2000,
  /// "Segmentation and Recovery of Superquadrics", Springer, doi:10.1007/978-94-015-9456-1,
  /// ch. 2; the moments are derived in docs/shapes.md):
  ///   V    = abc e1 e2 B(e2/2, e2/2) B(e1/2, e1 + 1)
  ///   Sxx  = 2 a^3 b c e1 e2 B(3e2/2, e2/2 + 1) B(e1/2, 2e1 + 1), Syy likewise with b^3
  ///   Szz  = a b c^3 e1 e2 B(e2/2, e2/2) B(3e1/2, e1 + 1).
  VolumeMoments volume_moments() const override;
  /// No closed form: double-exponential (tanh-sinh) quadrature of the parametric surface
  /// element over one octant, refined until successive levels agree to 1e-13 (the element has
  /// integrable power singularities at the octant's edges, which this rule handles).
  double surface_area() const override { return area_; }
  /// Exact along the body axes (the shadow is the central section, a superellipse:
  /// ab e2 B(e2/2, e2/2) along z); otherwise Cauchy's formula on the triangulation above
  /// (relative error below 1e-4).
  double projected_area(const Eigen::Vector3d& direction) const override;
  /// Cauchy's formula on the triangulation (exact for it; relative error below 1e-4).
  double mean_projected_area_perpendicular(const Eigen::Vector3d& axis) const override;
  /// Lloyd clustering of a cubed-sphere triangulation with edges <= h/3; seeds moved radially
  /// onto the exact surface; exact normals.
  SurfaceMarkers surface_markers(double spacing) const override;

 private:
  Eigen::Vector3d gauge_gradient(const Eigen::Vector3d& p) const;
  /// The gauge and its gradient from the same five powers (surface_crossing's Newton steps).
  std::pair<double, Eigen::Vector3d> gauge_and_gradient(const Eigen::Vector3d& p) const;
  Eigen::Vector3d radial_projection(const Eigen::Vector3d& p) const;
  /// From surface point q towards the foot of p: q + tangential part of (p - q), moved
  /// radially back onto the surface.
  Eigen::Vector3d tangent_step(const Eigen::Vector3d& p, const Eigen::Vector3d& q) const;
  double compute_surface_area() const;

  Eigen::Vector3d semi_axes_;
  double e1_, e2_;
  double bounding_radius_ = 0.0;
  double area_ = 0.0;
  TriangleMesh surface_mesh_;
  TriangleBvh bvh_;
};

}  // namespace settle::body
