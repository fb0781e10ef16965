#pragma once
// Where a block's cells lie: its extent and the padded layout of its populations (lbm/grid.hpp),
// the kinds of the lattice's faces, and on a split lattice the blocks beyond its faces
// (lbm/decomposition.hpp). What the storage, the obstacle, the halo and the window shift of one
// block ask of the place of a cell; fixed at construction. An unsplit lattice is a split into one
// block.
#include <array>
#include <cstddef>
#include <optional>

#include "lbm/config.hpp"
#include "lbm/decomposition.hpp"
#include "lbm/grid.hpp"

namespace settle::lbm {

class BlockGeometry {
 public:
  /// The block `config` describes, with q populations of `element_bytes` bytes per cell.
  BlockGeometry(const SolverConfig& config, std::size_t element_bytes, int q);

  const GridLayout& layout() const { return layout_; }
  const std::array<int, 3>& extent() const { return extent_; }
  const std::array<Boundary, 3>& boundaries() const { return boundaries_; }
  const FaceKinds& face_kinds() const { return kinds_; }
  /// The split this block is one block of (rank 0 of 1 when the lattice is not split).
  const BlockSplit& split() const { return split_; }
  std::size_t cell_count() const;
  /// Below ~16 k cells a step costs less than waking the OpenMP team (and far less than a
  /// barrier on an oversubscribed machine), so small grids run on the calling thread.
  bool threaded() const { return cell_count() >= 16384; }

  /// The linear index x + nx (y + ny z) of an interior cell, and back.
  std::size_t linear_index(int x, int y, int z) const {
    return static_cast<std::size_t>(x) +
           static_cast<std::size_t>(extent_[0]) *
               (static_cast<std::size_t>(y) + static_cast<std::size_t>(extent_[1]) * static_cast<std::size_t>(z));
  }
  std::array<int, 3> cell_of_linear(std::size_t n) const;
  std::size_t padded_of_linear(std::size_t n) const;
  /// Coordinates of padded index p (inverse of GridLayout::index).
  std::array<int, 3> padded_coordinates(std::size_t p) const;

  /// Interior coordinates after wrapping periodic axes of one block; throws std::out_of_range for
  /// others out of range.
  std::array<int, 3> resolve(int x, int y, int z) const;
  /// True when the block has an adjacent block beyond its face `side` (0 lower, 1 upper) of axis a,
  /// through the lattice's periodic wrap too when `through_wrap`.
  bool has_block_beyond(std::size_t a, int side, bool through_wrap) const;
  /// The rank of the block beyond face `side` of axis a, not through the wrap.
  std::optional<int> block_beyond(std::size_t a, int side) const;
  /// Cell c in this block's coordinates: periodic axes of one block wrap; -1 and n on a face shared
  /// with an adjacent block name a ghost (that block's cell; `ghost` is set). Empty when c lies
  /// beyond a face of the lattice that is not periodic.
  std::optional<std::array<int, 3>> site(std::array<int, 3> c, bool& ghost) const;

 private:
  std::array<int, 3> extent_;
  std::array<Boundary, 3> boundaries_;
  FaceKinds kinds_;
  BlockSplit split_;
  GridLayout layout_;
};

}  // namespace settle::lbm
