#pragma once
// Closest-point queries on a triangle mesh through a bounding-volume hierarchy of axis-aligned
// boxes (median split on the longest axis, at most 4 triangles per leaf). A query descends the
// nearer child first and prunes boxes farther than the best triangle found, so it costs
// O(log n) triangle tests for points near the surface.
#include <array>
#include <span>
#include <vector>

#include <Eigen/Dense>

#include "body/triangle_mesh.hpp"

namespace settle::body {

/// Which part of a triangle a closest point lies on: its interior, edge k (from vertex k to
/// vertex k+1 mod 3) or vertex k.
struct TriangleFeature {
  enum class Kind { face, edge, vertex };
  Kind kind = Kind::face;
  int index = 0;
};

/// The closest point of a triangle (a, b, c) to p and the feature it lies on, by the Voronoi
/// regions of the triangle's vertices and edges (Ericson 2005, Real-Time Collision Detection,
/// section 5.1.5).
Eigen::Vector3d closest_point_on_triangle(const Eigen::Vector3d& p, const Eigen::Vector3d& a, const Eigen::Vector3d& b,
                                          const Eigen::Vector3d& c, TriangleFeature* feature = nullptr);

class TriangleBvh {
 public:
  struct Hit {
    double distance_squared = 0.0;
    int triangle = -1;  ///< index into the mesh the tree was built from
    TriangleFeature feature;
    Eigen::Vector3d point = Eigen::Vector3d::Zero();
  };

  TriangleBvh() = default;
  explicit TriangleBvh(const TriangleMesh& mesh);

  /// The closest point of the mesh surface to p (the mesh must have triangles).
  Hit closest(const Eigen::Vector3d& p) const;

  /// Where the segment from `from` to `to` meets a triangle: t, the fraction of the way, and
  /// whether it enters the triangle's back side (its direction against the normal of the winding,
  /// which for an outward-oriented closed mesh is entering the solid).
  struct SegmentHit {
    double t = 0.0;
    bool entering = false;
  };
  /// The segment's hits, in tree order, written to `hits`; returns their number, or -1 when there
  /// are more than `hits` holds. Möller and Trumbore's test (1997, J. Graphics Tools 2(1) 21-28,
  /// doi:10.1080/10867651.1997.10487468) with a margin of kHitMargin on the barycentric
  /// coordinates and on t, so that a segment through an edge or a vertex is not lost between
  /// triangles by round-off (it is then reported by each of them); a segment in a triangle's plane
  /// meets it nowhere.
  int segment_hits(const Eigen::Vector3d& from, const Eigen::Vector3d& to, std::span<SegmentHit> hits) const;
  static constexpr double kHitMargin = 1e-12;

  /// The leaves whose boxes come within a radius of a point (leaves_near): a segment from that
  /// point no longer than the radius meets only their triangles, so several segments from it (the
  /// links of a lattice cell) share one walk down the tree. Their boxes, relative to the point and
  /// widened by kHitMargin of their size, are stored axis by axis, so that the compiler tests
  /// several at once.
  struct LeavesNear {
    static constexpr int kCapacity = 64;
    Eigen::Vector3d point = Eigen::Vector3d::Zero();
    int count = 0;  ///< -1: more than kCapacity leaves
    std::array<int, kCapacity> node{};
    std::array<std::array<double, kCapacity>, 3> lower{}, upper{};
    std::array<double, kCapacity> distance_squared{};
  };
  void leaves_near(const Eigen::Vector3d& p, double radius, LeavesNear& near) const;
  /// segment_hits of the segment from near.point to `to` (no longer than leaves_near's radius),
  /// on the triangles of `near` only: the same hits as the walk from the root, to the bit (the
  /// boxes only filter; each hit is the same arithmetic on the same triangle).
  int segment_hits(const LeavesNear& near, const Eigen::Vector3d& to, std::span<SegmentHit> hits) const;

 private:
  struct Node {
    Eigen::Vector3d lower = Eigen::Vector3d::Zero();
    Eigen::Vector3d upper = Eigen::Vector3d::Zero();
    int first = 0;  ///< leaf: first triangle slot; inner: index of the right child
    int count = 0;  ///< leaf: number of triangles; inner: 0 (the left child follows the node)
  };
  int build(std::vector<int>& order, std::vector<Eigen::Vector3d>& centres, int begin, int end);
  /// Adds the hits of the segment from `from` along `d` on a leaf's triangles to hits[found...];
  /// false when `hits` is full.
  bool triangle_hits(const Node& leaf, const Eigen::Vector3d& from, const Eigen::Vector3d& d,
                     std::span<SegmentHit> hits, int& found) const;

  // Widens a squared reach, so that a leaf that a segment of exactly that length touches at its
  // end is kept against round-off.
  static constexpr double kReachMargin = 1.0 + 1e-9;

  std::vector<Node> nodes_;
  std::vector<std::array<Eigen::Vector3d, 3>> corners_;  ///< triangles in leaf order
  std::vector<int> triangle_ids_;                        ///< leaf order -> mesh triangle index
};

}  // namespace settle::body
