#pragma once
// A moving sphere as an obstacle of solid cells with Bouzidi links (lbm::Obstacle), in global
// lattice coordinates, and a block's part of it: what tests/lbm/test_halo_obstacle.cpp (one process)
// and tests/parallel/test_mpi_halo.cpp (across MPI ranks) set on the unsplit lattice and its blocks.
#include <array>
#include <cmath>
#include <span>

#include <Eigen/Core>

#include "lbm/decomposition.hpp"
#include "lbm/solver.hpp"

namespace settle::test::halo {

// A sphere moving rigidly, in global lattice coordinates: its solid cells and the links of the
// fluid cells next to it, with the wall's fraction q along each link and its velocity there.
struct Sphere {
  Eigen::Vector3d centre;
  double radius;
  Eigen::Vector3d velocity{0.01, -0.006, 0.02};
  Eigen::Vector3d spin{0.002, 0.003, -0.001};

  bool inside(const std::array<int, 3>& c) const {
    return (Eigen::Vector3d(c[0], c[1], c[2]) - centre).norm() < radius;
  }
  // The first crossing of the sphere from x along c (0 < q <= 1).
  double fraction(const Eigen::Vector3d& x, const Eigen::Vector3d& c) const {
    const Eigen::Vector3d d = x - centre;
    const double a = c.squaredNorm(), b = d.dot(c), e = d.squaredNorm() - radius * radius;
    return (-b - std::sqrt(b * b - a * e)) / a;
  }
};

inline lbm::Obstacle whole_obstacle(const Sphere& s, const lbm::SolverConfig& cfg,
                                    std::span<const std::array<int, 3>> velocities) {
  lbm::Obstacle o;
  for (int z = 0; z < cfg.nz; ++z)
    for (int y = 0; y < cfg.ny; ++y)
      for (int x = 0; x < cfg.nx; ++x) {
        const std::array<int, 3> cell{x, y, z};
        if (s.inside(cell)) {
          o.solid_cells.push_back(cell);
          continue;
        }
        for (int i = 1; i < static_cast<int>(velocities.size()); ++i) {
          const auto& c = velocities[static_cast<std::size_t>(i)];
          if (!s.inside({x + c[0], y + c[1], z + c[2]})) continue;
          const Eigen::Vector3d p(x, y, z), ci(c[0], c[1], c[2]);
          const double q = s.fraction(p, ci);
          const Eigen::Vector3d wall = p + q * ci;
          o.links.push_back({cell, i, q, s.velocity + s.spin.cross(wall - s.centre)});
        }
      }
  return o;
}

// Rank r's part: its cells and the ghosts of adjacent blocks (block coordinates), its links.
inline lbm::Obstacle block_obstacle(const lbm::Obstacle& whole, const lbm::BlockSplit& split, int r) {
  const std::array<int, 3> o = split.offset(r), n = split.extent(r);
  lbm::Obstacle part;
  part.rule = whole.rule;
  for (const auto& c : whole.solid_cells) {
    bool near = true, far = true;
    std::array<int, 3> local{};
    for (std::size_t a = 0; a < 3; ++a) {
      local[a] = c[a] - o[a];
      near = near && local[a] >= -1 && local[a] <= n[a];
      far = far && local[a] >= -2 && local[a] <= n[a] + 1;
    }
    // A ghost beyond a face of the lattice would be refused: the sphere stays clear of them.
    if (near) {
      part.solid_cells.push_back(local);
    } else if (far && whole.rule == lbm::WallRule::quadratic) {
      part.far_solid_cells.push_back(local);
    }
  }
  for (const lbm::WallLink& l : whole.links) {
    if (split.owner(l.cell) != r) continue;
    lbm::WallLink local = l;
    for (std::size_t a = 0; a < 3; ++a) local.cell[a] -= o[a];
    part.links.push_back(local);
  }
  return part;
}

}  // namespace settle::test::halo
