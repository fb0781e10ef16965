#pragma once
// Circular cylinder of diameter d and length L, axis along body z, centred at the origin.
// A disk is a short cylinder (L < d).
#include "body/shape.hpp"

namespace settle::body {

class Cylinder final : public Shape {
 public:
  /// diameter and length finite and > 0 (settle::InputError otherwise).
  Cylinder(double diameter, double length);

  double radius() const { return radius_; }
  double length() const { return length_; }

  std::string kind() const override { return "cylinder"; }
  bool contains(const Eigen::Vector3d& p) const override;
  bool contains_is_closed_form() const override { return true; }
  /// Exact: the distance to the rectangle |rho| <= R, |z| <= L/2 in the meridian plane.
  double signed_distance(const Eigen::Vector3d& p) const override;
  bool signed_distance_is_closed_form() const override { return true; }
  Eigen::Vector3d closest_surface_point(const Eigen::Vector3d& p) const override;
  Eigen::Vector3d outward_normal(const Eigen::Vector3d& surface_point) const override;
  double bounding_radius() const override;
  Aabb bounding_box() const override;
  /// h(n) = R |n_xy| + L/2 |n_z|.
  double support(const Eigen::Vector3d& direction) const override;

  /// V = pi R^2 L; S = V diag(R^2/4, R^2/4, L^2/12).
  VolumeMoments volume_moments() const override;
  double surface_area() const override;
  /// Exact: pi R^2 |n_z| + 2 R L sqrt(1 - n_z^2) (two half-ellipses and a rectangle).
  double projected_area(const Eigen::Vector3d& direction) const override;
  /// Exact: with s = |axis component perpendicular to z|, the mean over the circle is
  /// 2 R^2 s + (4 R L / pi) E(s).
  double mean_projected_area_perpendicular(const Eigen::Vector3d& axis) const override;
  /// Regular grids with exact areas: each cap is a central disk of radius D/2 plus n rings of
  /// width D = R / (n + 1/2) (n = round(R/h - 1/2)), ring k holding round(2 pi k) markers of
  /// equal area, successive rings turned by the golden angle; the mantle is a grid of
  /// round(2 pi R / h) x round(L / h) equal cells with a marker at each centre.
  SurfaceMarkers surface_markers(double spacing) const override;

 private:
  double radius_;
  double length_;
};

}  // namespace settle::body
