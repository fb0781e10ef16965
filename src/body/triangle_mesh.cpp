#include "body/triangle_mesh.hpp"

#include <algorithm>
#include <cmath>
#include <limits>
#include <numbers>
#include <tuple>

#include <fmt/core.h>

#include "common/error.hpp"

namespace settle::body {
namespace {

// A triangle whose area is below this fraction of its longest edge squared is a needle or a
// sliver with an undefined normal (aspect ratio beyond 1e10): its orientation, and so the sign
// of the distance near it, would be noise.
constexpr double kDegenerateAreaRatio = 1e-10;

struct HalfEdge {
  int low, high;  // vertex indices, low < high
  int triangle, corner;
  bool forward;  // traversed from low to high
  auto key() const { return std::tie(low, high, triangle); }
};

std::string point_text(const Eigen::Vector3d& p) {
  return fmt::format("({:.9g}, {:.9g}, {:.9g})", p.x(), p.y(), p.z());
}

void check_vertices_and_triangles(const TriangleMesh& mesh, const std::string& source) {
  if (mesh.triangles.empty()) throw InputError(source + ": the mesh contains no triangles");
  for (std::size_t i = 0; i < mesh.vertices.size(); ++i) {
    if (!mesh.vertices[i].allFinite()) throw InputError(fmt::format("{}: vertex {} is not finite", source, i));
  }
  const int vertex_count = static_cast<int>(mesh.vertices.size());
  for (std::size_t t = 0; t < mesh.triangles.size(); ++t) {
    const auto& tri = mesh.triangles[t];
    for (int v : tri) {
      if (v < 0 || v >= vertex_count) {
        throw InputError(
            fmt::format("{}: triangle {} refers to vertex {} (the mesh has {})", source, t + 1, v, vertex_count));
      }
    }
    if (tri[0] == tri[1] || tri[1] == tri[2] || tri[0] == tri[2]) {
      throw InputError(fmt::format("{}: triangle {} has a repeated vertex {}", source, t + 1,
                                   point_text(mesh.vertices[tri[0] == tri[1] || tri[0] == tri[2] ? tri[0] : tri[1]])));
    }
    const Eigen::Vector3d& a = mesh.vertices[tri[0]];
    const Eigen::Vector3d& b = mesh.vertices[tri[1]];
    const Eigen::Vector3d& c = mesh.vertices[tri[2]];
    const double longest = std::max({(b - a).squaredNorm(), (c - b).squaredNorm(), (a - c).squaredNorm()});
    if (0.5 * (b - a).cross(c - a).norm() <= kDegenerateAreaRatio * longest) {
      throw InputError(fmt::format("{}: triangle {} with vertices {}, {}, {} is degenerate (zero area)", source, t + 1,
                                   point_text(a), point_text(b), point_text(c)));
    }
  }
}

std::vector<HalfEdge> sorted_half_edges(const TriangleMesh& mesh) {
  std::vector<HalfEdge> edges;
  edges.reserve(3 * mesh.triangles.size());
  for (std::size_t t = 0; t < mesh.triangles.size(); ++t) {
    for (int k = 0; k < 3; ++k) {
      const int from = mesh.triangles[t][k], to = mesh.triangles[t][(k + 1) % 3];
      edges.push_back({std::min(from, to), std::max(from, to), static_cast<int>(t), k, from < to});
    }
  }
  std::sort(edges.begin(), edges.end(), [](const HalfEdge& x, const HalfEdge& y) { return x.key() < y.key(); });
  return edges;
}

}  // namespace

EdgeNeighbours check_closed_and_oriented(const TriangleMesh& mesh, const std::string& source) {
  check_vertices_and_triangles(mesh, source);
  const std::vector<HalfEdge> edges = sorted_half_edges(mesh);
  EdgeNeighbours neighbours(mesh.triangles.size(), std::array<int, 3>{-1, -1, -1});
  std::size_t begin = 0;
  while (begin < edges.size()) {
    std::size_t end = begin + 1;
    while (end < edges.size() && edges[end].low == edges[begin].low && edges[end].high == edges[begin].high) ++end;
    const HalfEdge& e = edges[begin];
    const std::string where =
        fmt::format("the edge from {} to {}", point_text(mesh.vertices[e.low]), point_text(mesh.vertices[e.high]));
    if (end - begin == 1) {
      throw InputError(
          fmt::format("{}: the mesh is not watertight: {} belongs to triangle {} only", source, where, e.triangle + 1));
    }
    if (end - begin > 2) {
      throw InputError(
          fmt::format("{}: the mesh is not manifold: {} is shared by {} triangles", source, where, end - begin));
    }
    const HalfEdge& f = edges[begin + 1];
    if (e.forward == f.forward) {
      throw InputError(
          fmt::format("{}: inconsistent orientation: triangles {} and {} traverse {} in the same direction "
                      "(every edge must be shared by exactly two triangles running it in opposite directions)",
                      source, e.triangle + 1, f.triangle + 1, where));
    }
    neighbours[e.triangle][e.corner] = f.triangle;
    neighbours[f.triangle][f.corner] = e.triangle;
    begin = end;
  }
  return neighbours;
}

VolumeMoments polyhedron_moments(const TriangleMesh& mesh) {
  Eigen::Vector3d reference = Eigen::Vector3d::Zero();
  for (const auto& v : mesh.vertices) reference += v;
  if (!mesh.vertices.empty()) reference /= static_cast<double>(mesh.vertices.size());

  double volume = 0.0;
  Eigen::Vector3d first = Eigen::Vector3d::Zero();
  Eigen::Matrix3d second = Eigen::Matrix3d::Zero();
  for (const auto& tri : mesh.triangles) {
    const Eigen::Vector3d a = mesh.vertices[tri[0]] - reference;
    const Eigen::Vector3d b = mesh.vertices[tri[1]] - reference;
    const Eigen::Vector3d c = mesh.vertices[tri[2]] - reference;
    const double det = a.dot(b.cross(c));  // 6 x signed volume of the tetrahedron (ref, a, b, c)
    const Eigen::Vector3d sum = a + b + c;
    volume += det / 6.0;
    first += det / 24.0 * sum;
    // int x x^T over the tetrahedron = det/120 (a a^T + b b^T + c c^T + s s^T).
    second += det / 120.0 * (a * a.transpose() + b * b.transpose() + c * c.transpose() + sum * sum.transpose());
  }
  VolumeMoments moments;
  moments.volume = volume;
  if (volume == 0.0) return moments;
  const Eigen::Vector3d centroid = first / volume;
  moments.centroid = reference + centroid;
  moments.second_moment = second - volume * centroid * centroid.transpose();  // parallel-axis shift
  return moments;
}

Eigen::Vector3d triangle_vector_area(const TriangleMesh& mesh, int t) {
  const auto& tri = mesh.triangles[t];
  const Eigen::Vector3d& a = mesh.vertices[tri[0]];
  return 0.5 * (mesh.vertices[tri[1]] - a).cross(mesh.vertices[tri[2]] - a);
}

double mesh_surface_area(const TriangleMesh& mesh) {
  double area = 0.0;
  for (std::size_t t = 0; t < mesh.triangles.size(); ++t)
    area += triangle_vector_area(mesh, static_cast<int>(t)).norm();
  return area;
}

std::array<Eigen::Vector3d, 2> vertex_bounds(const TriangleMesh& mesh) {
  Eigen::Vector3d lo = Eigen::Vector3d::Constant(std::numeric_limits<double>::infinity());
  Eigen::Vector3d hi = -lo;
  for (const auto& v : mesh.vertices) {
    lo = lo.cwiseMin(v);
    hi = hi.cwiseMax(v);
  }
  return {lo, hi};
}

bool is_convex(const TriangleMesh& mesh, const EdgeNeighbours& neighbours) {
  const auto [lo, hi] = vertex_bounds(mesh);
  const double tolerance = 1e-9 * (hi - lo).norm();
  std::vector<char> reached(mesh.triangles.size(), 0);
  std::vector<int> stack{0};
  reached[0] = 1;
  std::size_t reached_count = 1;
  while (!stack.empty()) {
    const int t = stack.back();
    stack.pop_back();
    for (int u : neighbours[t]) {
      if (!reached[u]) {
        reached[u] = 1;
        ++reached_count;
        stack.push_back(u);
      }
    }
  }
  if (reached_count != mesh.triangles.size()) return false;

  for (std::size_t t = 0; t < mesh.triangles.size(); ++t) {
    const Eigen::Vector3d normal = triangle_vector_area(mesh, static_cast<int>(t)).normalized();
    const Eigen::Vector3d& on_plane = mesh.vertices[mesh.triangles[t][0]];
    for (int u : neighbours[t]) {
      for (int v : mesh.triangles[u]) {
        if (normal.dot(mesh.vertices[v] - on_plane) > tolerance) return false;
      }
    }
  }
  return true;
}

double convex_projected_area(const TriangleMesh& mesh, const Eigen::Vector3d& direction) {
  double sum = 0.0;
  for (std::size_t t = 0; t < mesh.triangles.size(); ++t) {
    sum += std::abs(direction.dot(triangle_vector_area(mesh, static_cast<int>(t))));
  }
  return 0.5 * sum;
}

double convex_mean_projected_area_perpendicular(const TriangleMesh& mesh, const Eigen::Vector3d& axis) {
  double sum = 0.0;
  for (std::size_t t = 0; t < mesh.triangles.size(); ++t) {
    const Eigen::Vector3d n = triangle_vector_area(mesh, static_cast<int>(t));
    sum += (n - n.dot(axis) * axis).norm();
  }
  return sum / std::numbers::pi;
}

}  // namespace settle::body
