#include "lbm/decomposition.hpp"

#include <fmt/format.h>

#include <algorithm>
#include <cstdint>
#include <limits>

#include "common/error.hpp"

namespace settle::lbm {

std::array<int, 3> BlockSplit::block_coordinates(int of_rank) const {
  return {of_rank % blocks[0], of_rank / blocks[0] % blocks[1], of_rank / (blocks[0] * blocks[1])};
}

int BlockSplit::rank_of(const std::array<int, 3>& block) const {
  return block[0] + blocks[0] * (block[1] + blocks[1] * block[2]);
}

int BlockSplit::boundary(int axis, int k) const {
  const auto a = static_cast<std::size_t>(axis);
  return static_cast<int>(static_cast<std::int64_t>(global[a]) * k / blocks[a]);
}

int BlockSplit::thinnest_block() const {
  int thinnest = std::numeric_limits<int>::max();
  for (int a = 0; a < 3; ++a) {
    if (blocks[static_cast<std::size_t>(a)] < 2) continue;
    for (int k = 0; k < blocks[static_cast<std::size_t>(a)]; ++k)
      thinnest = std::min(thinnest, boundary(a, k + 1) - boundary(a, k));
  }
  return thinnest;
}

std::array<int, 3> BlockSplit::offset(int of_rank) const {
  const std::array<int, 3> b = block_coordinates(of_rank);
  return {boundary(0, b[0]), boundary(1, b[1]), boundary(2, b[2])};
}

std::array<int, 3> BlockSplit::extent(int of_rank) const {
  const std::array<int, 3> b = block_coordinates(of_rank);
  return {boundary(0, b[0] + 1) - boundary(0, b[0]), boundary(1, b[1] + 1) - boundary(1, b[1]),
          boundary(2, b[2] + 1) - boundary(2, b[2])};
}

int BlockSplit::owner(const std::array<int, 3>& c) const {
  std::array<int, 3> block{};
  for (int a = 0; a < 3; ++a) {
    const auto i = static_cast<std::size_t>(a);
    // The first block whose end lies beyond c: boundaries are floor(n k / b), so k = floor(c b / n)
    // is at most one short.
    int k = static_cast<int>(static_cast<std::int64_t>(c[i]) * blocks[i] / global[i]);
    while (k + 1 < blocks[i] && boundary(a, k + 1) <= c[i]) ++k;
    block[i] = k;
  }
  return rank_of(block);
}

std::vector<int> BlockSplit::adjacent_ranks() const {
  const std::array<int, 3> me = block_coordinates(rank);
  std::vector<int> ranks;
  for (int dz = -1; dz <= 1; ++dz)
    for (int dy = -1; dy <= 1; ++dy)
      for (int dx = -1; dx <= 1; ++dx) {
        const std::array<int, 3> d{dx, dy, dz};
        std::array<int, 3> other{};
        for (std::size_t a = 0; a < 3; ++a) other[a] = (me[a] + d[a] + blocks[a]) % blocks[a];
        const int r = rank_of(other);
        if (r != rank) ranks.push_back(r);
      }
  std::sort(ranks.begin(), ranks.end());
  ranks.erase(std::unique(ranks.begin(), ranks.end()), ranks.end());
  return ranks;
}

void validate(const BlockSplit& split) {
  for (std::size_t a = 0; a < 3; ++a) {
    if (split.blocks[a] < 1 || split.global[a] < split.blocks[a]) {
      throw InputError(
          fmt::format("parallel.blocks: axis {} has {} cells and {} blocks; each block needs at least "
                      "one cell",
                      "xyz"[a], split.global[a], split.blocks[a]));
    }
  }
  if (split.rank < 0 || split.rank >= split.block_count()) {
    throw InputError(fmt::format("parallel: rank {} outside [0, {})", split.rank, split.block_count()));
  }
}

BlockSplit unsplit(const std::array<int, 3>& global) {
  BlockSplit whole;
  whole.global = global;
  return whole;
}

BlockSplit choose_split(const std::array<int, 3>& global, int ranks, int rank) {
  if (ranks < 1) throw InputError(fmt::format("parallel: the rank count must be >= 1, got {}", ranks));
  BlockSplit best;
  best.global = global;
  best.rank = rank;
  double best_cut = std::numeric_limits<double>::infinity();
  bool found = false;
  // Ascending bz, then by: a later split with an equal cut has more blocks along z (then y).
  for (int bz = 1; bz <= ranks; ++bz) {
    if (ranks % bz != 0) continue;
    for (int by = 1; by <= ranks / bz; ++by) {
      if ((ranks / bz) % by != 0) continue;
      const std::array<int, 3> blocks{ranks / bz / by, by, bz};
      bool fits = true;
      for (std::size_t a = 0; a < 3; ++a) fits = fits && blocks[a] <= global[a];
      if (!fits) continue;
      // Cell faces cut: each interior cut along axis a crosses the plane of the other two axes.
      const double gx = global[0], gy = global[1], gz = global[2];
      const double cut = (blocks[0] - 1) * gy * gz + (blocks[1] - 1) * gx * gz + (blocks[2] - 1) * gx * gy;
      if (cut <= best_cut) best_cut = cut, best.blocks = blocks, found = true;
    }
  }
  if (!found) {
    throw InputError(
        fmt::format("parallel: {} ranks do not fit a grid of {} x {} x {} cells with one cell per "
                    "block at least",
                    ranks, global[0], global[1], global[2]));
  }
  validate(best);
  return best;
}

}  // namespace settle::lbm
