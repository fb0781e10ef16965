#pragma once
// The moments of a block's cells (density and velocity with Guo's half-force correction, docs/lbm.md)
// read from its populations at either parity: single cells, boxes, whole fields, the extrema of the
// health check and the total mass; and the writes of whole cells: the initial equilibrium and a
// cell's populations. Solid cells read as rest (density 1, velocity 0).
#include <Eigen/Core>
#include <algorithm>
#include <array>
#include <cmath>
#include <limits>
#include <span>
#include <stdexcept>
#include <vector>

#include "lbm/aa_populations.hpp"
#include "lbm/block_geometry.hpp"
#include "lbm/block_obstacle.hpp"
#include "lbm/collision.hpp"
#include "lbm/force_field.hpp"
#include "lbm/solver.hpp"

namespace settle::lbm {

template <Lattice L, class Real>
class BlockFields {
 public:
  static constexpr int Q = L::Q;

  /// The parts of the block whose moments these are; they outlive it.
  BlockFields(const BlockGeometry& geometry, AaPopulations<L, Real>& populations, const ForceField<Real>& forces,
              const BlockObstacle<L, Real>& obstacle, const Eigen::Vector3d& body_force)
      : geometry_(geometry), f_(populations), forces_(forces), obstacle_(obstacle), body_force_(body_force) {}

  /// Every cell at the equilibrium of field's density and velocity, storing rho u - F/2 so that
  /// Guo's velocity (sum f c + F/2) / rho is u (Solver::initialise).
  void initialise(const InitialField& field) {
    const std::array<int, 3>& n = geometry_.extent();
#pragma omp parallel for collapse(2) schedule(static) if (geometry_.threaded())
    for (int z = 0; z < n[2]; ++z) {
      for (int y = 0; y < n[1]; ++y) {
        for (int x = 0; x < n[0]; ++x) {
          const CellState state = field(x, y, z);
          const double F[3] = {total_force(0, x, y, z), total_force(1, x, y, z), total_force(2, x, y, z)};
          const double rho = state.density;
          const double u[3] = {state.velocity.x() - 0.5 * F[0] / rho, state.velocity.y() - 0.5 * F[1] / rho,
                               state.velocity.z() - 0.5 * F[2] / rho};
          const std::size_t cell = geometry_.layout().index(x, y, z);
          for (int i = 0; i < Q; ++i) {
            f_[f_.slot(i, cell)] = static_cast<Real>(shifted_equilibrium<L>(i, rho - 1.0, rho, u[0], u[1], u[2]));
          }
        }
      }
    }
  }

  double total_mass() const {
    // Sum over the interior slots: at an even parity these are the post-streaming populations of
    // each cell, at an odd parity the post-collision ones; streaming (with the copy lists) is a
    // permutation of populations, so both give sum(rho).
    double shifted_sum = 0.0;
    const int ny = geometry_.extent()[1], nz = geometry_.extent()[2];
#pragma omp parallel for collapse(2) reduction(+ : shifted_sum) schedule(static) if (geometry_.threaded())
    for (int z = 0; z < nz; ++z) {
      for (int y = 0; y < ny; ++y) shifted_sum += f_.row_sum(y, z);
    }
    return static_cast<double>(geometry_.cell_count()) + shifted_sum;
  }

  CellState cell_state(int x, int y, int z) const {
    const auto c = geometry_.resolve(x, y, z);
    if (obstacle_.solid_at(c[0], c[1], c[2])) return {};
    double g[Q];
    f_.gather(geometry_.layout().index(c[0], c[1], c[2]), g);
    const auto F = cell_force(c);
    const auto m = macroscopic<L>(g, F.data());
    return {m.rho, Eigen::Vector3d(m.ux, m.uy, m.uz)};
  }

  void box_states(const std::array<int, 3>& origin, const std::array<int, 3>& extent, double* density,
                  const std::array<double*, 3>& velocity) const {
    const std::array<int, 3>& n_block = geometry_.extent();
    std::size_t n = 0;
    for (int k = 0; k < extent[2]; ++k)
      for (int j = 0; j < extent[1]; ++j, n += static_cast<std::size_t>(extent[0])) {
        const int y = origin[1] + j, z = origin[2] + k;
        const bool inside = origin[0] >= 0 && origin[0] + extent[0] <= n_block[0] && y >= 0 && y < n_block[1] &&
                            z >= 0 && z < n_block[2];
        for (int x0 = 0; x0 < extent[0]; x0 += kRowChunk) {
          const int count = std::min(kRowChunk, extent[0] - x0);
          const std::array<double*, 3> u{velocity[0] + n + x0, velocity[1] + n + x0, velocity[2] + n + x0};
          if (inside) {
            row_states({origin[0] + x0, y, z}, count, density + n + x0, u);
            continue;
          }
          for (int i = 0; i < count; ++i) {
            const CellState c = cell_state(origin[0] + x0 + i, y, z);
            density[n + x0 + i] = c.density;
            for (int a = 0; a < 3; ++a) u[a][i] = c.velocity[a];
          }
        }
      }
  }

  /// The current post-streaming f_i of a cell, whatever the parity (Solver::cell_populations).
  void populations(int x, int y, int z, std::span<double> f) const {
    if (f.size() < static_cast<std::size_t>(Q)) {
      throw std::invalid_argument("cell_populations: span holds fewer than Q values");
    }
    double g[Q];
    const auto c = geometry_.resolve(x, y, z);
    f_.gather(geometry_.layout().index(c[0], c[1], c[2]), g);
    for (int i = 0; i < Q; ++i) f[i] = g[i] + L::set.w[i];
  }
  /// Makes f the populations the cell's next collision starts from (Solver::set_cell_populations).
  void set_populations(int x, int y, int z, std::span<const double> f) {
    if (f.size() < static_cast<std::size_t>(Q)) {
      throw std::invalid_argument("set_cell_populations: span holds fewer than Q values");
    }
    const auto c = geometry_.resolve(x, y, z);
    const std::size_t cell = geometry_.layout().index(c[0], c[1], c[2]);
    for (int i = 0; i < Q; ++i) f_[f_.pre_collision_slot(i, cell)] = static_cast<Real>(f[i] - L::set.w[i]);
  }

  double non_equilibrium(int x, int y, int z, std::span<double> f_neq) const {
    if (f_neq.size() < static_cast<std::size_t>(Q)) {
      throw std::invalid_argument("non_equilibrium: span holds fewer than Q values");
    }
    const auto d = geometry_.resolve(x, y, z);
    double g[Q];
    f_.gather(geometry_.layout().index(d[0], d[1], d[2]), g);
    const auto F = cell_force(d);
    const Macroscopic<L> m = macroscopic<L>(g, F.data());
    for (int i = 0; i < Q; ++i) f_neq[i] = g[i] - shifted_equilibrium<L>(i, m.drho, m.rho, m.ux, m.uy, m.uz);
    return m.rho;
  }

  std::vector<double> density_field() const {
    std::vector<double> rho(geometry_.cell_count());
    for_each_cell_moments([&](std::size_t n, double density, double, double, double) { rho[n] = density; });
    return rho;
  }

  VectorField velocity_field() const {
    const std::size_t cells = geometry_.cell_count();
    VectorField u{std::vector<double>(cells), std::vector<double>(cells), std::vector<double>(cells)};
    for_each_cell_moments([&](std::size_t n, double, double ux, double uy, double uz) {
      u.x[n] = ux;
      u.y[n] = uy;
      u.z[n] = uz;
    });
    return u;
  }

  FieldExtrema extrema() const {
    const int ny = geometry_.extent()[1], nz = geometry_.extent()[2];
    // One partial result per row, reduced in row order afterwards: the same answer, locations
    // included, for every thread count (an OpenMP min/max reduction keeps no location).
    std::vector<FieldExtrema> rows(static_cast<std::size_t>(ny) * nz);
#pragma omp parallel for collapse(2) schedule(static) if (geometry_.threaded())
    for (int z = 0; z < nz; ++z) {
      for (int y = 0; y < ny; ++y) {
        FieldExtrema& row = rows[static_cast<std::size_t>(y) + static_cast<std::size_t>(ny) * z];
        row.min_density = std::numeric_limits<double>::infinity();
        row.max_density = -std::numeric_limits<double>::infinity();
        double max_u2 = -1.0;
        for_each_in_row(y, z, [&](int x, double rho, double ux, double uy, double uz) {
          if (obstacle_.solid_at(x, y, z)) return;
          const double u2 = ux * ux + uy * uy + uz * uz;
          // A NaN fails every comparison: test finiteness explicitly.
          row.finite = row.finite && std::isfinite(rho) && std::isfinite(u2);
          if (rho < row.min_density) row.min_density = rho, row.min_density_cell = {x, y, z};
          if (rho > row.max_density) row.max_density = rho, row.max_density_cell = {x, y, z};
          if (u2 > max_u2) max_u2 = u2, row.max_speed_cell = {x, y, z};
        });
        row.max_speed = std::sqrt(max_u2);
      }
    }
    // Row-ordered reduction, starting from the rest state (density 1, speed 0) as a single pass
    // would, so an all-rest field reports its first cell.
    FieldExtrema e;
    for (const FieldExtrema& row : rows) e.merge_later(row);
    return e;
  }

 private:
  static constexpr int kRowChunk = 64;

  /// cell_state of `count` <= kRowChunk consecutive interior cells of a row from `first`: each
  /// direction's slots are read along the row, and each cell's sums run over the directions in
  /// the order macroscopic() takes, so the values are bit for bit cell_state's.
  void row_states(const std::array<int, 3>& first, int count, double* density,
                  const std::array<double*, 3>& velocity) const {
    double drho[kRowChunk], jx[kRowChunk], jy[kRowChunk], jz[kRowChunk];
    const std::size_t row = geometry_.layout().index(first[0], first[1], first[2]);
    const Real* source[Q];
    for (int i = 0; i < Q; ++i) source[i] = f_.data() + f_.pre_collision_slot(i, row);
      // Vectorised across the row, each cell's sums in registers in macroscopic()'s order.
#pragma omp simd
    for (int x = 0; x < count; ++x) {
      double d = 0.0, mx = 0.0, my = 0.0, mz = 0.0;
#pragma GCC unroll 32
      for (int i = 0; i < Q; ++i) {
        const double g = static_cast<double>(source[i][x]);
        d += g;
        mx += double(L::set.c[i][0]) * g;
        my += double(L::set.c[i][1]) * g;
        mz += double(L::set.c[i][2]) * g;
      }
      drho[x] = d;
      jx[x] = mx;
      jy[x] = my;
      jz[x] = mz;
    }
    const double* j[3] = {jx, jy, jz};
    for (int x = 0; x < count; ++x) {
      const int cx = first[0] + x;
      if (obstacle_.solid_at(cx, first[1], first[2])) {
        density[x] = 1.0;
        for (int a = 0; a < 3; ++a) velocity[a][x] = 0.0;
        continue;
      }
      const double rho = 1.0 + drho[x];
      const double inv_rho = 1.0 / rho;
      density[x] = rho;
      for (int a = 0; a < 3; ++a) velocity[a][x] = (j[a][x] + 0.5 * total_force(a, cx, first[1], first[2])) * inv_rho;
    }
  }

  std::array<double, 3> cell_force(const std::array<int, 3>& c) const {
    return {total_force(0, c[0], c[1], c[2]), total_force(1, c[0], c[1], c[2]), total_force(2, c[0], c[1], c[2])};
  }
  double total_force(int axis, int x, int y, int z) const {
    return body_force_[axis] + forces_.value(axis, geometry_.linear_index(x, y, z));
  }

  /// visit(n, rho, u) for every cell (linear index n), cell_state's values (solid cells: rho 1, u 0).
  template <class Visit>
  void for_each_cell_moments(Visit&& visit) const {
    const int ny = geometry_.extent()[1], nz = geometry_.extent()[2];
#pragma omp parallel for collapse(2) schedule(static) if (geometry_.threaded())
    for (int z = 0; z < nz; ++z) {
      for (int y = 0; y < ny; ++y) {
        for_each_in_row(y, z, [&](int x, double rho, double ux, double uy, double uz) {
          visit(geometry_.linear_index(x, y, z), rho, ux, uy, uz);
        });
      }
    }
  }

  /// visit(x, rho, ux, uy, uz) along the whole row (y, z), x ascending: cell_state's values
  /// (solid cells: rho 1, u 0), read a chunk at a time by row_states.
  template <class Visit>
  void for_each_in_row(int y, int z, Visit&& visit) const {
    double rho[kRowChunk], u[3][kRowChunk];
    const int nx = geometry_.extent()[0];
    for (int x0 = 0; x0 < nx; x0 += kRowChunk) {
      const int count = std::min(kRowChunk, nx - x0);
      row_states({x0, y, z}, count, rho, {u[0], u[1], u[2]});
      for (int i = 0; i < count; ++i) visit(x0 + i, rho[i], u[0][i], u[1][i], u[2][i]);
    }
  }

  const BlockGeometry& geometry_;
  AaPopulations<L, Real>& f_;
  const ForceField<Real>& forces_;
  const BlockObstacle<L, Real>& obstacle_;
  Eigen::Vector3d body_force_;
};

}  // namespace settle::lbm
