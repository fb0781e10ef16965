#pragma once
// A solid bounded by a closed triangle mesh (e.g. read from STL). The body frame keeps the
// input's axes with the origin moved to the centroid.
#include <filesystem>
#include <memory>

#include "body/shape.hpp"
#include "body/triangle_bvh.hpp"
#include "body/triangle_mesh.hpp"

namespace settle::body {

class MeshShape final : public Shape {
 public:
  /// Validates and adopts a mesh given in the input frame. Refused with settle::InputError
  /// (message starting with `source`): everything check_closed_and_oriented refuses, a volume
  /// that is zero to 1e-10 of the bounding-box diagonal cubed, a mesh made of several
  /// closed shells of which some are oriented inward (an inverted shell or a cavity: the body
  /// would be ambiguous), and a mesh so large or small that its volume or moments of inertia
  /// overflow or underflow double precision (sizes beyond about 1e61 or below about 1e-61). A mesh
  /// whose shells are all oriented inward (negative volume) is reversed, and notes() says so.
  /// Self-intersections are not detected.
  MeshShape(TriangleMesh mesh, std::string source);

  /// The mesh in the body frame (origin at the centroid).
  const TriangleMesh& body_mesh() const { return mesh_; }
  bool is_convex() const { return convex_; }

  std::string kind() const override { return "mesh"; }
  bool contains(const Eigen::Vector3d& p) const override { return signed_distance(p) <= 0.0; }
  /// Exact: the side the last crossing of the segment from `reference` to p leads to (TriangleBvh::
  /// segment_hits, no crossing: the reference's side); contains(p) where that is not clear (p on
  /// the surface within the hit margin, triangles at the first or last crossing that disagree, a
  /// first crossing that contradicts `reference_inside`).
  bool contains_from(const Eigen::Vector3d& p, const Eigen::Vector3d& reference, bool reference_inside) const override;
  /// Exact distance to the mesh (BVH); the sign from the angle-weighted pseudonormal of the
  /// nearest face, edge or vertex (Baerentzen and Aanaes 2005, IEEE TVCG 11(3) 243-253,
  /// doi:10.1109/TVCG.2005.49), which is correct for closed, consistently oriented meshes.
  double signed_distance(const Eigen::Vector3d& p) const override;
  Eigen::Vector3d closest_surface_point(const Eigen::Vector3d& p) const override;
  /// The pseudonormal of the nearest feature (the face normal inside a face).
  Eigen::Vector3d outward_normal(const Eigen::Vector3d& surface_point) const override;
  /// Exact: the segment's first hit on the mesh (TriangleBvh::segment_hits), when its first and
  /// last hits both enter the solid (then `outside` is outside and `inside` inside, the contract's
  /// ordinary case); a segment that crosses the surface three times gets its first crossing, the
  /// wall nearest the fluid. Anything else (no hit, a first or last crossing through an edge or
  /// vertex whose triangles disagree, more than 16 hits) takes the base class's root finder.
  double surface_crossing(const Eigen::Vector3d& outside, const Eigen::Vector3d& inside) const override;
  /// As surface_crossing, with the tree walked once for all the segments (TriangleBvh::leaves_near).
  void surface_crossings(const Eigen::Vector3d& outside, std::span<const Eigen::Vector3d> insides,
                         std::span<double> t) const override;
  double bounding_radius() const override { return bounding_radius_; }
  Aabb bounding_box() const override { return box_; }
  /// Exact: max over vertices of n . v.
  double support(const Eigen::Vector3d& direction) const override;

  /// Exact polyhedral moments (polyhedron_moments); centroid in the input frame.
  VolumeMoments volume_moments() const override { return moments_; }
  double surface_area() const override { return area_; }
  /// Convex meshes: exact (Cauchy). Otherwise: silhouette measured on 4096 scanlines
  /// (projected_area.hpp; relative error below ~1e-5).
  double projected_area(const Eigen::Vector3d& direction) const override;
  /// Convex meshes: exact. Otherwise: mean of 128 shadows (1024 scanlines each) evenly spaced
  /// in angle; the angular rule dominates the error (measured 5e-5 relative for an L-shaped
  /// prism in tests/body/test_mesh_shape.cpp).
  double mean_projected_area_perpendicular(const Eigen::Vector3d& axis) const override;
  /// Lloyd clustering of the mesh's triangles cut to edges <= h/3, seeds projected onto the
  /// mesh, normals the clusters' mean normals.
  SurfaceMarkers surface_markers(double spacing) const override;
  std::vector<std::string> notes() const override { return notes_; }

 private:
  Eigen::Vector3d feature_normal(const TriangleBvh::Hit& hit) const;

  TriangleMesh mesh_;
  VolumeMoments moments_;
  double area_ = 0.0;
  double bounding_radius_ = 0.0;
  Aabb box_;
  bool convex_ = false;
  TriangleBvh bvh_;
  std::vector<Eigen::Vector3d> face_normals_;
  std::vector<std::array<Eigen::Vector3d, 3>> edge_normals_;  ///< per triangle, per edge
  std::vector<Eigen::Vector3d> vertex_normals_;
  std::vector<std::string> notes_;
};

/// Reads an STL file, multiplies its coordinates by `scale` (> 0, finite) and builds the shape.
std::unique_ptr<MeshShape> load_mesh_shape(const std::filesystem::path& path, double scale = 1.0);

}  // namespace settle::body
