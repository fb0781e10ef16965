#pragma once
// The common interface of every particle shape (analytic or mesh).
//
// Body frame: the shape's own frame with its origin at the centroid (docs/architecture.md, "Frames and
// attitude"): a
// spheroid's and a cylinder's symmetry axis is body z; an ellipsoid's semi_axes and a cuboid's
// size lie along body x, y, z; a mesh keeps its file's axes with the origin moved to the
// centroid. Every point and direction passed to or returned by a Shape is in the body frame,
// lengths in the unit of the input (SI metres for cases).
//
// Shapes are immutable after construction and all queries are const and thread-safe, so the
// immersed-boundary code may call signed_distance from many threads.
#include <span>
#include <string>
#include <vector>

#include <Eigen/Dense>

#include "body/mass_properties.hpp"

namespace settle::body {

/// Axis-aligned bounding box in the body frame.
struct Aabb {
  Eigen::Vector3d lower = Eigen::Vector3d::Zero();
  Eigen::Vector3d upper = Eigen::Vector3d::Zero();
};

/// Lagrangian surface markers in the body frame: points on the surface, their unit outward
/// normals and the surface area each one represents (the areas tile the surface, so they sum to
/// its area). `spacing` is the requested nominal spacing h; the mean area per marker is about h^2.
struct SurfaceMarkers {
  std::vector<Eigen::Vector3d> positions;
  std::vector<Eigen::Vector3d> normals;
  std::vector<double> areas;
  double spacing = 0.0;

  std::size_t size() const { return positions.size(); }
  double total_area() const;
  void append(const Eigen::Vector3d& position, const Eigen::Vector3d& normal, double area);
};

/// Abstract particle shape. Analytic shapes implement every query in closed form where one
/// exists; each implementation documents the accuracy of the rest.
class Shape {
 public:
  virtual ~Shape() = default;

  /// "sphere", "spheroid", "ellipsoid", "cylinder", "cuboid", "superellipsoid" or "mesh".
  virtual std::string kind() const = 0;

  /// Exact inside test (points on the surface count as inside).
  virtual bool contains(const Eigen::Vector3d& p) const = 0;
  /// True when contains is a closed form costing a few arithmetic operations or powers (no tree
  /// walk): the momentum exchange then asks it for every cell near the body, and otherwise first
  /// asks a table of the signed distance (body::DistanceTable::certain_side).
  virtual bool contains_is_closed_form() const { return false; }
  /// contains(p), given a point `reference` near p whose side is known (`reference_inside`): a
  /// mesh counts the crossings between them instead of searching its nearest triangle. The default
  /// asks contains.
  virtual bool contains_from(const Eigen::Vector3d& p, const Eigen::Vector3d& /*reference*/,
                             bool /*reference_inside*/) const {
    return contains(p);
  }
  /// Signed distance to the surface, negative inside.
  virtual double signed_distance(const Eigen::Vector3d& p) const = 0;
  /// True when signed_distance is a closed form costing a few arithmetic operations (no root
  /// search, no tree walk): callers then need no tabulated distance (body::DistanceTable).
  virtual bool signed_distance_is_closed_form() const { return false; }
  /// The point of the surface nearest to p (projection onto the surface).
  virtual Eigen::Vector3d closest_surface_point(const Eigen::Vector3d& p) const = 0;
  /// Unit outward normal at a surface point (at edges and corners: one valid choice).
  virtual Eigen::Vector3d outward_normal(const Eigen::Vector3d& surface_point) const = 0;
  /// Where the segment from `outside` to `inside` meets the surface, as the fraction t in [0, 1]
  /// of the way (0 when `outside` is not outside, 1 when `inside` is not inside). The default
  /// finds the root of signed_distance along the segment (a lattice link of the momentum exchange,
  /// short against the body: one crossing) to 1e-9 of its length; ellipsoids (closed form),
  /// superellipsoids (Newton's method on the gauge) and meshes (the triangles' hits) override it.
  virtual double surface_crossing(const Eigen::Vector3d& outside, const Eigen::Vector3d& inside) const;
  /// surface_crossing of the segments from one `outside` point to each of `insides`, into `t` (the
  /// links of one fluid cell). The default asks surface_crossing for each; a mesh gathers the
  /// triangles near `outside` once.
  virtual void surface_crossings(const Eigen::Vector3d& outside, std::span<const Eigen::Vector3d> insides,
                                 std::span<double> t) const;

  /// Largest distance of a body point from the centroid.
  virtual double bounding_radius() const = 0;
  virtual Aabb bounding_box() const = 0;
  /// Support function h(n) = max over the body of n . x, for a unit direction n.
  virtual double support(const Eigen::Vector3d& direction) const = 0;

  /// Volume, centroid (input frame) and second moment about the centroid.
  virtual VolumeMoments volume_moments() const = 0;
  virtual double surface_area() const = 0;
  /// Area of the shadow of the body on a plane normal to the unit direction.
  virtual double projected_area(const Eigen::Vector3d& direction) const = 0;
  /// Mean of projected_area over all directions perpendicular to the unit direction `axis`
  /// (the "mean projected longitudinal cross-sectional area" of Hoelzer and Sommerfeld 2008
  /// when `axis` is the flow direction).
  virtual double mean_projected_area_perpendicular(const Eigen::Vector3d& axis) const = 0;

  /// Markers of nominal spacing h > 0 (see each shape for the construction).
  virtual SurfaceMarkers surface_markers(double spacing) const = 0;

  /// Remarks about how the shape was built (e.g. a mesh whose orientation was reversed).
  virtual std::vector<std::string> notes() const { return {}; }

  /// Mass properties for a uniform density.
  MassProperties mass_properties(double density) const;
  double volume() const { return volume_moments().volume; }
  /// Diameter of the sphere of equal volume, (6 V / pi)^(1/3).
  double equivalent_diameter() const;
  /// Width of the body along a unit direction, h(n) + h(-n).
  double width(const Eigen::Vector3d& direction) const;
};

/// Checks a marker spacing request against the body: throws settle::InputError naming
/// `what` when spacing is not finite and > 0, or would give fewer than 4 or more than a
/// million markers for the given surface area.
void validate_marker_spacing(double spacing, double surface_area, const char* what = "marker spacing");

/// A unit vector from a direction, or settle::InputError naming `what` for a zero or
/// non-finite vector.
Eigen::Vector3d unit_direction(const Eigen::Vector3d& direction, const char* what = "direction");

}  // namespace settle::body
