#include "body/cube_sphere.hpp"

#include <algorithm>
#include <cmath>
#include <numbers>
#include <unordered_map>

namespace settle::body {
namespace {

double grid_coordinate(int index, int cells) {
  if (index == 0) return -1.0;
  if (index == cells) return 1.0;  // tan(pi/4) rounds below 1; the cube's faces must meet exactly
  return std::tan(0.25 * std::numbers::pi * (2.0 * index / cells - 1.0));
}

class LatticeVertices {
 public:
  LatticeVertices(const std::array<int, 3>& cells, const RadialMap& to_surface, TriangleMesh& mesh)
      : cells_(cells), to_surface_(to_surface), mesh_(mesh) {}

  int index(const std::array<int, 3>& ijk) {
    const std::uint64_t key = (static_cast<std::uint64_t>(ijk[0]) << 42) | (static_cast<std::uint64_t>(ijk[1]) << 21) |
                              static_cast<std::uint64_t>(ijk[2]);
    const auto [it, inserted] = ids_.try_emplace(key, static_cast<int>(mesh_.vertices.size()));
    if (inserted) {
      const Eigen::Vector3d u(grid_coordinate(ijk[0], cells_[0]), grid_coordinate(ijk[1], cells_[1]),
                              grid_coordinate(ijk[2], cells_[2]));
      mesh_.vertices.push_back(to_surface_(u));
    }
    return it->second;
  }

 private:
  std::array<int, 3> cells_;
  const RadialMap& to_surface_;
  TriangleMesh& mesh_;
  std::unordered_map<std::uint64_t, int> ids_;
};

// Longest grid edge along each lattice axis. Edges along axis a lie on the lattice lines whose
// other two indices (jb, jc) are on the boundary of [0, n_b] x [0, n_c] (the cube's surface).
Eigen::Vector3d longest_grid_edges(const std::array<int, 3>& cells, const RadialMap& to_surface) {
  Eigen::Vector3d longest = Eigen::Vector3d::Zero();
  for (int a = 0; a < 3; ++a) {
    const int b = (a + 1) % 3, c = (a + 2) % 3;
    for (int jb = 0; jb <= cells[b]; ++jb) {
      for (int jc = 0; jc <= cells[c]; ++jc) {
        const bool on_surface = jb == 0 || jb == cells[b] || jc == 0 || jc == cells[c];
        if (!on_surface) continue;
        Eigen::Vector3d u;
        u(b) = grid_coordinate(jb, cells[b]);
        u(c) = grid_coordinate(jc, cells[c]);
        u(a) = -1.0;
        Eigen::Vector3d previous = to_surface(u);
        for (int i = 1; i <= cells[a]; ++i) {
          u(a) = grid_coordinate(i, cells[a]);
          const Eigen::Vector3d next = to_surface(u);
          longest(a) = std::max(longest(a), (next - previous).norm());
          previous = next;
        }
      }
    }
  }
  return longest;
}

// Grid intervals for a wanted (real) count: at least 2, and below 2^21, the largest index the
// vertex keys of LatticeVertices hold (21 bits per axis).
int cell_count(double wanted) {
  constexpr double kLargest = (1 << 21) - 1;
  return static_cast<int>(std::clamp(std::ceil(wanted), 2.0, kLargest));
}

// Triangles of cube_sphere_mesh: two per grid quad on each of the 6 faces.
double triangle_count(const std::array<int, 3>& cells) {
  const double x = cells[0], y = cells[1], z = cells[2];
  return 4.0 * (x * y + y * z + z * x);
}

}  // namespace

TriangleMesh cube_sphere_mesh(const std::array<int, 3>& cells, const RadialMap& to_surface) {
  TriangleMesh mesh;
  LatticeVertices lattice(cells, to_surface, mesh);
  for (int k = 0; k < 3; ++k) {
    const int a = (k + 1) % 3, b = (k + 2) % 3;  // e_a x e_b = e_k
    for (int side = 0; side < 2; ++side) {
      for (int i = 0; i < cells[a]; ++i) {
        for (int j = 0; j < cells[b]; ++j) {
          auto corner = [&](int di, int dj) {
            std::array<int, 3> ijk{};
            ijk[k] = side ? cells[k] : 0;
            ijk[a] = i + di;
            ijk[b] = j + dj;
            return lattice.index(ijk);
          };
          // Counterclockwise about +e_k; reversed on the face facing -e_k.
          std::array<int, 4> quad{corner(0, 0), corner(1, 0), corner(1, 1), corner(0, 1)};
          if (!side) std::reverse(quad.begin(), quad.end());
          const auto& v = mesh.vertices;
          if ((v[quad[0]] - v[quad[2]]).squaredNorm() <= (v[quad[1]] - v[quad[3]]).squaredNorm()) {
            mesh.triangles.push_back({quad[0], quad[1], quad[2]});
            mesh.triangles.push_back({quad[0], quad[2], quad[3]});
          } else {
            mesh.triangles.push_back({quad[0], quad[1], quad[3]});
            mesh.triangles.push_back({quad[1], quad[2], quad[3]});
          }
        }
      }
    }
  }
  return mesh;
}

TriangleMesh cube_sphere_mesh_with_max_edge(const Eigen::Vector3d& half_extents, double max_edge,
                                            const RadialMap& to_surface, double max_triangles) {
  std::array<int, 3> cells{};
  for (int i = 0; i < 3; ++i) cells[i] = cell_count(1.6 * half_extents(i) / max_edge);
  for (int attempt = 0; attempt < 4 && triangle_count(cells) <= max_triangles; ++attempt) {
    const Eigen::Vector3d longest = longest_grid_edges(cells, to_surface);
    bool fine_enough = true;
    for (int i = 0; i < 3; ++i) {
      if (longest(i) > max_edge) {
        fine_enough = false;
        cells[i] = cell_count(cells[i] * longest(i) / max_edge * 1.02);
      }
    }
    if (fine_enough) break;
  }
  if (const double count = triangle_count(cells); count > max_triangles) {
    // The count is quadratic in the cells: one factor sqrt(max / count) on every axis.
    const double shrink = std::sqrt(max_triangles / count);
    for (int& c : cells) c = std::max(2, static_cast<int>(std::floor(c * shrink)));
  }
  return cube_sphere_mesh(cells, to_surface);
}

}  // namespace settle::body
