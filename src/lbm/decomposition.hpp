#pragma once
// A lattice split into blocks, one per rank (docs/parallel.md). The blocks tile the grid: along
// axis a there are blocks[a] of them, block k covering cells [boundary(a, k), boundary(a, k + 1)).
// Block (bx, by, bz) is rank bx + blocks[0] (by + blocks[1] bz). Each block is an ordinary solver
// over its own cells with the usual one-cell ghost layer; the populations that cross a block face
// travel as messages (lbm/grid.hpp, HaloLinks).
#include <array>
#include <vector>

namespace settle::lbm {

struct BlockSplit {
  std::array<int, 3> global{1, 1, 1};  ///< interior cells of the whole lattice per axis
  std::array<int, 3> blocks{1, 1, 1};  ///< blocks per axis
  int rank = 0;                        ///< the block this solver holds

  int block_count() const { return blocks[0] * blocks[1] * blocks[2]; }
  std::array<int, 3> block_coordinates(int of_rank) const;
  int rank_of(const std::array<int, 3>& block) const;
  /// First cell of block k along `axis`, k in [0, blocks[axis]]; global[axis] for k = blocks[axis].
  int boundary(int axis, int k) const;
  /// First global cell and cells per axis of a rank's block.
  std::array<int, 3> offset(int of_rank) const;
  std::array<int, 3> extent(int of_rank) const;
  /// The cells of the thinnest block along an axis with more than one block (the largest int when
  /// no axis is split).
  int thinnest_block() const;
  /// The rank whose block holds global interior cell c.
  int owner(const std::array<int, 3>& c) const;
  /// Ranks whose blocks touch this rank's block, through a face, an edge or a corner, periodic
  /// wrap included (every axis wraps: a rank with no link across the wrap exchanges nothing),
  /// ascending, without this rank.
  std::vector<int> adjacent_ranks() const;
};

/// The whole lattice as one block (rank 0 of 1).
BlockSplit unsplit(const std::array<int, 3>& global);

/// The split of `global` cells over `ranks` blocks whose faces cut the fewest cell faces (the
/// ghost traffic), each block at least one cell thick; among equal cuts the one with more blocks
/// along z, then y, since a z-plane is contiguous in memory. Throws settle::InputError when no
/// split fits (more ranks than cells along the axes' products).
BlockSplit choose_split(const std::array<int, 3>& global, int ranks, int rank);

/// Throws settle::InputError naming the field when the split is unusable.
void validate(const BlockSplit& split);

}  // namespace settle::lbm
