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
  std::size_t x_begin = 0;  ///< element offset of interior x = 0 within a padded row
  std::size_t sx = 0;       ///< row stride (elements)
  std::size_t sxy = 0;      ///< plane stride (elements)
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

/// A population f_i(x) as "direction i at interior cell x".
struct Link {
  std::array<int, 3> cell;
  int dir;
};

/// Where the incoming population of a boundary link comes from: f_i(x) = f*_dir(cell), and at
/// inlets and outlets (`shifted`) a value from the moments of `moment_cell`:
///  - inlet: f*_dir(cell) + rho wall_term.u_w, rho that cell's density, u_w the inflow velocity;
///  - outlet (`equilibrium`): the equilibrium f_eq_i(1, u), u that cell's velocity.
struct PullSource {
  Link link;
  std::array<double, 3> wall_term{};
  bool equilibrium = false;
  std::array<int, 3> moment_cell{};
  bool shifted = false;
};

/// Pull resolution of a link whose upstream cell x - c_i lies outside the domain: the
/// post-collision population f*_dir(cell) that streams into f_i(x), plus a constant. Each
/// out-of-range axis names a face (its lower or upper side) and that face's kind:
///  - a no-slip face makes the link a half-way bounce-back, (x, opp(i)); no-slip wins at edges
///    and corners shared with other kinds;
///  - otherwise a velocity face makes it a bounce-back from a wall moving with the inflow
///    velocity u_w, f_i(x) = f*_opp(i)(x) + 6 w_i rho(x) c_i.u_w (Ladd 1994, J. Fluid Mech. 271,
///    285, doi:10.1017/S0022112094001771, with the cell's own density so that the face imposes
///    the velocity whatever the density level); velocity wins over the kinds below;
///  - otherwise axis by axis: a periodic axis wraps; a free-slip axis is mirrored (the source
///    cell keeps x's coordinate on that axis) and the direction's component on that axis is
///    reflected (specular reflection at the half-way wall); an outflow axis marks an outlet: the
///    unknown population is the equilibrium at the reference density 1 and the velocity of the
///    cell it would have been copied from, x - c_i brought back onto the face's layer (an
///    equilibrium pressure outlet; its velocity has zero normal gradient). A plain copy
///    f_i(x - n) lets the density level float: after a ramped inflow a channel settled at
///    rho = 1 / (1 - U), 5% high at U = 0.05, and every force with it.
/// Without open faces the map is a bijection between incoming and outgoing links with the same
/// set of out-of-range axes, so the copies conserve mass; inlets and outlets exchange mass with
/// the outside by design.
template <Lattice L>
PullSource pull_source(const std::array<int, 3>& x, int i, const std::array<int, 3>& extent, const FaceKinds& kinds) {
  std::array<int, 3> p{};
  std::array<int, 3> d = L::set.c[i];
  std::array<const Boundary*, 3> face{};  // the kind of the face each out-of-range axis crosses
  bool bounce = false, moving = false;
  for (std::size_t a = 0; a < 3; ++a) {
    p[a] = x[a] - d[a];
    if (p[a] >= 0 && p[a] < extent[a]) continue;
    face[a] = &kinds[a][p[a] < 0 ? 0 : 1];
    bounce |= *face[a] == Boundary::no_slip;
    moving |= *face[a] == Boundary::velocity;
  }
  if (bounce) return {{x, opposite(i)}};
  if (moving) {
    const double weight = 6.0 * L::set.w[i];
    return {{x, opposite(i)}, {weight * d[0], weight * d[1], weight * d[2]}, false, x, true};
  }
  bool outflow = false;
  for (std::size_t a = 0; a < 3; ++a) {
    if (!face[a]) continue;
    if (*face[a] == Boundary::periodic) {
      p[a] = (p[a] + extent[a]) % extent[a];
    } else {  // free slip or outflow
      p[a] = x[a];
      if (*face[a] == Boundary::free_slip) d[a] = -d[a];
      outflow |= *face[a] == Boundary::outflow;
    }
  }
  const Link source{p, direction_index<L>(d[0], d[1], d[2])};
  if (outflow) return {source, {}, true, p, true};
  return {source};
}

/// One element copy buf[dst] = buf[src], both absolute element indices in the population buffer
/// (q * pop_stride + cell); for inlets and outlets the value PullSource describes from the
/// moments of `cell`.
struct CopyEntry {
  std::size_t dst;
  std::size_t src;
};
struct ShiftedCopyEntry {
  std::size_t dst;
  std::size_t src;
  std::array<double, 3> wall_term;  ///< 6 w_i c_i at an inlet
  int equilibrium_dir;              ///< at an outlet the direction i of f_eq_i(1, u); -1 at an inlet
  std::size_t cell;                 ///< padded index of the cell whose populations give rho and u
};

/// The copy lists of the AA scheme (see docs/lbm.md, "AA pattern"):
///  - fill: applied after an even step. For every boundary link (x, i) it writes the ghost
///    slot that the odd kernel of x will read for f_i, slot opp(i) at x - c_i, from the slot
///    holding the source population f*_j(y) after the even step, slot opp(j) at y.
///  - fold: applied after an odd step. The odd kernel of y wrote f*_j(y) into slot j at the
///    ghost y + c_j; the fold copies it to the slot the even kernel of x reads for f_i,
///    slot i at x.
/// The links of inlets and outlets, whose values depend on a cell's moments, are in the shifted
/// lists.
/// No entry's source is another entry's destination (sources are interior slots after an even
/// step and slots the odd kernel wrote after an odd one), so each list applies in any order.
struct CopyLists {
  std::vector<CopyEntry> fill;
  std::vector<CopyEntry> fold;
  std::vector<ShiftedCopyEntry> fill_shifted;
  std::vector<ShiftedCopyEntry> fold_shifted;
};

template <Lattice L>
CopyLists build_copy_lists(const GridLayout& layout, const FaceKinds& kinds) {
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
          const PullSource src = pull_source<L>(x, i, extent, kinds);
          const auto& cj = L::set.c[src.link.dir];
          const std::array<int, 3> src_ghost{src.link.cell[0] + cj[0], src.link.cell[1] + cj[1],
                                             src.link.cell[2] + cj[2]};
          const std::size_t fill_dst = slot(opposite(i), upstream),
                            fill_src = slot(opposite(src.link.dir), src.link.cell);
          const std::size_t fold_dst = slot(i, x), fold_src = slot(src.link.dir, src_ghost);
          if (src.shifted) {
            const auto& m = src.moment_cell;
            const std::size_t cell = layout.index(m[0], m[1], m[2]);
            const int dir = src.equilibrium ? i : -1;
            lists.fill_shifted.push_back({fill_dst, fill_src, src.wall_term, dir, cell});
            lists.fold_shifted.push_back({fold_dst, fold_src, src.wall_term, dir, cell});
          } else {
            lists.fill.push_back({fill_dst, fill_src});
            lists.fold.push_back({fold_dst, fold_src});
          }
        }
      }
    }
  }
  return lists;
}

/// The lists for walls of one kind per pair of faces (no open faces).
template <Lattice L>
CopyLists build_copy_lists(const GridLayout& layout, const std::array<Boundary, 3>& boundaries) {
  return build_copy_lists<L>(
      layout,
      FaceKinds{{{boundaries[0], boundaries[0]}, {boundaries[1], boundaries[1]}, {boundaries[2], boundaries[2]}}});
}

}  // namespace settle::lbm
