#pragma once
// Helpers shared by the body tests: simple meshes built here (independently of the library's
// surface generators), random surface samples and the marker-quality measurements.
#include <array>
#include <cmath>
#include <map>
#include <numbers>
#include <random>
#include <vector>

#include <Eigen/Dense>

#include "body/shape.hpp"
#include "body/surface_markers.hpp"
#include "body/triangle_mesh.hpp"

namespace settle::body::testing {

/// Box [-size/2, size/2] rotated by `rotation` and moved to `centre`: 12 outward triangles.
inline TriangleMesh box_mesh(const Eigen::Vector3d& size, const Eigen::Vector3d& centre = Eigen::Vector3d::Zero(),
                             const Eigen::Matrix3d& rotation = Eigen::Matrix3d::Identity()) {
  TriangleMesh mesh;
  for (int i = 0; i < 8; ++i) {
    const Eigen::Vector3d corner((i & 4 ? 0.5 : -0.5) * size.x(), (i & 2 ? 0.5 : -0.5) * size.y(),
                                 (i & 1 ? 0.5 : -0.5) * size.z());
    mesh.vertices.push_back(centre + rotation * corner);
  }
  // Corner index 4x + 2y + z; faces counterclockwise seen from outside.
  mesh.triangles = {{0, 1, 3}, {0, 3, 2}, {4, 6, 7}, {4, 7, 5}, {0, 4, 5}, {0, 5, 1},
                    {2, 3, 7}, {2, 7, 6}, {0, 2, 6}, {0, 6, 4}, {1, 5, 7}, {1, 7, 3}};
  return mesh;
}

/// Icosahedron subdivided `levels` times, vertices pushed onto the sphere of radius r.
inline TriangleMesh icosphere(int levels, double radius) {
  const double t = (1.0 + std::sqrt(5.0)) / 2.0;
  TriangleMesh mesh;
  mesh.vertices = {{-1, t, 0},  {1, t, 0},  {-1, -t, 0}, {1, -t, 0}, {0, -1, t},  {0, 1, t},
                   {0, -1, -t}, {0, 1, -t}, {t, 0, -1},  {t, 0, 1},  {-t, 0, -1}, {-t, 0, 1}};
  mesh.triangles = {{0, 11, 5},  {0, 5, 1},  {0, 1, 7},  {0, 7, 10}, {0, 10, 11}, {1, 5, 9}, {5, 11, 4},
                    {11, 10, 2}, {10, 7, 6}, {7, 1, 8},  {3, 9, 4},  {3, 4, 2},   {3, 2, 6}, {3, 6, 8},
                    {3, 8, 9},   {4, 9, 5},  {2, 4, 11}, {6, 2, 10}, {8, 6, 7},   {9, 8, 1}};
  for (auto& v : mesh.vertices) v.normalize();
  for (int level = 0; level < levels; ++level) {
    std::map<std::pair<int, int>, int> midpoint;
    auto middle = [&](int a, int b) {
      const auto key = std::minmax(a, b);
      const auto it = midpoint.find(key);
      if (it != midpoint.end()) return it->second;
      mesh.vertices.push_back((mesh.vertices[a] + mesh.vertices[b]).normalized());
      return midpoint[key] = static_cast<int>(mesh.vertices.size()) - 1;
    };
    std::vector<std::array<int, 3>> finer;
    for (const auto& [a, b, c] : mesh.triangles) {
      const int ab = middle(a, b), bc = middle(b, c), ca = middle(c, a);
      finer.push_back({a, ab, ca});
      finer.push_back({b, bc, ab});
      finer.push_back({c, ca, bc});
      finer.push_back({ab, bc, ca});
    }
    mesh.triangles = std::move(finer);
  }
  for (auto& v : mesh.vertices) v *= radius;
  return mesh;
}

/// Random unit vector (uniform on the sphere).
inline Eigen::Vector3d random_unit(std::mt19937_64& rng) {
  std::normal_distribution<double> normal;
  Eigen::Vector3d v(normal(rng), normal(rng), normal(rng));
  return v.normalized();
}

/// Uniform random point in the box [-half, half].
inline Eigen::Vector3d random_in_box(std::mt19937_64& rng, const Eigen::Vector3d& half) {
  std::uniform_real_distribution<double> u(-1.0, 1.0);
  return Eigen::Vector3d(u(rng), u(rng), u(rng)).cwiseProduct(half);
}

/// Random points on a mesh's surface, uniform in area.
inline std::vector<Eigen::Vector3d> random_points_on_mesh(const TriangleMesh& mesh, int count, std::mt19937_64& rng) {
  std::vector<double> cumulative;
  double total = 0.0;
  for (std::size_t t = 0; t < mesh.triangles.size(); ++t) {
    total += triangle_vector_area(mesh, static_cast<int>(t)).norm();
    cumulative.push_back(total);
  }
  std::uniform_real_distribution<double> u(0.0, 1.0);
  std::vector<Eigen::Vector3d> points;
  for (int i = 0; i < count; ++i) {
    const auto it = std::lower_bound(cumulative.begin(), cumulative.end(), u(rng) * total);
    const auto& tri = mesh.triangles[std::min<std::size_t>(it - cumulative.begin(), mesh.triangles.size() - 1)];
    double r1 = u(rng), r2 = u(rng);
    if (r1 + r2 > 1.0) r1 = 1.0 - r1, r2 = 1.0 - r2;
    const Eigen::Vector3d& a = mesh.vertices[tri[0]];
    points.push_back(a + r1 * (mesh.vertices[tri[1]] - a) + r2 * (mesh.vertices[tri[2]] - a));
  }
  return points;
}

/// What the marker requirements are checked on (see MarkerQualityTest in the shape tests):
///  - area_error: sum of marker areas / exact surface area - 1;
///  - max_nearest / h: the largest distance from a marker to its nearest neighbour;
///  - max_coverage / h: the largest distance from a random surface point to its nearest marker;
///  - max_off_surface / h: the largest |signed distance| of a marker.
struct MarkerQuality {
  std::size_t count = 0;
  double area_error = 0.0;
  double min_nearest = 0.0, max_nearest = 0.0;
  double max_coverage = 0.0;
  double max_off_surface = 0.0;
  double min_area = 0.0, max_area = 0.0, mean_area = 0.0;  ///< in units of h^2
  double max_normal_error = 0.0;                           ///< |n - outward_normal| (smooth shapes)
  double vector_area_sum = 0.0;                            ///< |sum a_i n_i| / total area
};

inline MarkerQuality measure_markers(const Shape& shape, const SurfaceMarkers& markers,
                                     const std::vector<Eigen::Vector3d>& surface_samples) {
  const double h = markers.spacing;
  MarkerQuality q;
  q.count = markers.size();
  q.area_error = markers.total_area() / shape.surface_area() - 1.0;
  const std::vector<double> nearest = nearest_marker_distances(markers);
  q.min_nearest = *std::min_element(nearest.begin(), nearest.end()) / h;
  q.max_nearest = *std::max_element(nearest.begin(), nearest.end()) / h;
  const std::vector<double> coverage = distances_to_nearest_marker(markers, surface_samples);
  q.max_coverage = *std::max_element(coverage.begin(), coverage.end()) / h;
  Eigen::Vector3d vector_area = Eigen::Vector3d::Zero();
  for (std::size_t i = 0; i < markers.size(); ++i) {
    q.max_off_surface = std::max(q.max_off_surface, std::abs(shape.signed_distance(markers.positions[i])) / h);
    vector_area += markers.areas[i] * markers.normals[i];
  }
  q.vector_area_sum = vector_area.norm() / markers.total_area();
  q.min_area = *std::min_element(markers.areas.begin(), markers.areas.end()) / (h * h);
  q.max_area = *std::max_element(markers.areas.begin(), markers.areas.end()) / (h * h);
  q.mean_area = markers.total_area() / static_cast<double>(markers.size()) / (h * h);
  return q;
}

}  // namespace settle::body::testing
