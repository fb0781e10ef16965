#pragma once
// Memory layout of the populations and the boundary copy lists of the AA pattern.
//
// Populations are stored SoA: one array per direction q, each over the padded grid (the
// interior plus a one-cell ghost layer on every face). Element (q, cell) lives at
// q * pop_stride + cell. Within an array, cell (x, y, z) with x in [-1, nx], y in [-1, ny],
// z in [-1, nz] is at x_begin + x + sx (y + 1) + sxy (z + 1):
//  - x_begin and sx are multiples of one 64-byte line, so every interior row starts on a
//    cache-line (and AVX-512 vector) boundary; sx is nx + 2 rounded up to a line, the ghost
//    x = nx of a row sharing its line with the ghost x = -1 of the next;
//  - pop_stride is a whole number of 4 KiB pages plus `4096 / Q` rounded down to 64 bytes,
//    so the Q arrays start at Q different offsets modulo 4 KiB. Without this, the 2Q
//    streams of the kernel alias in the L1 cache sets and the store buffer (4K aliasing).
#include <array>
#include <cstddef>
#include <cstdint>
#include <vector>

#include "lbm/config.hpp"
#include "lbm/lattice.hpp"

namespace settle::lbm {

struct GridLayout {
  int nx = 0, ny = 0, nz = 0;
  std::size_t x_begin = 0;     ///< element offset of interior x = 0 within a padded row
  std::size_t sx = 0;          ///< row stride (elements)
  std::size_t sxy = 0;         ///< plane stride (elements)
  std::size_t padded_cells = 0;
  std::size_t pop_stride = 0;  ///< elements from one population array to the next

  /// Padded-grid index of cell (x, y, z); valid for -1 <= x <= nx etc.
  std::size_t index(int x, int y, int z) const {
    return x_begin + static_cast<std::size_t>(x) + sx * static_cast<std::size_t>(y + 1) +
           sxy * static_cast<std::size_t>(z + 1);
  }
  /// Signed index offset of a neighbour displaced by (cx, cy, cz).
  std::ptrdiff_t offset(const std::array<int, 3>& c) const {
    return c[0] + static_cast<std::ptrdiff_t>(sx) * c[1] + static_cast<std::ptrdiff_t>(sxy) * c[2];
  }
};

/// Layout for Q populations of `element_bytes` bytes each.
GridLayout make_layout(int nx, int ny, int nz, std::size_t element_bytes, int q_count);

/// One element copy buf[dst] = buf[src], both absolute element indices in the population
/// buffer (q * pop_stride + cell).
struct CopyEntry {
  std::size_t dst;
  std::size_t src;
};

/// A population f_i(x) as "direction i at interior cell x".
struct Link {
  std::array<int, 3> cell;
  int dir;
};

/// Pull resolution of a link whose upstream cell x - c_i lies outside the domain: the
/// post-collision population f*_dir(cell) that streams into f_i(x). Axis by axis: a no-slip
/// axis out of range makes the link a half-way bounce-back, (x, opp(i)) (no-slip wins at
/// edges and corners shared with other kinds); a periodic axis wraps; a free-slip axis is
/// mirrored (the source cell keeps x's coordinate on that axis) and the direction's
/// component on that axis is reflected (specular reflection at the half-way wall).
/// The map is a bijection between incoming and outgoing boundary links with the same set of
/// out-of-range axes, so the copies conserve mass.
template <Lattice L>
Link pull_source(const std::array<int, 3>& x, int i, const std::array<int, 3>& extent,
                 const std::array<Boundary, 3>& boundaries) {
  std::array<int, 3> p{};
  std::array<int, 3> d = L::set.c[i];
  for (int a = 0; a < 3; ++a) {
    p[a] = x[a] - d[a];
    if ((p[a] < 0 || p[a] >= extent[a]) && boundaries[a] == Boundary::no_slip) {
      return {x, opposite(i)};
    }
  }
  for (int a = 0; a < 3; ++a) {
    if (p[a] >= 0 && p[a] < extent[a]) continue;
    if (boundaries[a] == Boundary::periodic) {
      p[a] = (p[a] + extent[a]) % extent[a];
    } else {  // free slip
      p[a] = x[a];
      d[a] = -d[a];
    }
  }
  return {p, direction_index<L>(d[0], d[1], d[2])};
}

/// The two copy lists of the AA scheme (see docs/lbm.md, "AA pattern"):
///  - fill: applied after an even step. For every boundary link (x, i) it writes the ghost
///    slot that the odd kernel of x will read for f_i, slot opp(i) at x - c_i, from the slot
///    holding the source population f*_j(y) after the even step, slot opp(j) at y.
///  - fold: applied after an odd step. The odd kernel of y wrote f*_j(y) into slot j at the
///    ghost y + c_j; the fold copies it to the slot the even kernel of x reads for f_i,
///    slot i at x.
struct CopyLists {
  std::vector<CopyEntry> fill;
  std::vector<CopyEntry> fold;
};

template <Lattice L>
CopyLists build_copy_lists(const GridLayout& layout, const std::array<Boundary, 3>& boundaries) {
  CopyLists lists;
  const std::array<int, 3> extent{layout.nx, layout.ny, layout.nz};
  const auto slot = [&](int q, const std::array<int, 3>& cell) {
    return static_cast<std::size_t>(q) * layout.pop_stride + layout.index(cell[0], cell[1], cell[2]);
  };
  const auto on_face = [&](const std::array<int, 3>& x) {
    for (int a = 0; a < 3; ++a) {
      if (x[a] == 0 || x[a] == extent[a] - 1) return true;
    }
    return false;
  };
  std::array<int, 3> x{};
  for (x[2] = 0; x[2] < extent[2]; ++x[2]) {
    for (x[1] = 0; x[1] < extent[1]; ++x[1]) {
      for (x[0] = 0; x[0] < extent[0]; ++x[0]) {
        if (!on_face(x)) continue;
        for (int i = 1; i < L::Q; ++i) {
          const auto& c = L::set.c[i];
          const std::array<int, 3> upstream{x[0] - c[0], x[1] - c[1], x[2] - c[2]};
          bool outside = false;
          for (int a = 0; a < 3; ++a) outside |= upstream[a] < 0 || upstream[a] >= extent[a];
          if (!outside) continue;
          const Link src = pull_source<L>(x, i, extent, boundaries);
          const auto& cj = L::set.c[src.dir];
          const std::array<int, 3> src_ghost{src.cell[0] + cj[0], src.cell[1] + cj[1],
                                             src.cell[2] + cj[2]};
          lists.fill.push_back({slot(opposite(i), upstream), slot(opposite(src.dir), src.cell)});
          lists.fold.push_back({slot(i, x), slot(src.dir, src_ghost)});
        }
      }
    }
  }
  return lists;
}

}  // namespace settle::lbm
