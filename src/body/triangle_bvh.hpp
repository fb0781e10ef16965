#pragma once
// Closest-point queries on a triangle mesh through a bounding-volume hierarchy of axis-aligned
// boxes (median split on the longest axis, at most 4 triangles per leaf). A query descends the
// nearer child first and prunes boxes farther than the best triangle found, so it costs
// O(log n) triangle tests for points near the surface.
#include <array>
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

 private:
  struct Node {
    Eigen::Vector3d lower = Eigen::Vector3d::Zero();
    Eigen::Vector3d upper = Eigen::Vector3d::Zero();
    int first = 0;  ///< leaf: first triangle slot; inner: index of the right child
    int count = 0;  ///< leaf: number of triangles; inner: 0 (the left child follows the node)
  };
  int build(std::vector<int>& order, std::vector<Eigen::Vector3d>& centres, int begin, int end);

  std::vector<Node> nodes_;
  std::vector<std::array<Eigen::Vector3d, 3>> corners_;  ///< triangles in leaf order
  std::vector<int> triangle_ids_;                        ///< leaf order -> mesh triangle index
};

}  // namespace settle::body
