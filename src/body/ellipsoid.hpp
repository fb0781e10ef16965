#pragma once
// Ellipsoids: spheres, spheroids and triaxial ellipsoids x^2/a^2 + y^2/b^2 + z^2/c^2 <= 1 with
// semi-axes a, b, c along body x, y, z. A spheroid's symmetry axis is body z: semi-axes
// (d/2, d/2, aspect_ratio d/2) for equatorial diameter d and aspect ratio polar/equatorial.
#include "body/shape.hpp"

namespace settle::body {

class Ellipsoid final : public Shape {
 public:
  /// Semi-axes must be finite and > 0 (settle::InputError otherwise). `kind` names the family
  /// ("sphere", "spheroid" or "ellipsoid") for reports.
  Ellipsoid(const Eigen::Vector3d& semi_axes, std::string kind = "ellipsoid");

  static Ellipsoid sphere(double diameter);
  /// Equatorial diameter and aspect ratio polar / equatorial (> 1 prolate, < 1 oblate).
  static Ellipsoid spheroid(double diameter, double aspect_ratio);

  const Eigen::Vector3d& semi_axes() const { return semi_axes_; }
  bool is_sphere() const { return semi_axes_.x() == semi_axes_.y() && semi_axes_.y() == semi_axes_.z(); }

  std::string kind() const override { return kind_; }
  bool contains(const Eigen::Vector3d& p) const override;
  bool contains_is_closed_form() const override { return true; }
  /// Exact (to round-off): the closest point solves the Lagrange condition
  /// x_i = a_i^2 p_i / (a_i^2 + t), whose multiplier t is the root of a monotone convex function,
  /// bracketed and solved to machine precision by Newton's method from below (bisection where
  /// that crawls), with the special cases of points on the symmetry planes handled separately
  /// (Eberly 2013, "Distance from a point to an ellipse, an ellipsoid, or a hyperellipsoid",
  /// Geometric Tools, which bisects throughout).
  double signed_distance(const Eigen::Vector3d& p) const override;
  bool signed_distance_is_closed_form() const override { return is_sphere(); }
  Eigen::Vector3d closest_surface_point(const Eigen::Vector3d& p) const override;
  Eigen::Vector3d outward_normal(const Eigen::Vector3d& surface_point) const override;
  /// Closed form: the smaller root of a quadratic in the semi-axes' scaled coordinates.
  double surface_crossing(const Eigen::Vector3d& outside, const Eigen::Vector3d& inside) const override;
  double bounding_radius() const override { return semi_axes_.maxCoeff(); }
  Aabb bounding_box() const override { return {-semi_axes_, semi_axes_}; }
  /// h(n) = |diag(a, b, c) n|.
  double support(const Eigen::Vector3d& direction) const override;

  /// V = 4/3 pi abc; S = V/5 diag(a^2, b^2, c^2).
  VolumeMoments volume_moments() const override;
  /// Exact: 4 pi abc R_G(a^-2, b^-2, c^-2) (DLMF 19.33.1) with Carlson's R_G.
  double surface_area() const override;
  /// Exact: pi abc |diag(1/a, 1/b, 1/c) n|.
  double projected_area(const Eigen::Vector3d& direction) const override;
  /// Exact: on the circle m(phi) the shadow is pi abc sqrt(Q(phi)) with Q a quadratic form of
  /// eigenvalues l1 >= l2, whose mean is (2/pi) sqrt(l1) E(sqrt(1 - l2/l1)).
  double mean_projected_area_perpendicular(const Eigen::Vector3d& axis) const override;
  /// Sphere: Fibonacci lattice. Otherwise: Lloyd clustering of a cubed-sphere triangulation with
  /// edges <= h/3, seeds projected exactly onto the ellipsoid, exact normals.
  SurfaceMarkers surface_markers(double spacing) const override;

 private:
  Eigen::Vector3d semi_axes_;
  std::string kind_;
};

}  // namespace settle::body
