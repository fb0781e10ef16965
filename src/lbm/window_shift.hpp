#pragma once
// The moving window of one block (Solver::shift, docs/lbm.md, "Moving window"): the block's content
// moves one cell along an axis, the layer that leaves goes to the adjacent block on that side (or
// out of the lattice), the opposite layer enters from the adjacent block there (or at rest from
// outside). At an odd parity the ghosts are then rebuilt, with the adjacent blocks' new faces where
// split, and the populations that wall links had returned into them are written back at their
// links' new places. On a split lattice each part runs around an exchange (parallel::shift).
#include <Eigen/Core>
#include <algorithm>
#include <array>
#include <cstring>
#include <optional>
#include <stdexcept>
#include <string>
#include <utility>
#include <vector>

#include "lbm/aa_populations.hpp"
#include "lbm/block_exchange.hpp"
#include "lbm/block_geometry.hpp"
#include "lbm/block_halo.hpp"
#include "lbm/block_obstacle.hpp"
#include "lbm/grid.hpp"
#include "lbm/solver.hpp"

namespace settle::lbm {

template <Lattice L, class Real>
class WindowShift {
 public:
  static constexpr int Q = L::Q;

  /// The parts of the block a shift moves and reads; they outlive it.
  struct Parts {
    const BlockGeometry& geometry;
    AaPopulations<L, Real>& populations;
    BlockObstacle<L, Real>& obstacle;
    const BlockHalo<L, Real>& halo;
    const CopyLists& lists;
    const Eigen::Vector3d& inflow_velocity;
  };
  explicit WindowShift(Parts parts) : p_(parts) {}

  /// Moves the block's content and fills messages.send with the leaving layer for the block it
  /// enters (Solver::begin_shift).
  ShiftMass begin(int axis, int sign, HaloMessages& messages);
  /// Writes the entering layer; true when the ghosts need the adjacent blocks' new faces, whose
  /// fill values it has put in messages.send (Solver::end_shift).
  bool end(HaloMessages& messages);
  /// Writes the adjacent blocks' new faces into the ghosts and finishes the shift.
  void end_ghost_refresh(const HaloMessages& messages);

 private:
  /// A window shift between begin_shift and the last of its exchanges. At an odd parity the
  /// ghosts are rebuilt from the moved content, which loses the populations that wall links
  /// returned into them (the obstacle's close() writes a link's returning population where its
  /// fluid cell reads it, a ghost when the solid cell lies across a face): `returns` keeps them,
  /// moved with their fluid cells, to be written back (slot, value).
  struct Pending {
    int axis = 0, sign = 1;
    std::vector<std::pair<std::size_t, double>> returns;
  };

  /// The cells of layer k along the shift's axis, in message order.
  template <class Visit>
  void for_each_layer_cell(int axis, int k, Visit&& visit) const {
    const std::array<int, 3>& extent = p_.geometry.extent();
    const int nu = extent[static_cast<std::size_t>((axis + 1) % 3)],
              nv = extent[static_cast<std::size_t>((axis + 2) % 3)];
    for (int v = 0; v < nv; ++v) {
      for (int u = 0; u < nu; ++u) {
        std::array<int, 3> c{};
        c[static_cast<std::size_t>(axis)] = k;
        c[static_cast<std::size_t>((axis + 1) % 3)] = u;
        c[static_cast<std::size_t>((axis + 2) % 3)] = v;
        visit(c);
      }
    }
  }
  /// The links' returned populations after an odd step, with their fluid cells' new places; those
  /// whose fluid cell moves into the onward block go to `out` (x, y, z, direction, value).
  void keep_returns(std::size_t a, int sign, std::optional<int> onward, std::vector<double>* out);
  void move_layers(int axis, int sign);
  void restore_returns() {
    for (const auto& [at, value] : pending_->returns) p_.populations[at] = static_cast<Real>(value);
    pending_.reset();
  }

  Parts p_;
  std::optional<Pending> pending_;
};

template <Lattice L, class Real>
ShiftMass WindowShift<L, Real>::begin(int axis, int sign, HaloMessages& messages) {
  if (axis < 0 || axis > 2) throw std::invalid_argument("shift: axis must be 0, 1 or 2");
  if (sign != 1 && sign != -1) throw std::invalid_argument("shift: sign must be +1 or -1");
  if (pending_) throw std::logic_error("begin_shift: the last shift has not ended");
  const auto a = static_cast<std::size_t>(axis);
  const std::array<int, 3>& extent = p_.geometry.extent();
  // The window moves by `sign`: new cell k holds old cell k + sign. The layer at k = 0 (sign -1:
  // k = n - 1) of the old content leaves the block, into the adjacent block on that side or out
  // of the lattice (also across a periodic wrap: the window is not periodic); the opposite layer
  // enters from the adjacent block there, or at rest from outside.
  const int leaving = sign > 0 ? 0 : extent[a] - 1;
  const std::optional<int> onward = p_.geometry.block_beyond(a, sign > 0 ? 0 : 1);
  messages.send.assign(p_.halo.size(), {});
  std::vector<double>* out = onward ? &messages.send[p_.halo.index_of(*onward)] : nullptr;
  double leaving_sum = 0.0, layer_cells = 0.0;
  const AaPopulations<L, Real>& f = p_.populations;
  for_each_layer_cell(axis, leaving, [&](const std::array<int, 3>& c) {
    const std::size_t cell = f.layout().index(c[0], c[1], c[2]);
    layer_cells += 1.0;
    for (int q = 0; q < Q; ++q) {
      const double g = static_cast<double>(f[f.slot(q, cell)]);
      if (out) out->push_back(g);
      leaving_sum += g;
    }
    if (out) out->push_back(p_.obstacle.solid_at(c[0], c[1], c[2]) ? 1.0 : 0.0);
  });
  ShiftMass mass;
  if (!onward) mass.left = layer_cells + leaving_sum;
  if (!p_.geometry.block_beyond(a, sign > 0 ? 1 : 0)) mass.entered = layer_cells;

  pending_ = Pending{axis, sign, {}};
  if (f.odd_parity()) keep_returns(a, sign, onward, out);
  move_layers(axis, sign);
  return mass;
}

template <Lattice L, class Real>
void WindowShift<L, Real>::keep_returns(std::size_t a, int sign, std::optional<int> onward, std::vector<double>* out) {
  const AaPopulations<L, Real>& f = p_.populations;
  const std::array<int, 3>& extent = p_.geometry.extent();
  const int onward_extent = onward ? p_.geometry.split().extent(*onward)[a] : 0;
  for (const PreparedLink& l : p_.obstacle.links()) {
    std::array<int, 3> fluid = p_.geometry.padded_coordinates(l.fluid),
                       target = p_.geometry.padded_coordinates(l.solid);
    fluid[a] -= sign, target[a] -= sign;
    const double value = static_cast<double>(f[f.slot(l.dir, l.solid)]);
    if (fluid[a] >= 0 && fluid[a] < extent[a]) {
      pending_->returns.emplace_back(f.slot(l.dir, f.layout().index(target[0], target[1], target[2])), value);
    } else if (out) {
      target[a] += sign > 0 ? onward_extent : -extent[a];
      out->insert(out->end(), {static_cast<double>(target[0]), static_cast<double>(target[1]),
                               static_cast<double>(target[2]), static_cast<double>(l.dir), value});
    }
  }
}

template <Lattice L, class Real>
void WindowShift<L, Real>::move_layers(int axis, int sign) {
  const GridLayout& layout = p_.populations.layout();
  const int n_axis = p_.geometry.extent()[static_cast<std::size_t>(axis)];
  // Layers along an axis are contiguous blocks of the padded grid (a cell along x, a row of sx
  // elements along y, a plane of sxy along z), so the shift is a memmove of whole blocks per
  // population array: sequential traffic instead of strided walks. Ghost cells inside the
  // moved blocks move too; they are stale at an even parity and rebuilt at an odd one (end).
  const std::array<std::size_t, 3> block{1, layout.sx, layout.sxy};
  const std::size_t layer = block[static_cast<std::size_t>(axis)];
  // Blocks that hold the layers: one per (y, z) row for x, one per plane for y, one for z.
  std::vector<std::size_t> starts;
  if (axis == 0) {
    for (int z = 0; z < layout.nz; ++z)
      for (int y = 0; y < layout.ny; ++y) starts.push_back(layout.index(0, y, z));
  } else if (axis == 1) {
    // A row's sx elements counted from its ghost x = -1 hold the whole row, both ghosts included
    // (grid.hpp: sx >= nx + 2); counted from the line start they would not when nx + 2 < sx + x_begin.
    for (int z = 0; z < layout.nz; ++z) starts.push_back(layout.index(-1, 0, z));
  } else {
    starts.push_back(layout.index(-1, -1, 0));
  }
  const std::size_t moved = layer * static_cast<std::size_t>(n_axis - 1);
  Real* const data = p_.populations.data();
  const std::ptrdiff_t block_count = static_cast<std::ptrdiff_t>(starts.size());
#pragma omp parallel for collapse(2) schedule(static) if (p_.geometry.threaded())
  for (int q = 0; q < Q; ++q) {
    for (std::ptrdiff_t b = 0; b < block_count; ++b) {
      Real* const first = data + static_cast<std::size_t>(q) * layout.pop_stride + starts[b];
      if (sign > 0) {
        std::memmove(first, first + layer, moved * sizeof(Real));
        std::fill(first + moved, first + moved + layer, Real(0));  // rest at rho = 1 (shifted storage)
      } else {
        std::memmove(first + layer, first, moved * sizeof(Real));
        std::fill(first, first + layer, Real(0));
      }
    }
  }
}

template <Lattice L, class Real>
bool WindowShift<L, Real>::end(HaloMessages& messages) {
  if (!pending_) throw std::logic_error("end_shift: no shift has begun");
  p_.halo.check_message_count(messages, "end_shift");
  const int axis = pending_->axis, sign = pending_->sign;
  const auto a = static_cast<std::size_t>(axis);
  const std::array<int, 3>& extent = p_.geometry.extent();
  AaPopulations<L, Real>& f = p_.populations;
  std::vector<std::size_t> entering_solids;
  if (const std::optional<int> from = p_.geometry.block_beyond(a, sign > 0 ? 1 : 0)) {
    const std::vector<double>& in = messages.receive[p_.halo.index_of(*from)];
    const std::size_t layer_values = static_cast<std::size_t>(Q + 1) * static_cast<std::size_t>(extent[(a + 1) % 3]) *
                                     static_cast<std::size_t>(extent[(a + 2) % 3]);
    if (in.size() < layer_values || (in.size() - layer_values) % 5 != 0) {
      throw std::invalid_argument("end_shift: a layer of " + std::to_string(in.size()) + " values from rank " +
                                  std::to_string(*from) + ", expected " + std::to_string(layer_values) +
                                  " and five per returned population");
    }
    std::size_t k = 0;
    for_each_layer_cell(axis, sign > 0 ? extent[a] - 1 : 0, [&](const std::array<int, 3>& c) {
      const std::size_t cell = f.layout().index(c[0], c[1], c[2]);
      for (int q = 0; q < Q; ++q) f[f.slot(q, cell)] = static_cast<Real>(in[k++]);
      if (in[k++] != 0.0) entering_solids.push_back(p_.geometry.linear_index(c[0], c[1], c[2]));
    });
    for (; k < in.size(); k += 5) {
      const std::size_t at =
          f.layout().index(static_cast<int>(in[k]), static_cast<int>(in[k + 1]), static_cast<int>(in[k + 2]));
      pending_->returns.emplace_back(f.slot(static_cast<int>(in[k + 3]), at), in[k + 4]);
    }
  }
  p_.obstacle.shift_solid_cells(axis, sign, std::move(entering_solids));
  if (!f.odd_parity()) {
    pending_.reset();
    return false;
  }
  // At an odd parity the ghost slots hold copies of the old content: rebuild them, with the
  // adjacent blocks' new faces where split.
  f.template apply<false>(p_.lists.fill, p_.lists.fill_shifted, p_.inflow_velocity);
  if (p_.halo.empty()) {
    restore_returns();
    return false;
  }
  p_.halo.pack_fill(f, p_.inflow_velocity, messages);
  return true;
}

template <Lattice L, class Real>
void WindowShift<L, Real>::end_ghost_refresh(const HaloMessages& messages) {
  if (!pending_) throw std::logic_error("end_ghost_refresh: no shift is waiting for its ghosts");
  p_.halo.check_message_count(messages, "end_ghost_refresh");
  p_.halo.write_received(p_.populations, messages, false, "end_ghost_refresh");
  restore_returns();
}

}  // namespace settle::lbm
