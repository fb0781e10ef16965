#pragma once
// The whole lattice as a body sees it from one block of a split lattice (docs/parallel.md): a body's
// cells are given in whole-lattice coordinates, unwrapped; this says where each lives. Internal to
// the coupling module (both couplings and the simulation use it).
#include <array>
#include <cmath>
#include <cstddef>
#include <optional>

#include "lbm/decomposition.hpp"
#include "lbm/solver.hpp"

namespace settle::coupling {

/// The whole lattice's extents and periodic axes, and where its cells live (this block, an adjacent
/// one's ghost here, or another block). An unsplit solver is a split into one block.
class LatticeView {
 public:
  explicit LatticeView(const lbm::Solver& fluid)
      : split_(fluid.config().split.value_or(lbm::unsplit({fluid.nx(), fluid.ny(), fluid.nz()}))) {
    for (std::size_t a = 0; a < 3; ++a) periodic_[a] = fluid.config().boundaries[a] == lbm::Boundary::periodic;
  }
  bool split() const { return split_.block_count() > 1; }
  int rank() const { return split_.rank; }
  /// The cell with periodic axes wrapped; empty beyond a face that is not periodic.
  std::optional<std::array<int, 3>> wrap(std::array<int, 3> c) const {
    for (std::size_t a = 0; a < 3; ++a) {
      const int n = split_.global[a];
      if (c[a] >= 0 && c[a] < n) continue;
      if (!periodic_[a]) return std::nullopt;
      c[a] = ((c[a] % n) + n) % n;
    }
    return c;
  }
  /// The image of a wrapped cell nearest to `near` (lattice coordinates) along the periodic axes: the
  /// unwrapped place of a body's cell when the body straddles a wrap (its centre lies on one side,
  /// the cell's wrapped coordinates on the other).
  std::array<int, 3> image_near(std::array<int, 3> wrapped, const std::array<double, 3>& near) const {
    for (std::size_t a = 0; a < 3; ++a) {
      if (!periodic_[a]) continue;
      const int n = split_.global[a];
      wrapped[a] += n * static_cast<int>(std::lround((near[a] - wrapped[a]) / n));
    }
    return wrapped;
  }
  std::size_t index(const std::array<int, 3>& c) const {
    const auto g = split_.global;
    return static_cast<std::size_t>(c[0]) +
           static_cast<std::size_t>(g[0]) * (static_cast<std::size_t>(c[1]) + static_cast<std::size_t>(g[1]) * c[2]);
  }
  int owner(const std::array<int, 3>& wrapped) const { return split_.owner(wrapped); }
  std::array<int, 3> to_block(const std::array<int, 3>& wrapped) const {
    const auto o = split_.offset(split_.rank);
    return {wrapped[0] - o[0], wrapped[1] - o[1], wrapped[2] - o[2]};
  }
  std::array<int, 3> to_lattice(const std::array<int, 3>& local) const {
    const auto o = split_.offset(split_.rank);
    return {local[0] + o[0], local[1] + o[1], local[2] + o[2]};
  }
  /// Block `rank`'s coordinates of a wrapped cell in its padded range: its own cells, and the
  /// `depth` layers beyond its faces shared with another block (also across a periodic wrap): the
  /// ghosts (depth 1), and the layer after them where the quadratic wall rule reads (depth 2).
  std::optional<std::array<int, 3>> in_padded_block(const std::array<int, 3>& wrapped, int rank, int depth = 1) const {
    const auto o = split_.offset(rank), n = split_.extent(rank);
    const auto b = split_.block_coordinates(rank);
    std::array<int, 3> local{};
    for (std::size_t a = 0; a < 3; ++a) {
      const int g = split_.global[a];
      bool found = false;
      for (const int image : {0, -g, g}) {
        const int l = wrapped[a] + image - o[a];
        if (l >= 0 && l < n[a]) {
          found = image == 0;
        } else if (l >= -depth && l < n[a] + depth && split_.blocks[a] > 1) {
          const int k = b[a] + (l < 0 ? -1 : 1);
          found = (image == 0 && k >= 0 && k < split_.blocks[a]) || (image != 0 && periodic_[a]);
        }
        if (found) {
          local[a] = l;
          break;
        }
      }
      if (!found) return std::nullopt;
    }
    return local;
  }

 private:
  lbm::BlockSplit split_;
  std::array<bool, 3> periodic_{};
};

}  // namespace settle::coupling
