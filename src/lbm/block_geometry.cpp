#include "lbm/block_geometry.hpp"

#include <stdexcept>
#include <string>

namespace settle::lbm {

BlockGeometry::BlockGeometry(const SolverConfig& config, std::size_t element_bytes, int q)
    : extent_{config.nx, config.ny, config.nz},
      boundaries_(config.boundaries),
      kinds_(lbm::face_kinds(config)),
      split_(config.split.value_or(unsplit(extent_))),
      layout_(make_layout(config.nx, config.ny, config.nz, element_bytes, q)) {}

std::size_t BlockGeometry::cell_count() const {
  return static_cast<std::size_t>(extent_[0]) * static_cast<std::size_t>(extent_[1]) *
         static_cast<std::size_t>(extent_[2]);
}

std::array<int, 3> BlockGeometry::cell_of_linear(std::size_t n) const {
  const std::size_t nx = static_cast<std::size_t>(extent_[0]), ny = static_cast<std::size_t>(extent_[1]);
  return {static_cast<int>(n % nx), static_cast<int>(n / nx % ny), static_cast<int>(n / (nx * ny))};
}

std::size_t BlockGeometry::padded_of_linear(std::size_t n) const {
  const std::array<int, 3> c = cell_of_linear(n);
  return layout_.index(c[0], c[1], c[2]);
}

std::array<int, 3> BlockGeometry::padded_coordinates(std::size_t p) const {
  const std::size_t r = p - layout_.x_begin + 1;
  return {static_cast<int>(r % layout_.sx) - 1, static_cast<int>(r % layout_.sxy / layout_.sx) - 1,
          static_cast<int>(r / layout_.sxy) - 1};
}

std::array<int, 3> BlockGeometry::resolve(int x, int y, int z) const {
  std::array<int, 3> c{x, y, z};
  for (std::size_t a = 0; a < 3; ++a) {
    if (c[a] >= 0 && c[a] < extent_[a]) continue;
    if (boundaries_[a] != Boundary::periodic || split_.blocks[a] > 1) {
      throw std::out_of_range("lbm cell query: coordinate " + std::to_string(c[a]) + " outside [0, " +
                              std::to_string(extent_[a]) + ") on axis " + std::to_string(a));
    }
    c[a] = ((c[a] % extent_[a]) + extent_[a]) % extent_[a];
  }
  return c;
}

bool BlockGeometry::has_block_beyond(std::size_t a, int side, bool through_wrap) const {
  if (split_.blocks[a] <= 1) return false;
  const int k = split_.block_coordinates(split_.rank)[a] + (side == 0 ? -1 : 1);
  if (k >= 0 && k < split_.blocks[a]) return true;
  return through_wrap && boundaries_[a] == Boundary::periodic;
}

std::optional<int> BlockGeometry::block_beyond(std::size_t a, int side) const {
  if (!has_block_beyond(a, side, false)) return std::nullopt;
  std::array<int, 3> b = split_.block_coordinates(split_.rank);
  b[a] += side == 0 ? -1 : 1;
  return split_.rank_of(b);
}

std::optional<std::array<int, 3>> BlockGeometry::site(std::array<int, 3> c, bool& ghost) const {
  ghost = false;
  for (std::size_t a = 0; a < 3; ++a) {
    if (c[a] >= 0 && c[a] < extent_[a]) continue;
    const int side = c[a] < 0 ? 0 : 1;
    if ((c[a] == -1 || c[a] == extent_[a]) && has_block_beyond(a, side, true)) {
      ghost = true;
      continue;
    }
    if (boundaries_[a] != Boundary::periodic || split_.blocks[a] > 1) return std::nullopt;
    c[a] = ((c[a] % extent_[a]) + extent_[a]) % extent_[a];
  }
  return c;
}

}  // namespace settle::lbm
