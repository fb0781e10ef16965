#pragma once
// A block's populations in the AA pattern's one array (Bailey, Myre, Walsh, Lilja & Saar 2009,
// doi:10.1109/ICPP.2009.37) and the parity that gives the array its meaning. With A[q][x] the
// stored value of direction q at padded cell x (lbm/grid.hpp) and g = f - w (collision.hpp):
//  - after an odd step (even step count) A[i][x] = g_i(x), the natural layout;
//  - after an even step (odd step count) the post-collision g*_i(x) sits in A[opp(i)][x], and the
//    next (odd) kernel of x reads g_i(x) from A[opp(i)][x - c_i] and writes g*_i(x) to A[i][x + c_i].
// The parity lives here, with the array, as waLBerla's TimestepTracker lives beside its in-place
// sweep: the kernel, the walls, the halo and the window shift all ask it which slot holds what.
#include <Eigen/Core>
#include <cstddef>
#include <cstdint>
#include <vector>

#include "lbm/aligned_array.hpp"
#include "lbm/block_geometry.hpp"
#include "lbm/collision.hpp"
#include "lbm/grid.hpp"
#include "lbm/lattice.hpp"

namespace settle::lbm {

template <Lattice L, class Real>
class AaPopulations {
 public:
  static constexpr int Q = L::Q;

  explicit AaPopulations(const BlockGeometry& geometry)
      : layout_(geometry.layout()), threaded_(geometry.threaded()), values_(layout_.pop_stride * Q) {}

  /// Steps taken since initialise(); its parity selects the next kernel.
  std::int64_t step_count() const { return steps_; }
  void set_step_count(std::int64_t steps) { steps_ = steps; }
  void advance() { ++steps_; }
  bool odd_parity() const { return (steps_ & 1) != 0; }

  const GridLayout& layout() const { return layout_; }
  Real* data() { return values_.data(); }
  const Real* data() const { return values_.data(); }
  std::size_t size() const { return values_.size(); }
  Real& operator[](std::size_t slot) { return values_[slot]; }
  const Real& operator[](std::size_t slot) const { return values_[slot]; }

  std::size_t slot(int q, std::size_t cell) const { return static_cast<std::size_t>(q) * layout_.pop_stride + cell; }
  /// Padded index of the neighbour x - c_i of padded cell x (a ghost at the faces).
  std::size_t upstream_of(std::size_t cell, int i) const {
    return static_cast<std::size_t>(static_cast<std::ptrdiff_t>(cell) - layout_.offset(L::set.c[i]));
  }
  /// The slot the next kernel of interior cell `cell` reads its f_i from at the current parity.
  std::size_t pre_collision_slot(int i, std::size_t cell) const {
    return odd_parity() ? slot(opposite(i), upstream_of(cell, i)) : slot(i, cell);
  }
  /// Shifted post-streaming populations g_i of interior cell `cell` at the current parity.
  void gather(std::size_t cell, double* g) const {
    if (odd_parity()) {
      for (int i = 0; i < Q; ++i) g[i] = static_cast<double>(values_[slot(opposite(i), upstream_of(cell, i))]);
    } else {
      for (int i = 0; i < Q; ++i) g[i] = static_cast<double>(values_[slot(i, cell)]);
    }
  }
  /// f*_j(y) of padded cell y after the kernel of the given parity: in the cell's own slot opp(j)
  /// after an even kernel, pushed to slot j at y + c_j after an odd one.
  template <bool Odd>
  double post_collision(int j, std::size_t y) const {
    return static_cast<double>(
        values_[Odd ? slot(j, static_cast<std::size_t>(static_cast<std::ptrdiff_t>(y) + layout_.offset(L::set.c[j])))
                    : slot(opposite(j), y)]);
  }

  /// Applies a copy list after the kernel of the given parity. Inlet and outlet entries take the
  /// moments of their cell from its post-collision populations: in its own slots after an even
  /// kernel (f*_j in slot opp j), pushed to its neighbours after an odd one (f*_j in slot j at
  /// x + c_j). Neither place is a destination of the lists.
  template <bool Odd>
  void apply(const std::vector<CopyEntry>& list, const std::vector<ShiftedCopyEntry>& shifted,
             const Eigen::Vector3d& inflow_velocity) {
    Real* const data = values_.data();
    const std::size_t count = list.size();
    const CopyEntry* const entries = list.data();
#pragma omp parallel for schedule(static) if (threaded_)
    for (std::size_t k = 0; k < count; ++k) data[entries[k].dst] = data[entries[k].src];
    for (const ShiftedCopyEntry& e : shifted) data[e.dst] = shifted_value<Odd>(e, inflow_velocity);
  }

  /// The value an inlet or outlet entry stores, in storage precision.
  template <bool Odd>
  Real shifted_value(const ShiftedCopyEntry& e, const Eigen::Vector3d& inflow_velocity) const {
    double drho = 0.0, j[3] = {0.0, 0.0, 0.0};
    for (int q = 0; q < Q; ++q) {
      const double g = post_collision<Odd>(q, e.cell);
      drho += g;
      for (int a = 0; a < 3; ++a) j[a] += L::set.c[q][a] * g;
    }
    const double rho = 1.0 + drho;
    if (e.equilibrium_dir >= 0) {
      return static_cast<Real>(shifted_equilibrium<L>(e.equilibrium_dir, 0.0, 1.0, j[0] / rho, j[1] / rho, j[2] / rho));
    }
    const double term =
        e.wall_term[0] * inflow_velocity[0] + e.wall_term[1] * inflow_velocity[1] + e.wall_term[2] * inflow_velocity[2];
    return static_cast<Real>(static_cast<double>(values_[e.src]) + rho * term);
  }

  /// The sum of the stored values of the interior row (y, z) over every direction.
  double row_sum(int y, int z) const {
    double sum = 0.0;
    const std::size_t row = layout_.index(0, y, z);
    for (int q = 0; q < Q; ++q) {
      const Real* p = values_.data() + slot(q, row);
      for (int x = 0; x < layout_.nx; ++x) sum += static_cast<double>(p[x]);
    }
    return sum;
  }

  /// Every value at rest (0, the shifted rest state), written by the threads that stream them:
  /// pages land near them (first touch).
  void zero_fill() {
    Real* data = values_.data();
    const std::size_t count = values_.size();
#pragma omp parallel for schedule(static) if (threaded_)
    for (std::size_t k = 0; k < count; ++k) data[k] = Real(0);
  }

 private:
  GridLayout layout_;
  bool threaded_;
  AlignedArray<Real> values_;
  std::int64_t steps_ = 0;
};

}  // namespace settle::lbm
