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
#include <stdexcept>
#include <vector>

#include "lbm/config.hpp"
#include "lbm/decomposition.hpp"
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

/// What a block of a split lattice (lbm/decomposition.hpp) exchanges with one adjacent block in
/// every step: the links of the receiving block whose source population lies in the sending one.
/// Both sides list them in the receiving block's order (for_each_block_link), so the k-th value of
/// a message goes to the k-th receive slot:
///  - send: copy lists evaluated as the block's own are at the same point of the step (fill after
///    an even kernel, fold after an odd one), each entry's `dst` its position in the message;
///  - fill_receive, fold_receive: the slots (absolute element indices) the values go to, those the
///    copy lists would write if the sending block's cells were here.
struct HaloLinks {
  int rank = 0;
  CopyLists send;
  std::vector<std::size_t> fill_receive, fold_receive;
};

/// A block's own copy lists and its exchanges with each adjacent block (ascending rank).
struct BlockLists {
  CopyLists local;
  std::vector<HaloLinks> halo;
};

/// Calls visit(x, i, source) for every link (x, i) of block `rank` (x in the block's coordinates)
/// whose upstream cell x - c_i lies outside the block, in the order z, y, x, i. `source` (global
/// coordinates) says where f_i(x) comes from: the plain stream from the adjacent block when the
/// upstream cell is inside the lattice, pull_source at the lattice's faces otherwise.
template <Lattice L, class Visit>
void for_each_block_link(const BlockSplit& split, int rank, const FaceKinds& kinds, Visit&& visit) {
  const std::array<int, 3> origin = split.offset(rank), extent = split.extent(rank);
  const auto on_face = [&](const std::array<int, 3>& x) {
    for (std::size_t a = 0; a < 3; ++a) {
      if (x[a] == 0 || x[a] == extent[a] - 1) return true;
    }
    return false;
  };
  std::array<int, 3> x{};
  for (x[2] = 0; x[2] < extent[2]; ++x[2]) {
    for (x[1] = 0; x[1] < extent[1]; ++x[1]) {
      for (x[0] = 0; x[0] < extent[0]; ++x[0]) {
        if (!on_face(x)) continue;
        const std::array<int, 3> g{x[0] + origin[0], x[1] + origin[1], x[2] + origin[2]};
        for (int i = 1; i < L::Q; ++i) {
          const auto& c = L::set.c[i];
          bool leaves_block = false, leaves_lattice = false;
          for (std::size_t a = 0; a < 3; ++a) {
            leaves_block |= x[a] - c[a] < 0 || x[a] - c[a] >= extent[a];
            leaves_lattice |= g[a] - c[a] < 0 || g[a] - c[a] >= split.global[a];
          }
          if (!leaves_block) continue;
          const PullSource source = leaves_lattice ? pull_source<L>(g, i, split.global, kinds)
                                                   : PullSource{{{g[0] - c[0], g[1] - c[1], g[2] - c[2]}, i}};
          visit(x, i, source);
        }
      }
    }
  }
}

/// The copy lists and halo links of block split.rank, whose populations `layout` describes.
template <Lattice L>
BlockLists build_block_lists(const GridLayout& layout, const FaceKinds& kinds, const BlockSplit& split) {
  BlockLists out;
  const std::array<int, 3> origin = split.offset(split.rank);
  const auto local = [&](const std::array<int, 3>& g) {
    return std::array<int, 3>{g[0] - origin[0], g[1] - origin[1], g[2] - origin[2]};
  };
  const auto slot = [&](int q, const std::array<int, 3>& cell) {
    return static_cast<std::size_t>(q) * layout.pop_stride + layout.index(cell[0], cell[1], cell[2]);
  };
  // The entries of link (x, i) fed from `source`, a cell of this block: fill writes fill_dst from
  // the slot holding f*_dir(cell) after an even kernel, fold writes fold_dst from the ghost slot
  // the odd kernel of cell wrote it to.
  const auto add = [&](CopyLists& lists, std::size_t fill_dst, std::size_t fold_dst, int i, const PullSource& source) {
    const std::array<int, 3> cell = local(source.link.cell);
    const auto& cj = L::set.c[source.link.dir];
    const std::array<int, 3> ghost{cell[0] + cj[0], cell[1] + cj[1], cell[2] + cj[2]};
    const std::size_t fill_src = slot(opposite(source.link.dir), cell), fold_src = slot(source.link.dir, ghost);
    if (!source.shifted) {
      lists.fill.push_back({fill_dst, fill_src});
      lists.fold.push_back({fold_dst, fold_src});
      return;
    }
    const std::array<int, 3> m = local(source.moment_cell);
    const std::size_t moment = layout.index(m[0], m[1], m[2]);
    const int dir = source.equilibrium ? i : -1;
    lists.fill_shifted.push_back({fill_dst, fill_src, source.wall_term, dir, moment});
    lists.fold_shifted.push_back({fold_dst, fold_src, source.wall_term, dir, moment});
  };

  for (const int r : split.adjacent_ranks()) out.halo.emplace_back().rank = r;
  const auto halo_of = [&](int r) -> std::size_t {
    for (std::size_t k = 0; k < out.halo.size(); ++k)
      if (out.halo[k].rank == r) return k;
    throw std::logic_error("build_block_lists: a link's source lies in a block that is not adjacent");
  };
  for_each_block_link<L>(split, split.rank, kinds, [&](const std::array<int, 3>& x, int i, const PullSource& source) {
    const auto& c = L::set.c[i];
    const std::size_t fill_dst = slot(opposite(i), {x[0] - c[0], x[1] - c[1], x[2] - c[2]}), fold_dst = slot(i, x);
    const int from = split.owner(source.link.cell);
    if (from == split.rank) return add(out.local, fill_dst, fold_dst, i, source);
    HaloLinks& h = out.halo[halo_of(from)];
    h.fill_receive.push_back(fill_dst);
    h.fold_receive.push_back(fold_dst);
  });
  for (HaloLinks& h : out.halo) {
    std::size_t position = 0;
    for_each_block_link<L>(split, h.rank, kinds, [&](const std::array<int, 3>&, int i, const PullSource& source) {
      if (split.owner(source.link.cell) != split.rank) return;
      add(h.send, position, position, i, source);
      ++position;
    });
  }
  // A block touching this one only across a wall or an edge no link crosses exchanges nothing; the
  // relation is symmetric (a link's source block sends exactly what its block receives), so both
  // sides drop each other.
  std::erase_if(out.halo, [](const HaloLinks& h) {
    return h.fill_receive.empty() && h.send.fill.empty() && h.send.fill_shifted.empty();
  });
  return out;
}

/// The copy lists of an unsplit lattice.
template <Lattice L>
CopyLists build_copy_lists(const GridLayout& layout, const FaceKinds& kinds) {
  return build_block_lists<L>(layout, kinds, unsplit({layout.nx, layout.ny, layout.nz})).local;
}

/// The lists for walls of one kind per pair of faces (no open faces).
template <Lattice L>
CopyLists build_copy_lists(const GridLayout& layout, const std::array<Boundary, 3>& boundaries) {
  return build_copy_lists<L>(
      layout,
      FaceKinds{{{boundaries[0], boundaries[0]}, {boundaries[1], boundaries[1]}, {boundaries[2], boundaries[2]}}});
}

}  // namespace settle::lbm
