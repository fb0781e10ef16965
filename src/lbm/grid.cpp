#include "lbm/grid.hpp"

namespace settle::lbm {

namespace {
constexpr std::size_t kLineBytes = 64;
constexpr std::size_t kPageBytes = 4096;

std::size_t round_up(std::size_t value, std::size_t multiple) { return (value + multiple - 1) / multiple * multiple; }
}  // namespace

GridLayout make_layout(int nx, int ny, int nz, std::size_t element_bytes, int q_count) {
  GridLayout layout;
  layout.nx = nx;
  layout.ny = ny;
  layout.nz = nz;
  const std::size_t per_line = kLineBytes / element_bytes;
  layout.x_begin = per_line;  // ghost x = -1 is the last element of the line before
  // Ghost x = nx of one row and ghost x = -1 of the next share a line, so a row costs
  // nx + 2 elements rounded up to whole lines (264 doubles for nx = 256, not 272: the AA odd
  // step touches both ghosts, and every line of a row is transferred).
  layout.sx = round_up(static_cast<std::size_t>(nx) + 2, per_line);
  layout.sxy = layout.sx * static_cast<std::size_t>(ny + 2);
  // The last row's ghost x = nx lies x_begin past the last plane.
  layout.padded_cells = layout.sxy * static_cast<std::size_t>(nz + 2) + layout.x_begin;
  const std::size_t stagger_bytes = kPageBytes / static_cast<std::size_t>(q_count) / kLineBytes * kLineBytes;
  const std::size_t array_bytes = round_up(layout.padded_cells * element_bytes, kPageBytes);
  layout.pop_stride = (array_bytes + stagger_bytes) / element_bytes;
  return layout;
}

}  // namespace settle::lbm
