#pragma once
// An obstacle inside a block's grid (Solver::set_obstacle; docs/lbm.md, "Walls inside the grid"):
// its solid cells, the solid cells of adjacent blocks in the ghost layer and one layer beyond, and
// its wall links prepared in slot terms with their rule's coefficients (lbm/wall_rules.hpp). After
// each kernel close() writes every link's returning population where the next kernel reads it and
// records the momentum the fluid gave the wall.
#include <omp.h>

#include <Eigen/Core>
#include <algorithm>
#include <array>
#include <cstdint>
#include <exception>
#include <optional>
#include <stdexcept>
#include <vector>

#include "lbm/aa_populations.hpp"
#include "lbm/block_geometry.hpp"
#include "lbm/far_values.hpp"
#include "lbm/lattice.hpp"
#include "lbm/solver.hpp"
#include "lbm/wall_rules.hpp"

namespace settle::lbm {

/// Below this many wall links their preparation runs on one thread: a parallel loop's wake-up
/// costs a few microseconds, a link about 0.1 us (docs/performance.md, "Small grids").
inline constexpr std::ptrdiff_t kLinksWorthThreads = 128;

/// A wall link in slot terms. The population coming back from the wall,
///   f_back = a f*_i(x) + b f*_i(x - c_i) + c f*_opp(i)(x)
///          + b2 f*_i(x - 2 c_i) + c2 f*_opp(i)(x - c_i) + wall,
/// goes where the next kernel reads f_opp(i)(x) (docs/lbm.md, "Walls inside the grid").
struct PreparedLink {
  // Padded indices, unwrapped: x +- c_i may be a ghost (a periodic image or a cell of an adjacent
  // block). The kernels of x read and write there, and the ghosts hold what crossed the face when
  // the links close, so no index needs the cell's home.
  std::size_t fluid = 0;   ///< the fluid cell x
  std::size_t solid = 0;   ///< x + c_i
  std::size_t second = 0;  ///< x - c_i when it is fluid (read only when b != 0), else x
  std::size_t behind = 0;  ///< x - c_i: where the odd kernel puts f*_opp(i)(x)
  std::size_t third = 0;   ///< x - 2 c_i when the quadratic rule reads it (b2 or c2 != 0), else x
  /// With the quadratic rule and x - c_i a ghost: the entry of FarValues that holds the third value
  /// (kNoFar otherwise; kFarUnplanned between prepare_link and plan_far_values).
  std::size_t far = kNoFar;
  int dir = 0;
  double a = 1.0, b = 0.0, c = 0.0, b2 = 0.0, c2 = 0.0, wall = 0.0;
  Eigen::Vector3d wall_velocity = Eigen::Vector3d::Zero();

  static constexpr std::size_t kNoFar = FarValues::kNone, kFarUnplanned = kNoFar - 1;
};

template <Lattice L, class Real>
class BlockObstacle {
 public:
  static constexpr int Q = L::Q;

  explicit BlockObstacle(const BlockGeometry& geometry) : geometry_(geometry) {}

  bool solid_at(int x, int y, int z) const {
    return !solid_flag_.empty() && solid_flag_[geometry_.linear_index(x, y, z)] != 0;
  }
  /// The solid cells, linear indices ascending.
  const std::vector<std::size_t>& solid_cells() const { return solid_cells_; }
  WallRule rule() const { return rule_; }
  const std::vector<PreparedLink>& links() const { return links_; }
  const std::vector<Eigen::Vector3d>& wall_momentum() const { return wall_momentum_; }
  FarValues& far_values() { return far_; }
  const FarValues& far_values() const { return far_; }

  /// Replaces the obstacle (Solver::set_obstacle says what it must be); `halo_ranks` are the adjacent
  /// blocks a far value may be asked of.
  void set(const Obstacle& obstacle, const std::vector<int>& halo_ranks);
  /// Replaces the solid cells (ascending linear indices) and drops the links.
  void set_solid_cells(std::vector<std::size_t> cells);
  /// The solid cells move with the content in a window shift (those leaving the grid are dropped,
  /// `entering` join); the links are dropped, to be set again at the obstacle's new place.
  void shift_solid_cells(int axis, int sign, std::vector<std::size_t> entering);

  /// Closes every wall link after the kernel of the given parity and records its momentum
  /// exchange. After an even kernel f*_j(y) sits in slot opp(j) at y and the odd kernel of x will
  /// read f_opp(i)(x) from slot i at x + c_i (a solid cell); after an odd kernel f*_i(x) sits in
  /// slot i at x + c_i, f*_i(x - c_i) in slot i at x, f*_opp(i)(x) in slot opp(i) at x - c_i, and
  /// the even kernel reads f_opp(i)(x) from slot opp(i) at x. No link writes a slot another
  /// reads (writes go to solid cells after an even kernel, reads to fluid ones; after an odd
  /// one the written slot opp(i) at x would be read only by a link from x + c_i, a solid cell).
  template <bool Odd>
  void close(AaPopulations<L, Real>& f);
  /// Sets the solid cells to rest (stored 0), so that what streams into them from the fluid
  /// does not pile up over the run. After the odd step's links have read their slots.
  void reset_solid_cells(AaPopulations<L, Real>& f) const {
    for (const std::size_t n : solid_cells_) {
      const std::size_t cell = geometry_.padded_of_linear(n);
      for (int q = 0; q < Q; ++q) f[f.slot(q, cell)] = Real(0);
    }
  }

 private:
  enum class Site { outside, fluid, solid };
  /// What lies at x + d for interior x, |d| <= 1 per axis: a cell of this block, a ghost, or nothing.
  Site site_of(const std::array<int, 3>& x, const std::array<int, 3>& d) const {
    bool ghost = false;
    const auto c = geometry_.site({x[0] + d[0], x[1] + d[1], x[2] + d[2]}, ghost);
    if (!c) return Site::outside;
    const bool solid = ghost ? std::binary_search(ghost_solids_.begin(), ghost_solids_.end(),
                                                  geometry_.layout().index((*c)[0], (*c)[1], (*c)[2]))
                             : solid_at((*c)[0], (*c)[1], (*c)[2]);
    return solid ? Site::solid : Site::fluid;
  }
  /// True when x - c_i and x - 2 c_i are fluid cells of the lattice (x in block coordinates).
  bool has_two_fluid_cells_behind(const std::array<int, 3>& x, const std::array<int, 3>& c) const {
    for (const int k : {1, 2}) {
      const auto solid = solid_near({x[0] - k * c[0], x[1] - k * c[1], x[2] - k * c[2]});
      if (!solid || *solid) return false;
    }
    return true;
  }
  /// Whether cell y (block coordinates, at most two cells beyond the block's faces) is solid; empty
  /// beyond a face of the lattice that is not periodic.
  std::optional<bool> solid_near(std::array<int, 3> y) const;
  std::size_t far_key(const std::array<int, 3>& y) const {
    const auto n = [](int v) { return static_cast<std::size_t>(v + 2); };
    const std::array<int, 3>& e = geometry_.extent();
    return n(y[0]) + n(e[0] + 2) * (n(y[1]) + n(e[1] + 2) * n(y[2]));
  }
  std::size_t upstream_of(std::size_t cell, int i) const {
    return static_cast<std::size_t>(static_cast<std::ptrdiff_t>(cell) - geometry_.layout().offset(L::set.c[i]));
  }
  std::size_t slot(int q, std::size_t cell) const {
    return static_cast<std::size_t>(q) * geometry_.layout().pop_stride + cell;
  }
  PreparedLink prepare_link(const WallLink& link, WallRule rule) const;
  std::vector<PreparedLink> prepare_links(const Obstacle& obstacle) const;
  /// Assigns the far values of the links prepare_link marked: read here, or asked of their block.
  void plan_far_values(const Obstacle& obstacle, const std::vector<int>& halo_ranks);

  const BlockGeometry& geometry_;
  // Solid cells: a flag per interior cell, allocated with the first obstacle, and their linear
  // indices in ascending order.
  std::vector<std::uint8_t> solid_flag_;
  std::vector<std::size_t> solid_cells_;
  std::vector<PreparedLink> links_;
  std::vector<Eigen::Vector3d> wall_momentum_;  ///< each link's in the last step
  /// Solid cells of adjacent blocks in the ghost layer (padded indices, ascending): where this
  /// block's links end across a block face.
  std::vector<std::size_t> ghost_solids_;
  /// Solid cells one layer beyond the ghosts (far_key, ascending): the quadratic rule's x - 2 c_i.
  std::vector<std::size_t> far_solids_;
  WallRule rule_ = WallRule::bouzidi;
  FarValues far_;
};

template <Lattice L, class Real>
void BlockObstacle<L, Real>::set(const Obstacle& obstacle, const std::vector<int>& halo_ranks) {
  std::vector<std::size_t> cells, ghosts;
  cells.reserve(obstacle.solid_cells.size());
  // A free-slip or outflow face copies populations from cells of its own layer, which would
  // carry a solid cell's scratch into the fluid; walls and inlets copy only within a cell. The
  // block that holds a cell checks it.
  const FaceKinds& kinds = geometry_.face_kinds();
  const std::array<int, 3>& extent = geometry_.extent();
  for (const auto& cell : obstacle.solid_cells) {
    bool ghost = false;
    const auto c = geometry_.site(cell, ghost);
    if (!c) throw std::invalid_argument("set_obstacle: a solid cell lies outside the lattice");
    const std::size_t padded = geometry_.layout().index((*c)[0], (*c)[1], (*c)[2]);
    if (ghost) {
      ghosts.push_back(padded);
      continue;
    }
    cells.push_back(geometry_.linear_index((*c)[0], (*c)[1], (*c)[2]));
    for (std::size_t a = 0; a < 3; ++a) {
      for (const int side : {0, 1}) {
        const Boundary kind = kinds[a][static_cast<std::size_t>(side)];
        const bool on_face = (*c)[a] == (side == 0 ? 0 : extent[a] - 1) && !geometry_.has_block_beyond(a, side, true);
        if ((kind == Boundary::free_slip || kind == Boundary::outflow) && on_face) {
          throw std::invalid_argument("set_obstacle: a solid cell lies on a free-slip or outflow face");
        }
      }
    }
  }
  std::sort(cells.begin(), cells.end());
  cells.erase(std::unique(cells.begin(), cells.end()), cells.end());
  std::sort(ghosts.begin(), ghosts.end());
  ghosts.erase(std::unique(ghosts.begin(), ghosts.end()), ghosts.end());
  // Every block refuses, so that none waits for another's exchange.
  if (obstacle.rule == WallRule::quadratic && geometry_.split().thinnest_block() < 2) {
    throw std::invalid_argument(
        "set_obstacle: the quadratic rule reads two cells behind a link, which needs blocks at least two cells "
        "thick along a split axis");
  }
  std::vector<std::size_t> far;
  for (const auto& cell : obstacle.far_solid_cells) {
    for (std::size_t a = 0; a < 3; ++a) {
      if (cell[a] < -2 || cell[a] > extent[a] + 1) {
        throw std::invalid_argument("set_obstacle: a far solid cell lies more than two cells beyond the block");
      }
    }
    far.push_back(far_key(cell));
  }
  std::sort(far.begin(), far.end());
  set_solid_cells(std::move(cells));
  ghost_solids_ = std::move(ghosts);
  far_solids_ = std::move(far);
  rule_ = obstacle.rule;
  links_ = prepare_links(obstacle);
  plan_far_values(obstacle, halo_ranks);
  wall_momentum_.assign(links_.size(), Eigen::Vector3d::Zero());
}

template <Lattice L, class Real>
void BlockObstacle<L, Real>::set_solid_cells(std::vector<std::size_t> cells) {
  for (const std::size_t n : solid_cells_) solid_flag_[n] = 0;
  links_.clear();
  wall_momentum_.clear();
  ghost_solids_.clear();
  far_solids_.clear();
  far_.clear();
  solid_cells_ = std::move(cells);
  if (solid_cells_.empty()) return;
  if (solid_flag_.empty()) solid_flag_.assign(geometry_.cell_count(), 0);
  for (const std::size_t n : solid_cells_) solid_flag_[n] = 1;
}

template <Lattice L, class Real>
void BlockObstacle<L, Real>::shift_solid_cells(int axis, int sign, std::vector<std::size_t> entering) {
  if (solid_cells_.empty() && entering.empty()) {
    ghost_solids_.clear(), far_solids_.clear(), links_.clear(), wall_momentum_.clear(), far_.clear();
    return;
  }
  const auto a = static_cast<std::size_t>(axis);
  std::vector<std::size_t> moved;
  for (const std::size_t n : solid_cells_) {
    std::array<int, 3> c = geometry_.cell_of_linear(n);
    c[a] -= sign;
    if (c[a] < 0 || c[a] >= geometry_.extent()[a]) continue;
    moved.push_back(geometry_.linear_index(c[0], c[1], c[2]));
  }
  moved.insert(moved.end(), entering.begin(), entering.end());
  std::sort(moved.begin(), moved.end());
  set_solid_cells(std::move(moved));
}

template <Lattice L, class Real>
template <bool Odd>
void BlockObstacle<L, Real>::close(AaPopulations<L, Real>& f) {
  Real* const A = f.data();
  const std::ptrdiff_t count = static_cast<std::ptrdiff_t>(links_.size());
#pragma omp parallel for schedule(static) if (geometry_.threaded() && count > 4096)
  for (std::ptrdiff_t k = 0; k < count; ++k) {
    const PreparedLink& l = links_[static_cast<std::size_t>(k)];
    const int i = l.dir, o = opposite(i);
    const std::size_t in_slot = Odd ? slot(i, l.solid) : slot(o, l.fluid);
    const std::size_t out_slot = Odd ? slot(o, l.fluid) : slot(i, l.solid);
    const double f_in = static_cast<double>(A[in_slot]);
    const double f_second = l.b != 0.0 ? static_cast<double>(Odd ? A[slot(i, l.fluid)] : A[slot(o, l.second)]) : 0.0;
    const double f_opposite = l.c != 0.0 ? static_cast<double>(Odd ? A[slot(o, l.behind)] : A[slot(i, l.fluid)]) : 0.0;
    // The quadratic rule's third points: f*_i(x - 2c_i) and f*_opp(i)(x - c_i).
    // A link whose x - c_i is a ghost reads the one it needs from far_ (plan_far_values).
    const double far = l.far != PreparedLink::kNoFar ? far_.value(l.far) : 0.0;
    const double f_third = l.b2 == 0.0 ? 0.0
                           : l.far != PreparedLink::kNoFar
                               ? far
                               : static_cast<double>(Odd ? A[slot(i, l.behind)] : A[slot(o, l.third)]);
    const double f_opposite_behind = l.c2 == 0.0 ? 0.0
                                     : l.far != PreparedLink::kNoFar
                                         ? far
                                         : static_cast<double>(Odd ? A[slot(o, l.third)] : A[slot(i, l.behind)]);
    const Real back = static_cast<Real>(l.a * f_in + l.b * f_second + l.c * f_opposite + l.b2 * f_third +
                                        l.c2 * f_opposite_behind + l.wall);
    A[out_slot] = back;
    // Shifted storage holds f - w: the momentum needs f itself.
    const double w = L::set.w[i];
    const double f_out = f_in + w, f_back = static_cast<double>(back) + w;
    const auto& c = L::set.c[i];
    wall_momentum_[static_cast<std::size_t>(k)] =
        Eigen::Vector3d(c[0], c[1], c[2]) * (f_out + f_back) - l.wall_velocity * (f_out - f_back);
  }
}

template <Lattice L, class Real>
std::vector<PreparedLink> BlockObstacle<L, Real>::prepare_links(const Obstacle& obstacle) const {
  const auto count = static_cast<std::ptrdiff_t>(obstacle.links.size());
  std::vector<PreparedLink> prepared(obstacle.links.size());
  // A moving body's links are prepared every step. An exception may not leave a parallel region:
  // the first bad link's (the serial loop's) is kept and thrown after it.
  std::ptrdiff_t first_bad = count;
  std::exception_ptr error;
#pragma omp parallel for schedule(static) if (geometry_.threaded() && count > kLinksWorthThreads)
  for (std::ptrdiff_t k = 0; k < count; ++k) {
    try {
      prepared[static_cast<std::size_t>(k)] = prepare_link(obstacle.links[static_cast<std::size_t>(k)], obstacle.rule);
    } catch (...) {
#pragma omp critical(settle_prepare_links)
      if (k < first_bad) first_bad = k, error = std::current_exception();
    }
  }
  if (error) std::rethrow_exception(error);
  return prepared;
}

template <Lattice L, class Real>
PreparedLink BlockObstacle<L, Real>::prepare_link(const WallLink& link, WallRule rule) const {
  if (link.dir < 1 || link.dir >= Q) throw std::invalid_argument("set_obstacle: link direction out of range");
  if (!(link.q > 0.0 && link.q <= 1.0)) throw std::invalid_argument("set_obstacle: link fraction q outside (0, 1]");
  const auto x = geometry_.resolve(link.cell[0], link.cell[1], link.cell[2]);
  const auto& c = L::set.c[link.dir];
  if (solid_at(x[0], x[1], x[2]) || site_of(x, c) != Site::solid) {
    throw std::invalid_argument("set_obstacle: a link must lead from a fluid cell to a solid one");
  }
  const bool has_second = site_of(x, {-c[0], -c[1], -c[2]}) == Site::fluid;
  const bool has_third = rule == WallRule::quadratic && has_two_fluid_cells_behind(x, c);
  const WallCoefficients k = wall_coefficients(rule, link.q, has_second, has_third);
  PreparedLink p;
  p.fluid = geometry_.layout().index(x[0], x[1], x[2]);
  p.solid = static_cast<std::size_t>(static_cast<std::ptrdiff_t>(p.fluid) + geometry_.layout().offset(c));
  p.behind = upstream_of(p.fluid, link.dir);
  p.second = has_second ? p.behind : p.fluid;
  p.third = p.fluid;
  p.dir = link.dir;
  p.wall_velocity = link.wall_velocity;
  p.a = k.a, p.b = k.b, p.c = k.c, p.b2 = k.b2, p.c2 = k.c2;
  p.wall = k.wall_term(moving_wall_term(L::set.w[link.dir], c, link.wall_velocity));
  if (k.reads_third) {
    const std::array<int, 3>& extent = geometry_.extent();
    bool second_inside = true;
    for (std::size_t a = 0; a < 3; ++a) second_inside = second_inside && x[a] - c[a] >= 0 && x[a] - c[a] < extent[a];
    // A ghost's neighbour x - 2 c_i lies beyond the padded block: its value comes from its home.
    if (second_inside) {
      p.third = upstream_of(p.behind, link.dir);
    } else {
      p.far = PreparedLink::kFarUnplanned;
    }
  }
  return p;
}

template <Lattice L, class Real>
std::optional<bool> BlockObstacle<L, Real>::solid_near(std::array<int, 3> y) const {
  const std::array<int, 3>& extent = geometry_.extent();
  int overhang = 0;  // how far beyond the block's faces, the largest over the axes
  for (std::size_t a = 0; a < 3; ++a) {
    if (y[a] >= 0 && y[a] < extent[a]) continue;
    const int side = y[a] < 0 ? 0 : 1;
    if (geometry_.has_block_beyond(a, side, true)) {
      overhang = std::max(overhang, side == 0 ? -y[a] : y[a] - extent[a] + 1);
      continue;
    }
    if (geometry_.boundaries()[a] != Boundary::periodic) return std::nullopt;
    y[a] = ((y[a] % extent[a]) + extent[a]) % extent[a];  // one block along a periodic axis
  }
  if (overhang == 0) return solid_at(y[0], y[1], y[2]);
  if (overhang == 1)
    return std::binary_search(ghost_solids_.begin(), ghost_solids_.end(), geometry_.layout().index(y[0], y[1], y[2]));
  return std::binary_search(far_solids_.begin(), far_solids_.end(), far_key(y));
}

template <Lattice L, class Real>
void BlockObstacle<L, Real>::plan_far_values(const Obstacle& obstacle, const std::vector<int>& halo_ranks) {
  far_.reset(halo_ranks.size());
  const BlockSplit& split = geometry_.split();
  const std::array<int, 3> origin = split.offset(split.rank);
  for (std::size_t k = 0; k < links_.size(); ++k) {
    PreparedLink& p = links_[k];
    if (p.far != PreparedLink::kFarUnplanned) continue;
    const auto x = geometry_.resolve(obstacle.links[k].cell[0], obstacle.links[k].cell[1], obstacle.links[k].cell[2]);
    const auto& c = L::set.c[p.dir];
    // q < 1/2 reads f*_i(x - 2 c_i), q >= 1/2 reads f*_opp(i)(x - c_i).
    const int steps_back = p.b2 != 0.0 ? 2 : 1, j = p.b2 != 0.0 ? p.dir : opposite(p.dir);
    std::array<int, 3> y{};
    for (std::size_t a = 0; a < 3; ++a) {
      const int g = split.global[a];
      y[a] = ((x[a] - steps_back * c[a] + origin[a]) % g + g) % g;  // fluid, so inside or across a wrap
    }
    const int home = split.owner(y);
    const std::array<int, 3> at = split.offset(home);
    for (std::size_t a = 0; a < 3; ++a) y[a] -= at[a];
    if (home == split.rank) {
      p.far = far_.add_local(geometry_.layout().index(y[0], y[1], y[2]), j);
      continue;
    }
    // x - 2 c_i lies at most one cell beyond the ghosts, in an adjacent block: set() refuses
    // splits with blocks thinner than two cells.
    const auto n = std::find(halo_ranks.begin(), halo_ranks.end(), home);
    if (n == halo_ranks.end())
      throw std::logic_error("halo: rank " + std::to_string(home) + " is not an adjacent block");
    p.far = far_.add_request(static_cast<std::size_t>(n - halo_ranks.begin()), y, j);
  }
}

}  // namespace settle::lbm
