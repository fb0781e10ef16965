#pragma once
// Rectangular box with full edge lengths (a, b, c) along body x, y, z, centred at the origin.
#include "body/shape.hpp"

namespace settle::body {

class Cuboid final : public Shape {
 public:
  /// Edge lengths finite and > 0 (settle::InputError otherwise).
  explicit Cuboid(const Eigen::Vector3d& size);

  const Eigen::Vector3d& size() const { return size_; }

  std::string kind() const override { return "cuboid"; }
  bool contains(const Eigen::Vector3d& p) const override;
  bool contains_is_closed_form() const override { return true; }
  /// Exact box distance: |max(q, 0)| + min(max_i q_i, 0) with q = |p| - size/2.
  double signed_distance(const Eigen::Vector3d& p) const override;
  bool signed_distance_is_closed_form() const override { return true; }
  Eigen::Vector3d closest_surface_point(const Eigen::Vector3d& p) const override;
  Eigen::Vector3d outward_normal(const Eigen::Vector3d& surface_point) const override;
  double bounding_radius() const override { return 0.5 * size_.norm(); }
  Aabb bounding_box() const override { return {-0.5 * size_, 0.5 * size_}; }
  /// h(n) = sum_i |n_i| size_i / 2.
  double support(const Eigen::Vector3d& direction) const override;

  /// V = abc; S = V/12 diag(a^2, b^2, c^2).
  VolumeMoments volume_moments() const override;
  double surface_area() const override;
  /// Exact (Cauchy): |n_x| bc + |n_y| ac + |n_z| ab.
  double projected_area(const Eigen::Vector3d& direction) const override;
  /// Exact: (2/pi) (bc s_x + ac s_y + ab s_z), s_i = |e_i perpendicular to the axis|.
  double mean_projected_area_perpendicular(const Eigen::Vector3d& axis) const override;
  /// Each face is a grid of round(edge/h) x round(edge/h) equal cells (at least 1 x 1), one
  /// marker at each cell centre carrying the cell's exact area.
  SurfaceMarkers surface_markers(double spacing) const override;

 private:
  Eigen::Vector3d size_;
};

}  // namespace settle::body
