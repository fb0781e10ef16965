#pragma once
// The fluid solver of one block: the composition of the parts of lbm/ (docs/lbm.md, "Files"),
// templated over lattice, collision and storage type. The kernel and the relaxation rates are in
// lbm/aa_kernel.hpp, the population array and its parity in lbm/aa_populations.hpp, the per-cell
// force in lbm/force_field.hpp, where cells lie in lbm/block_geometry.hpp.
#include <algorithm>
#include <cmath>
#include <cstring>
#include <exception>
#include <limits>
#include <stdexcept>
#include <string>

#include "lbm/aa_kernel.hpp"
#include "lbm/aa_populations.hpp"
#include "lbm/block_exchange.hpp"
#include "lbm/block_geometry.hpp"
#include "lbm/block_halo.hpp"
#include "lbm/block_obstacle.hpp"
#include "lbm/collision.hpp"
#include "lbm/force_field.hpp"
#include "lbm/grid.hpp"
#include "lbm/lattice.hpp"
#include "lbm/solver.hpp"

namespace settle::lbm {

template <Lattice L, class Collision, class Real>
class AaSolver final : public Solver, public BlockExchange {
 public:
  static constexpr int Q = L::Q;

  explicit AaSolver(const SolverConfig& config)
      : config_(config),
        geometry_(config, sizeof(Real), Q),
        threaded_(geometry_.threaded()),
        populations_(geometry_),
        forces_(geometry_.cell_count(), threaded_),
        kernel_(config, threaded_),
        block_lists_(build_block_lists<L>(layout(), geometry_.face_kinds(), geometry_.split())),
        halo_(std::move(block_lists_.halo), geometry_),
        inflow_velocity_(config.inflow_velocity),
        obstacle_(geometry_) {
    populations_.zero_fill();
  }

  const SolverConfig& config() const override { return config_; }
  std::int64_t step_count() const override { return populations_.step_count(); }
  int velocity_count() const override { return Q; }
  BlockExchange& block_exchange() override { return *this; }
  const BlockExchange& block_exchange() const override { return *this; }

  void step() override {
    if (!halo_.empty()) {
      throw std::logic_error("step: a block of a split lattice steps by begin_step and end_step around its exchange");
    }
    begin_local();
    end_local();
  }

  // --- the exchange protocol (BlockExchange)
  std::vector<int> halo_ranks() const override { return halo_.ranks(); }
  void begin_step(HaloMessages& messages) override {
    begin_local();
    halo_.pack(populations_, inflow_velocity_, messages);
  }
  void begin_step_faces(HaloMessages& messages) override {
    if (odd_parity()) {
      kernel_.template run_rows<true>(populations_, forces_, halo_.face_rows());
    } else {
      kernel_.template run_rows<false>(populations_, forces_, halo_.face_rows());
    }
    halo_.pack(populations_, inflow_velocity_, messages);
  }
  void step_interior() override {
    if (odd_parity()) {
      kernel_.template run_rows<true>(populations_, forces_, halo_.interior_rows());
      populations_.template apply<true>(lists_.fold, lists_.fold_shifted, inflow_velocity_);
    } else {
      kernel_.template run_rows<false>(populations_, forces_, halo_.interior_rows());
      populations_.template apply<false>(lists_.fill, lists_.fill_shifted, inflow_velocity_);
    }
  }
  std::vector<std::size_t> halo_receive_counts() const override { return halo_.receive_counts(odd_parity()); }
  bool exchanges_far_values() const override { return !halo_.empty() && obstacle_.rule() == WallRule::quadratic; }
  void far_requests(HaloMessages& messages) const override { obstacle_.far_values().requests(messages, halo_.size()); }
  void take_far_requests(const HaloMessages& messages) override {
    halo_.check_message_count(messages, "take_far_requests");
    obstacle_.far_values().take_requests(messages, {config_.nx, config_.ny, config_.nz}, Q);
  }
  void far_answers(HaloMessages& messages) const override {
    obstacle_.far_values().answers(messages, halo_.size(), populations_);
  }
  void take_far_answers(const HaloMessages& messages) override {
    halo_.check_message_count(messages, "take_far_answers");
    obstacle_.far_values().take_answers(messages, halo_ranks());
  }

  void end_step(const HaloMessages& messages) override {
    halo_.check_message_count(messages, "end_step");
    halo_.write_received(populations_, messages, odd_parity(), "end_step");
    end_local();
  }

  void initialise(const InitialField& field) override {
    populations_.set_step_count(0);
    const int nx = config_.nx, ny = config_.ny, nz = config_.nz;
#pragma omp parallel for collapse(2) schedule(static) if (threaded_)
    for (int z = 0; z < nz; ++z) {
      for (int y = 0; y < ny; ++y) {
        for (int x = 0; x < nx; ++x) {
          const CellState state = field(x, y, z);
          const double F[3] = {total_force(0, x, y, z), total_force(1, x, y, z), total_force(2, x, y, z)};
          // Stored momentum rho u - F/2, so that Guo's velocity (sum f c + F/2)/rho is u.
          const double rho = state.density;
          const double u[3] = {state.velocity.x() - 0.5 * F[0] / rho, state.velocity.y() - 0.5 * F[1] / rho,
                               state.velocity.z() - 0.5 * F[2] / rho};
          const std::size_t cell = layout().index(x, y, z);
          for (int i = 0; i < Q; ++i) {
            populations_[slot(i, cell)] =
                static_cast<Real>(shifted_equilibrium<L>(i, rho - 1.0, rho, u[0], u[1], u[2]));
          }
        }
      }
    }
  }

  ShiftMass shift(int axis, int sign) override {
    if (!halo_.empty()) {
      throw std::logic_error(
          "shift: a block of a split lattice shifts by begin_shift and end_shift around its exchanges");
    }
    HaloMessages none;
    const ShiftMass mass = begin_shift(axis, sign, none);
    end_shift(none);
    return mass;
  }
  ShiftMass begin_shift(int axis, int sign, HaloMessages& messages) override;
  bool end_shift(HaloMessages& messages) override;
  void end_ghost_refresh(const HaloMessages& messages) override;

  double total_mass() const override {
    // Sum over the interior slots: at an even parity these are the post-streaming
    // populations of each cell, at an odd parity the post-collision ones; streaming (with
    // the copy lists) is a permutation of populations, so both give sum(rho).
    double shifted_sum = 0.0;
    const int ny = config_.ny, nz = config_.nz;
#pragma omp parallel for collapse(2) reduction(+ : shifted_sum) schedule(static) if (threaded_)
    for (int z = 0; z < nz; ++z) {
      for (int y = 0; y < ny; ++y) shifted_sum += populations_.row_sum(y, z);
    }
    return static_cast<double>(cell_count()) + shifted_sum;
  }

  CellState cell_state(int x, int y, int z) const override {
    if (is_solid(x, y, z)) return {};
    double g[Q];
    gather_shifted(resolve(x, y, z), g);
    const auto F = cell_force(x, y, z);
    const auto m = macroscopic<L>(g, F.data());
    return {m.rho, Eigen::Vector3d(m.ux, m.uy, m.uz)};
  }

  void box_states(const std::array<int, 3>& origin, const std::array<int, 3>& extent, double* density,
                  const std::array<double*, 3>& velocity) const override {
    std::size_t n = 0;
    for (int k = 0; k < extent[2]; ++k)
      for (int j = 0; j < extent[1]; ++j, n += static_cast<std::size_t>(extent[0])) {
        const int y = origin[1] + j, z = origin[2] + k;
        const bool inside = origin[0] >= 0 && origin[0] + extent[0] <= config_.nx && y >= 0 && y < config_.ny &&
                            z >= 0 && z < config_.nz;
        for (int x0 = 0; x0 < extent[0]; x0 += kRowChunk) {
          const int count = std::min(kRowChunk, extent[0] - x0);
          const std::array<double*, 3> u{velocity[0] + n + x0, velocity[1] + n + x0, velocity[2] + n + x0};
          if (inside) {
            row_states({origin[0] + x0, y, z}, count, density + n + x0, u);
            continue;
          }
          for (int i = 0; i < count; ++i) {
            const CellState c = cell_state(origin[0] + x0 + i, y, z);
            density[n + x0 + i] = c.density;
            for (int a = 0; a < 3; ++a) u[a][i] = c.velocity[a];
          }
        }
      }
  }

  void cell_populations(int x, int y, int z, std::span<double> f) const override {
    if (f.size() < static_cast<std::size_t>(Q)) {
      throw std::invalid_argument("cell_populations: span holds fewer than Q values");
    }
    double g[Q];
    gather_shifted(resolve(x, y, z), g);
    for (int i = 0; i < Q; ++i) f[i] = g[i] + L::set.w[i];
  }

  void set_cell_populations(int x, int y, int z, std::span<const double> f) override {
    if (f.size() < static_cast<std::size_t>(Q)) {
      throw std::invalid_argument("set_cell_populations: span holds fewer than Q values");
    }
    const auto c = resolve(x, y, z);
    const std::size_t cell = layout().index(c[0], c[1], c[2]);
    for (int i = 0; i < Q; ++i) {
      // The slot gather_shifted reads f_i from at this parity (see there).
      const std::size_t source = odd_parity() ? slot(opposite(i), upstream_of(cell, i)) : slot(i, cell);
      populations_[source] = static_cast<Real>(f[i] - L::set.w[i]);
    }
  }

  double non_equilibrium(int x, int y, int z, std::span<double> f_neq) const override {
    if (f_neq.size() < static_cast<std::size_t>(Q)) {
      throw std::invalid_argument("non_equilibrium: span holds fewer than Q values");
    }
    const auto d = resolve(x, y, z);
    double g[Q];
    gather_shifted(d, g);
    const auto F = cell_force(d[0], d[1], d[2]);
    const Macroscopic<L> m = macroscopic<L>(g, F.data());
    for (int i = 0; i < Q; ++i) f_neq[i] = g[i] - shifted_equilibrium<L>(i, m.drho, m.rho, m.ux, m.uy, m.uz);
    return m.rho;
  }

  void refill_cell_with(const std::array<int, 3>& cell, double rho, const Eigen::Vector3d& u,
                        std::span<const double> non_equilibrium) override {
    if (non_equilibrium.size() < static_cast<std::size_t>(Q)) {
      throw std::invalid_argument("refill_cell_with: span holds fewer than Q values");
    }
    double f[Q];
    for (int i = 0; i < Q; ++i) {
      f[i] = shifted_equilibrium<L>(i, rho - 1.0, rho, u.x(), u.y(), u.z()) + non_equilibrium[i] + L::set.w[i];
    }
    set_cell_populations(cell[0], cell[1], cell[2], std::span<const double>(f, Q));
  }

  std::vector<double> density_field() const override {
    std::vector<double> rho(cell_count());
    for_each_cell_moments([&](std::size_t n, double density, double, double, double) { rho[n] = density; });
    return rho;
  }

  VectorField velocity_field() const override {
    VectorField u{std::vector<double>(cell_count()), std::vector<double>(cell_count()),
                  std::vector<double>(cell_count())};
    for_each_cell_moments([&](std::size_t n, double, double ux, double uy, double uz) {
      u.x[n] = ux;
      u.y[n] = uy;
      u.z[n] = uz;
    });
    return u;
  }

  FieldExtrema extrema() const override {
    const int ny = config_.ny, nz = config_.nz;
    // One partial result per row, reduced in row order afterwards: the same answer, locations
    // included, for every thread count (an OpenMP min/max reduction keeps no location).
    std::vector<FieldExtrema> rows(static_cast<std::size_t>(ny) * nz);
#pragma omp parallel for collapse(2) schedule(static) if (threaded_)
    for (int z = 0; z < nz; ++z) {
      for (int y = 0; y < ny; ++y) {
        FieldExtrema& row = rows[static_cast<std::size_t>(y) + static_cast<std::size_t>(ny) * z];
        row.min_density = std::numeric_limits<double>::infinity();
        row.max_density = -std::numeric_limits<double>::infinity();
        double max_u2 = -1.0;
        for_each_in_row(y, z, [&](int x, double rho, double ux, double uy, double uz) {
          if (solid_at(x, y, z)) return;
          const double u2 = ux * ux + uy * uy + uz * uz;
          // A NaN fails every comparison: test finiteness explicitly.
          row.finite = row.finite && std::isfinite(rho) && std::isfinite(u2);
          if (rho < row.min_density) row.min_density = rho, row.min_density_cell = {x, y, z};
          if (rho > row.max_density) row.max_density = rho, row.max_density_cell = {x, y, z};
          if (u2 > max_u2) max_u2 = u2, row.max_speed_cell = {x, y, z};
        });
        row.max_speed = std::sqrt(max_u2);
      }
    }
    return reduce_rows(rows);
  }

  /// Row-ordered reduction of extrema(); starts from the rest state (density 1, speed 0) as the
  /// single-pass version did, so an all-rest field reports its first cell.
  static FieldExtrema reduce_rows(const std::vector<FieldExtrema>& rows) {
    FieldExtrema e;
    for (const FieldExtrema& row : rows) e.merge_later(row);
    return e;
  }

  void add_force(int x, int y, int z, const Eigen::Vector3d& force) override {
    forces_.add(resolved_index(x, y, z), force);
  }
  void set_force(int x, int y, int z, const Eigen::Vector3d& force) override {
    forces_.set(resolved_index(x, y, z), force);
  }
  Eigen::Vector3d force(int x, int y, int z) const override { return forces_.at(resolved_index(x, y, z)); }
  void clear_forces() override { forces_.clear(); }
  std::size_t forced_cell_count() const override { return forces_.cells().size(); }

  void set_obstacle(const Obstacle& obstacle) override { obstacle_.set(obstacle, halo_ranks()); }
  void set_inflow_velocity(const Eigen::Vector3d& velocity) override {
    if (!velocity.allFinite() || velocity.norm() >= 0.3) {
      throw std::invalid_argument("set_inflow_velocity: must be finite with magnitude below 0.3");
    }
    inflow_velocity_ = velocity;
  }
  const Eigen::Vector3d& inflow_velocity() const override { return inflow_velocity_; }
  bool is_solid(int x, int y, int z) const override {
    const auto c = resolve(x, y, z);
    return solid_at(c[0], c[1], c[2]);
  }
  std::size_t solid_cell_count() const override { return obstacle_.solid_cells().size(); }
  std::vector<std::array<int, 3>> solid_cell_list() const override {
    std::vector<std::array<int, 3>> cells;
    cells.reserve(obstacle_.solid_cells().size());
    for (const std::size_t n : obstacle_.solid_cells()) cells.push_back(geometry_.cell_of_linear(n));
    return cells;
  }
  const std::vector<Eigen::Vector3d>& wall_momentum() const override { return obstacle_.wall_momentum(); }

  std::size_t bytes_per_cell_update() const override { return (2 * Q + 3) * sizeof(Real); }

  FluidState export_state() const override {
    FluidState state;
    state.layout = state_layout();
    state.step_count = populations_.step_count();
    state.populations = std::as_bytes(std::span<const Real>(populations_.data(), populations_.size()));
    state.forced_cells.reserve(forces_.cells().size());
    state.forced_values.reserve(3 * forces_.cells().size());
    for (const std::size_t n : forces_.cells()) {
      state.forced_cells.push_back(n);
      for (int a = 0; a < 3; ++a) state.forced_values.push_back(forces_.value(a, n));
    }
    state.solid_cells.assign(obstacle_.solid_cells().begin(), obstacle_.solid_cells().end());
    return state;
  }

  void import_state(const FluidState& state) override;

 private:
  bool odd_parity() const { return populations_.odd_parity(); }
  const GridLayout& layout() const { return geometry_.layout(); }
  std::size_t resolved_index(int x, int y, int z) const {
    const auto c = resolve(x, y, z);
    return linear_index(c[0], c[1], c[2]);
  }

  // A step is the kernel and the copies of the block's own faces (begin_local), the exchange with
  // adjacent blocks when split, and the rest (end_local). Walls inside the grid close last: after
  // an odd kernel once the fold (own faces and messages) has brought home what crossed a face,
  // after an even one once the fill has written the ghosts, so that a link may read its second
  // node from a ghost and write its returning population into one (BlockObstacle::close).
  void begin_local() {
    if (odd_parity()) {
      kernel_.template run<true>(populations_, forces_);
      populations_.template apply<true>(lists_.fold, lists_.fold_shifted, inflow_velocity_);
    } else {
      kernel_.template run<false>(populations_, forces_);
      populations_.template apply<false>(lists_.fill, lists_.fill_shifted, inflow_velocity_);
    }
  }
  void end_local() {
    if (odd_parity()) {
      obstacle_.far_values().template read_local<true>(populations_);
      obstacle_.template close<true>(populations_);
      obstacle_.reset_solid_cells(populations_);
    } else {
      obstacle_.far_values().template read_local<false>(populations_);
      obstacle_.template close<false>(populations_);
    }
    populations_.advance();
  }

  /// A window shift between begin_shift and the last of its exchanges. At an odd parity the
  /// ghosts are rebuilt from the moved content, which loses the populations that wall links
  /// returned into them (BlockObstacle::close writes a link's returning population where its fluid
  /// cell reads it, a ghost when the solid cell lies across a face): `returns` keeps them, moved
  /// with their fluid cells, to be written back (slot, value).
  struct PendingShift {
    int axis = 0, sign = 1;
    std::vector<std::pair<std::size_t, double>> returns;
  };
  /// The cells of layer k along the shift's axis, in message order.
  template <class Visit>
  void for_each_layer_cell(int axis, int k, Visit&& visit) const {
    const std::array<int, 3> extent{config_.nx, config_.ny, config_.nz};
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
  void move_layers(int axis, int sign);
  void restore_returns() {
    for (const auto& [at, value] : pending_shift_->returns) populations_[at] = static_cast<Real>(value);
    pending_shift_.reset();
  }

  std::size_t slot(int q, std::size_t cell) const { return populations_.slot(q, cell); }

  std::array<int, 3> resolve(int x, int y, int z) const { return geometry_.resolve(x, y, z); }

  /// Shifted post-streaming populations g_i(x) of interior cell c at the current parity.
  void gather_shifted(const std::array<int, 3>& c, double* g) const {
    populations_.gather(layout().index(c[0], c[1], c[2]), g);
  }

  static constexpr int kRowChunk = 64;

  /// cell_state of `count` <= kRowChunk consecutive interior cells of a row from `first`: each
  /// direction's slots are read along the row, and each cell's sums run over the directions in
  /// the order macroscopic() takes, so the values are bit for bit cell_state's.
  void row_states(const std::array<int, 3>& first, int count, double* density,
                  const std::array<double*, 3>& velocity) const {
    double drho[kRowChunk], jx[kRowChunk], jy[kRowChunk], jz[kRowChunk];
    const std::size_t row = layout().index(first[0], first[1], first[2]);
    const Real* source[Q];
    for (int i = 0; i < Q; ++i)
      source[i] = populations_.data() + (odd_parity() ? slot(opposite(i), upstream_of(row, i)) : slot(i, row));
      // Vectorised across the row, each cell's sums in registers in macroscopic()'s order.
#pragma omp simd
    for (int x = 0; x < count; ++x) {
      double d = 0.0, mx = 0.0, my = 0.0, mz = 0.0;
#pragma GCC unroll 32
      for (int i = 0; i < Q; ++i) {
        const double g = static_cast<double>(source[i][x]);
        d += g;
        mx += double(L::set.c[i][0]) * g;
        my += double(L::set.c[i][1]) * g;
        mz += double(L::set.c[i][2]) * g;
      }
      drho[x] = d;
      jx[x] = mx;
      jy[x] = my;
      jz[x] = mz;
    }
    const double* j[3] = {jx, jy, jz};
    for (int x = 0; x < count; ++x) {
      const int cx = first[0] + x;
      if (solid_at(cx, first[1], first[2])) {
        density[x] = 1.0;
        for (int a = 0; a < 3; ++a) velocity[a][x] = 0.0;
        continue;
      }
      const double rho = 1.0 + drho[x];
      const double inv_rho = 1.0 / rho;
      density[x] = rho;
      for (int a = 0; a < 3; ++a) velocity[a][x] = (j[a][x] + 0.5 * total_force(a, cx, first[1], first[2])) * inv_rho;
    }
  }

  /// Padded index of the neighbour x - c_i of padded cell x (a ghost at the faces).
  std::size_t upstream_of(std::size_t cell, int i) const { return populations_.upstream_of(cell, i); }

  std::array<double, 3> cell_force(int x, int y, int z) const {
    const auto c = resolve(x, y, z);
    return {total_force(0, c[0], c[1], c[2]), total_force(1, c[0], c[1], c[2]), total_force(2, c[0], c[1], c[2])};
  }

  double total_force(int axis, int x, int y, int z) const {
    return config_.body_force[axis] + forces_.value(axis, linear_index(x, y, z));
  }

  /// visit(n, rho, u) for every cell (linear index n), cell_state's values (solid cells: rho 1, u 0).
  template <class Visit>
  void for_each_cell_moments(Visit&& visit) const {
    const int ny = config_.ny, nz = config_.nz;
#pragma omp parallel for collapse(2) schedule(static) if (threaded_)
    for (int z = 0; z < nz; ++z) {
      for (int y = 0; y < ny; ++y) {
        for_each_in_row(y, z, [&](int x, double rho, double ux, double uy, double uz) {
          visit(linear_index(x, y, z), rho, ux, uy, uz);
        });
      }
    }
  }

  /// visit(x, rho, ux, uy, uz) along the whole row (y, z), x ascending: cell_state's values
  /// (solid cells: rho 1, u 0), read a chunk at a time by row_states.
  template <class Visit>
  void for_each_in_row(int y, int z, Visit&& visit) const {
    double rho[kRowChunk], u[3][kRowChunk];
    for (int x0 = 0; x0 < config_.nx; x0 += kRowChunk) {
      const int count = std::min(kRowChunk, config_.nx - x0);
      row_states({x0, y, z}, count, rho, {u[0], u[1], u[2]});
      for (int i = 0; i < count; ++i) visit(x0 + i, rho[i], u[0][i], u[1][i], u[2][i]);
    }
  }

  bool solid_at(int x, int y, int z) const { return obstacle_.solid_at(x, y, z); }

  bool has_block_beyond(std::size_t a, int side, bool through_wrap) const {
    return geometry_.has_block_beyond(a, side, through_wrap);
  }
  std::optional<int> block_beyond(std::size_t a, int side) const { return geometry_.block_beyond(a, side); }
  /// Coordinates of padded index p (inverse of GridLayout::index).
  std::array<int, 3> padded_coordinates(std::size_t p) const { return geometry_.padded_coordinates(p); }

  StateLayout state_layout() const {
    return {config_.nx,
            config_.ny,
            config_.nz,
            Q,
            static_cast<std::uint32_t>(sizeof(Real)),
            layout().x_begin,
            layout().sx,
            layout().sxy,
            layout().pop_stride,
            populations_.size()};
  }

  SolverConfig config_;
  BlockGeometry geometry_;
  bool threaded_;
  AaPopulations<L, Real> populations_;
  ForceField<Real> forces_;
  AaKernel<L, Collision, Real> kernel_;
  BlockLists block_lists_;  ///< the copy lists of the block's own faces (`local`); `halo` moved to halo_
  const CopyLists& lists_ = block_lists_.local;
  BlockHalo<L, Real> halo_;
  Eigen::Vector3d inflow_velocity_;
  BlockObstacle<L, Real> obstacle_;
  std::optional<PendingShift> pending_shift_;
};

template <Lattice L, class Collision, class Real>
void AaSolver<L, Collision, Real>::import_state(const FluidState& state) {
  // Everything is checked before anything is written, so a refused state leaves the solver as it was.
  if (!(state.layout == state_layout())) {
    throw std::invalid_argument(
        "import_state: the state was saved from a solver with another grid, lattice, "
        "precision or memory layout");
  }
  if (state.populations.size() != populations_.size() * sizeof(Real)) {
    throw std::invalid_argument("import_state: population buffer of " + std::to_string(state.populations.size()) +
                                " bytes, this solver holds " + std::to_string(populations_.size() * sizeof(Real)));
  }
  if (state.step_count < 0) throw std::invalid_argument("import_state: negative step count");
  if (state.forced_values.size() != 3 * state.forced_cells.size()) {
    throw std::invalid_argument("import_state: forced_values must hold three values per forced cell");
  }
  for (std::size_t k = 0; k < state.solid_cells.size(); ++k) {
    if (state.solid_cells[k] >= cell_count() || (k > 0 && state.solid_cells[k] <= state.solid_cells[k - 1])) {
      throw std::invalid_argument("import_state: solid cells must be ascending interior cell indices");
    }
  }
  std::vector<std::uint8_t> seen(cell_count(), 0);
  for (const std::uint64_t n : state.forced_cells) {
    if (n >= cell_count() || seen[n]) {
      throw std::invalid_argument("import_state: forced cell index " + std::to_string(n) + " out of range or repeated");
    }
    seen[n] = 1;
  }

  std::memcpy(populations_.data(), state.populations.data(), state.populations.size());
  populations_.set_step_count(state.step_count);
  forces_.restore(state.forced_cells, state.forced_values);
  obstacle_.set_solid_cells(std::vector<std::size_t>(state.solid_cells.begin(), state.solid_cells.end()));
}

template <Lattice L, class Collision, class Real>
ShiftMass AaSolver<L, Collision, Real>::begin_shift(int axis, int sign, HaloMessages& messages) {
  if (axis < 0 || axis > 2) throw std::invalid_argument("shift: axis must be 0, 1 or 2");
  if (sign != 1 && sign != -1) throw std::invalid_argument("shift: sign must be +1 or -1");
  if (pending_shift_) throw std::logic_error("begin_shift: the last shift has not ended");
  const auto a = static_cast<std::size_t>(axis);
  const std::array<int, 3> extent{config_.nx, config_.ny, config_.nz};
  // The window moves by `sign`: new cell k holds old cell k + sign. The layer at k = 0 (sign -1:
  // k = n - 1) of the old content leaves the block, into the adjacent block on that side or out
  // of the lattice (also across a periodic wrap: the window is not periodic); the opposite layer
  // enters from the adjacent block there, or at rest from outside.
  const int leaving = sign > 0 ? 0 : extent[a] - 1;
  const std::optional<int> onward = block_beyond(a, sign > 0 ? 0 : 1);
  messages.send.assign(halo_.size(), {});
  std::vector<double>* out = onward ? &messages.send[halo_.index_of(*onward)] : nullptr;
  double leaving_sum = 0.0, layer_cells = 0.0;
  for_each_layer_cell(axis, leaving, [&](const std::array<int, 3>& c) {
    const std::size_t cell = layout().index(c[0], c[1], c[2]);
    layer_cells += 1.0;
    for (int q = 0; q < Q; ++q) {
      const double g = static_cast<double>(populations_[slot(q, cell)]);
      if (out) out->push_back(g);
      leaving_sum += g;
    }
    if (out) out->push_back(solid_at(c[0], c[1], c[2]) ? 1.0 : 0.0);
  });
  ShiftMass mass;
  if (!onward) mass.left = layer_cells + leaving_sum;
  if (!block_beyond(a, sign > 0 ? 1 : 0)) mass.entered = layer_cells;

  PendingShift pending{axis, sign, {}};
  if (odd_parity()) {
    // The links' returned populations, with their fluid cells' new places; those whose fluid cell
    // moves into the onward block travel with the layer (its coordinates: x, y, z, direction, value).
    const int onward_extent = onward ? config_.split->extent(*onward)[a] : 0;
    for (const PreparedLink& l : obstacle_.links()) {
      std::array<int, 3> fluid = padded_coordinates(l.fluid), target = padded_coordinates(l.solid);
      fluid[a] -= sign, target[a] -= sign;
      const double value = static_cast<double>(populations_[slot(l.dir, l.solid)]);
      if (fluid[a] >= 0 && fluid[a] < extent[a]) {
        pending.returns.emplace_back(slot(l.dir, layout().index(target[0], target[1], target[2])), value);
      } else if (out) {
        target[a] += sign > 0 ? onward_extent : -extent[a];
        out->insert(out->end(), {static_cast<double>(target[0]), static_cast<double>(target[1]),
                                 static_cast<double>(target[2]), static_cast<double>(l.dir), value});
      }
    }
  }
  move_layers(axis, sign);
  pending_shift_ = std::move(pending);
  return mass;
}

template <Lattice L, class Collision, class Real>
void AaSolver<L, Collision, Real>::move_layers(int axis, int sign) {
  const std::array<int, 3> extent{config_.nx, config_.ny, config_.nz};
  const int n_axis = extent[static_cast<std::size_t>(axis)];
  // Layers along an axis are contiguous blocks of the padded grid (a cell along x, a row of sx
  // elements along y, a plane of sxy along z), so the shift is a memmove of whole blocks per
  // population array: sequential traffic instead of strided walks. Ghost cells inside the
  // moved blocks move too; they are stale at an even parity and rebuilt at an odd one (end_shift).
  const std::array<std::size_t, 3> block{1, layout().sx, layout().sxy};
  const std::size_t layer = block[static_cast<std::size_t>(axis)];
  // Blocks that hold the layers: one per (y, z) row for x, one per plane for y, one for z.
  std::vector<std::size_t> starts;
  if (axis == 0) {
    for (int z = 0; z < config_.nz; ++z)
      for (int y = 0; y < config_.ny; ++y) starts.push_back(layout().index(0, y, z));
  } else if (axis == 1) {
    // A row's sx elements counted from its ghost x = -1 hold the whole row, both ghosts included
    // (grid.hpp: sx >= nx + 2); counted from the line start they would not when nx + 2 < sx + x_begin.
    for (int z = 0; z < config_.nz; ++z) starts.push_back(layout().index(-1, 0, z));
  } else {
    starts.push_back(layout().index(-1, -1, 0));
  }
  const std::size_t moved = layer * static_cast<std::size_t>(n_axis - 1);
  Real* const data = populations_.data();
  const std::ptrdiff_t block_count = static_cast<std::ptrdiff_t>(starts.size());
#pragma omp parallel for collapse(2) schedule(static) if (threaded_)
  for (int q = 0; q < Q; ++q) {
    for (std::ptrdiff_t b = 0; b < block_count; ++b) {
      Real* const first = data + static_cast<std::size_t>(q) * layout().pop_stride + starts[b];
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

template <Lattice L, class Collision, class Real>
bool AaSolver<L, Collision, Real>::end_shift(HaloMessages& messages) {
  if (!pending_shift_) throw std::logic_error("end_shift: no shift has begun");
  halo_.check_message_count(messages, "end_shift");
  const int axis = pending_shift_->axis, sign = pending_shift_->sign;
  const auto a = static_cast<std::size_t>(axis);
  const std::array<int, 3> extent{config_.nx, config_.ny, config_.nz};
  std::vector<std::size_t> entering_solids;
  if (const std::optional<int> from = block_beyond(a, sign > 0 ? 1 : 0)) {
    const std::vector<double>& in = messages.receive[halo_.index_of(*from)];
    const std::size_t layer_values = static_cast<std::size_t>(Q + 1) * static_cast<std::size_t>(extent[(a + 1) % 3]) *
                                     static_cast<std::size_t>(extent[(a + 2) % 3]);
    if (in.size() < layer_values || (in.size() - layer_values) % 5 != 0) {
      throw std::invalid_argument("end_shift: a layer of " + std::to_string(in.size()) + " values from rank " +
                                  std::to_string(*from) + ", expected " + std::to_string(layer_values) +
                                  " and five per returned population");
    }
    std::size_t k = 0;
    for_each_layer_cell(axis, sign > 0 ? extent[a] - 1 : 0, [&](const std::array<int, 3>& c) {
      const std::size_t cell = layout().index(c[0], c[1], c[2]);
      for (int q = 0; q < Q; ++q) populations_[slot(q, cell)] = static_cast<Real>(in[k++]);
      if (in[k++] != 0.0) entering_solids.push_back(linear_index(c[0], c[1], c[2]));
    });
    for (; k < in.size(); k += 5) {
      const std::size_t at =
          layout().index(static_cast<int>(in[k]), static_cast<int>(in[k + 1]), static_cast<int>(in[k + 2]));
      pending_shift_->returns.emplace_back(slot(static_cast<int>(in[k + 3]), at), in[k + 4]);
    }
  }
  obstacle_.shift_solid_cells(axis, sign, std::move(entering_solids));
  if (!odd_parity()) {
    pending_shift_.reset();
    return false;
  }
  // At an odd parity the ghost slots hold copies of the old content: rebuild them, with the
  // adjacent blocks' new faces where split.
  populations_.template apply<false>(lists_.fill, lists_.fill_shifted, inflow_velocity_);
  if (halo_.empty()) {
    restore_returns();
    return false;
  }
  halo_.pack_fill(populations_, inflow_velocity_, messages);
  return true;
}

template <Lattice L, class Collision, class Real>
void AaSolver<L, Collision, Real>::end_ghost_refresh(const HaloMessages& messages) {
  if (!pending_shift_) throw std::logic_error("end_ghost_refresh: no shift is waiting for its ghosts");
  halo_.check_message_count(messages, "end_ghost_refresh");
  halo_.write_received(populations_, messages, false, "end_ghost_refresh");
  restore_returns();
}

}  // namespace settle::lbm
