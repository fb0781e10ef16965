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
#include "lbm/block_geometry.hpp"
#include "lbm/collision.hpp"
#include "lbm/force_field.hpp"
#include "lbm/grid.hpp"
#include "lbm/lattice.hpp"
#include "lbm/solver.hpp"
#include "lbm/wall_rules.hpp"

namespace settle::lbm {

/// Below this many wall links their preparation runs on one thread: a parallel loop's wake-up
/// costs a few microseconds, a link about 0.1 us (docs/performance.md, "Small grids").
inline constexpr std::ptrdiff_t kLinksWorthThreads = 128;

template <Lattice L, class Collision, class Real>
class AaSolver final : public Solver {
 public:
  static constexpr int Q = L::Q;

  explicit AaSolver(const SolverConfig& config)
      : config_(config),
        geometry_(config, sizeof(Real), Q),
        threaded_(geometry_.threaded()),
        populations_(geometry_),
        forces_(geometry_.cell_count(), threaded_),
        kernel_(config, threaded_),
        inflow_velocity_(config.inflow_velocity) {
    BlockLists block = build_block_lists<L>(layout(), geometry_.face_kinds(), geometry_.split());
    lists_ = std::move(block.local);
    halo_ = std::move(block.halo);
    split_rows();
    populations_.zero_fill();
  }

  const SolverConfig& config() const override { return config_; }
  std::int64_t step_count() const override { return populations_.step_count(); }
  int velocity_count() const override { return Q; }

  void step() override {
    if (!halo_.empty()) {
      throw std::logic_error("step: a block of a split lattice steps by begin_step and end_step around its exchange");
    }
    begin_local();
    end_local();
  }

  std::vector<int> halo_ranks() const override {
    std::vector<int> ranks;
    for (const HaloLinks& h : halo_) ranks.push_back(h.rank);
    return ranks;
  }

  void begin_step(HaloMessages& messages) override {
    begin_local();
    pack_messages(messages);
  }

  void begin_step_faces(HaloMessages& messages) override {
    if (odd_parity()) {
      kernel_.template run_rows<true>(populations_, forces_, face_rows_);
    } else {
      kernel_.template run_rows<false>(populations_, forces_, face_rows_);
    }
    pack_messages(messages);
  }

  void step_interior() override {
    if (odd_parity()) {
      kernel_.template run_rows<true>(populations_, forces_, interior_rows_);
      populations_.template apply<true>(lists_.fold, lists_.fold_shifted, inflow_velocity_);
    } else {
      kernel_.template run_rows<false>(populations_, forces_, interior_rows_);
      populations_.template apply<false>(lists_.fill, lists_.fill_shifted, inflow_velocity_);
    }
  }

  std::vector<std::size_t> halo_receive_counts() const override {
    std::vector<std::size_t> counts;
    for (const HaloLinks& h : halo_) counts.push_back(odd_parity() ? h.fold_receive.size() : h.fill_receive.size());
    return counts;
  }

  bool exchanges_far_values() const override { return !halo_.empty() && obstacle_rule_ == WallRule::quadratic; }
  void far_requests(HaloMessages& messages) const override {
    messages.send.assign(halo_.size(), {});
    for (std::size_t k = 0; k < far_.requests.size(); ++k) messages.send[k] = far_.requests[k];
  }
  void take_far_requests(const HaloMessages& messages) override;
  void far_answers(HaloMessages& messages) const override {
    messages.send.assign(halo_.size(), {});
    for (std::size_t k = 0; k < far_.asked.size(); ++k) {
      const std::vector<double>& asked = far_.asked[k];
      for (std::size_t n = 0; n < asked.size(); n += 4) {
        const auto at = [&](std::size_t m) { return static_cast<int>(asked[n + m]); };
        const std::size_t cell = layout().index(at(0), at(1), at(2));
        messages.send[k].push_back(odd_parity() ? post_collision<true>(at(3), cell)
                                                : post_collision<false>(at(3), cell));
      }
    }
  }
  void take_far_answers(const HaloMessages& messages) override;

  void end_step(const HaloMessages& messages) override {
    check_message_count(messages, "end_step");
    write_received(messages, odd_parity(), "end_step");
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

  void set_obstacle(const Obstacle& obstacle) override;
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
  std::size_t solid_cell_count() const override { return solid_cells_.size(); }
  std::vector<std::array<int, 3>> solid_cell_list() const override {
    std::vector<std::array<int, 3>> cells;
    cells.reserve(solid_cells_.size());
    const std::size_t nx = static_cast<std::size_t>(config_.nx), ny = static_cast<std::size_t>(config_.ny);
    for (const std::size_t n : solid_cells_) {
      cells.push_back({static_cast<int>(n % nx), static_cast<int>(n / nx % ny), static_cast<int>(n / (nx * ny))});
    }
    return cells;
  }
  const std::vector<Eigen::Vector3d>& wall_momentum() const override { return wall_momentum_; }

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
    state.solid_cells.assign(solid_cells_.begin(), solid_cells_.end());
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
  // node from a ghost and write its returning population into one (close_wall_links).
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
      read_local_far_values<true>();
      close_wall_links<true>();
      reset_solid_cells();
    } else {
      read_local_far_values<false>();
      close_wall_links<false>();
    }
    populations_.advance();
  }

  /// Writes what the adjacent blocks sent into the slots of their links: the fold after an odd
  /// kernel, the fill after an even one.
  void write_received(const HaloMessages& messages, bool fold, const char* who) {
    Real* const data = populations_.data();
    for (std::size_t k = 0; k < halo_.size(); ++k) {
      const std::vector<std::size_t>& slots = fold ? halo_[k].fold_receive : halo_[k].fill_receive;
      const std::vector<double>& values = messages.receive[k];
      if (values.size() != slots.size()) {
        throw std::invalid_argument(std::string(who) + ": a message of " + std::to_string(values.size()) +
                                    " values from rank " + std::to_string(halo_[k].rank) + ", expected " +
                                    std::to_string(slots.size()));
      }
      for (std::size_t j = 0; j < slots.size(); ++j) data[slots[j]] = static_cast<Real>(values[j]);
    }
  }
  void check_message_count(const HaloMessages& messages, const char* who) const {
    if (messages.receive.size() != halo_.size()) {
      throw std::invalid_argument(std::string(who) + ": " + std::to_string(messages.receive.size()) + " messages for " +
                                  std::to_string(halo_.size()) + " adjacent blocks");
    }
  }

  /// A window shift between begin_shift and the last of its exchanges. At an odd parity the
  /// ghosts are rebuilt from the moved content, which loses the populations that wall links
  /// returned into them (close_wall_links writes a link's returning population where its fluid
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

  void pack_messages(HaloMessages& messages) const {
    messages.send.resize(halo_.size());
    for (std::size_t k = 0; k < halo_.size(); ++k) {
      if (odd_parity()) {
        pack<true>(halo_[k].send.fold, halo_[k].send.fold_shifted, messages.send[k]);
      } else {
        pack<false>(halo_[k].send.fill, halo_[k].send.fill_shifted, messages.send[k]);
      }
    }
  }

  /// The values of a block's send entries (HaloLinks), each as the copy lists would store it.
  template <bool Odd>
  void pack(const std::vector<CopyEntry>& list, const std::vector<ShiftedCopyEntry>& shifted,
            std::vector<double>& message) const {
    const Real* const data = populations_.data();
    message.assign(list.size() + shifted.size(), 0.0);
    for (const CopyEntry& e : list) message[e.dst] = static_cast<double>(data[e.src]);
    for (const ShiftedCopyEntry& e : shifted)
      message[e.dst] = static_cast<double>(populations_.template shifted_value<Odd>(e, inflow_velocity_));
  }
  std::size_t slot(int q, std::size_t cell) const { return populations_.slot(q, cell); }

  /// The rows whose kernel results an adjacent block receives: those within kFaceRows of a face
  /// the block shares with another block along y or z (a link's source cell is next to the face,
  /// and an inlet's or outlet's value reads the moments of a cell one further in; a margin of
  /// three covers both). A block cut along x has a face cell in every row: all rows are face rows.
  void split_rows() {
    face_rows_.clear(), interior_rows_.clear();
    constexpr int kFaceRows = 3;
    const int ny = config_.ny, nz = config_.nz;
    const auto shares = [&](std::size_t axis, int side) { return has_block_beyond(axis, side, true); };
    const bool all_faces = shares(0, 0) || shares(0, 1);
    for (int z = 0; z < nz; ++z)
      for (int y = 0; y < ny; ++y) {
        const bool near = all_faces || (shares(1, 0) && y < kFaceRows) || (shares(1, 1) && y >= ny - kFaceRows) ||
                          (shares(2, 0) && z < kFaceRows) || (shares(2, 1) && z >= nz - kFaceRows);
        (near ? face_rows_ : interior_rows_).push_back(y + ny * z);
      }
  }

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

  bool solid_at(int x, int y, int z) const { return !solid_flag_.empty() && solid_flag_[linear_index(x, y, z)] != 0; }

  bool has_block_beyond(std::size_t a, int side, bool through_wrap) const {
    return geometry_.has_block_beyond(a, side, through_wrap);
  }
  std::optional<int> block_beyond(std::size_t a, int side) const { return geometry_.block_beyond(a, side); }
  std::size_t halo_index(int rank) const {
    for (std::size_t k = 0; k < halo_.size(); ++k)
      if (halo_[k].rank == rank) return k;
    throw std::logic_error("halo: rank " + std::to_string(rank) + " is not an adjacent block");
  }

  std::optional<std::array<int, 3>> obstacle_site(std::array<int, 3> c, bool& ghost) const {
    return geometry_.site(c, ghost);
  }
  enum class Site { outside, fluid, solid };
  /// What lies at x + d for interior x, |d| <= 1 per axis: a cell of this block, a ghost, or nothing.
  Site site_of(const std::array<int, 3>& x, const std::array<int, 3>& d) const {
    bool ghost = false;
    const auto c = obstacle_site({x[0] + d[0], x[1] + d[1], x[2] + d[2]}, ghost);
    if (!c) return Site::outside;
    const bool solid = ghost ? std::binary_search(ghost_solids_.begin(), ghost_solids_.end(),
                                                  layout().index((*c)[0], (*c)[1], (*c)[2]))
                             : solid_at((*c)[0], (*c)[1], (*c)[2]);
    return solid ? Site::solid : Site::fluid;
  }
  /// Coordinates of padded index p (inverse of GridLayout::index).
  std::array<int, 3> padded_coordinates(std::size_t p) const { return geometry_.padded_coordinates(p); }

  /// A wall link in slot terms. The population coming back from the wall,
  ///   f_back = a f*_i(x) + b f*_i(x - c_i) + c f*_opp(i)(x)
  ///          + b2 f*_i(x - 2 c_i) + c2 f*_opp(i)(x - c_i) + wall,
  /// goes where the next kernel reads f_opp(i)(x) (docs/lbm.md, "Walls inside the grid").
  struct PreparedLink {
    // Padded indices, unwrapped: x +- c_i may be a ghost (a periodic image or a cell of an adjacent
    // block). The kernels of x read and write there, and the ghosts hold what crossed the face when
    // the links close (begin_local), so no index needs the cell's home.
    std::size_t fluid = 0;   ///< the fluid cell x
    std::size_t solid = 0;   ///< x + c_i
    std::size_t second = 0;  ///< x - c_i when it is fluid (read only when b != 0), else x
    std::size_t behind = 0;  ///< x - c_i: where the odd kernel puts f*_opp(i)(x)
    std::size_t third = 0;   ///< x - 2 c_i when the quadratic rule reads it (b2 or c2 != 0), else x
    /// With the quadratic rule and x - c_i a ghost: the entry of far_.values that holds the third
    /// value (kNoFar otherwise; kFarUnplanned between prepare_link and plan_far_values).
    std::size_t far = kNoFar;
    int dir = 0;
    double a = 1.0, b = 0.0, c = 0.0, b2 = 0.0, c2 = 0.0, wall = 0.0;
    Eigen::Vector3d wall_velocity = Eigen::Vector3d::Zero();
  };
  static constexpr std::size_t kNoFar = static_cast<std::size_t>(-1), kFarUnplanned = kNoFar - 1;
  /// True when x - c_i and x - 2 c_i are fluid cells of the lattice (x in block coordinates).
  bool has_two_fluid_cells_behind(const std::array<int, 3>& x, const std::array<int, 3>& c) const;
  /// Whether cell y (block coordinates, at most two cells beyond the block's faces) is solid; empty
  /// beyond a face of the lattice that is not periodic.
  std::optional<bool> solid_near(std::array<int, 3> y) const;
  std::size_t far_key(const std::array<int, 3>& y) const {
    const auto n = [](int v) { return static_cast<std::size_t>(v + 2); };
    return n(y[0]) + n(config_.nx + 2) * (n(y[1]) + n(config_.ny + 2) * n(y[2]));
  }
  /// Assigns the far values of the links prepare_link marked: read here, or asked of their block.
  void plan_far_values(const Obstacle& obstacle);
  /// f*_j(y) of interior cell y (padded index) after the kernel of the given parity.
  template <bool Odd>
  double post_collision(int j, std::size_t y) const {
    return populations_.template post_collision<Odd>(j, y);
  }
  template <bool Odd>
  void read_local_far_values() {
    for (const FarLocal& e : far_.local) far_.values[e.value] = post_collision<Odd>(e.population, e.cell);
  }

  PreparedLink prepare_link(const WallLink& link, WallRule rule) const;
  std::vector<PreparedLink> prepare_links(const Obstacle& obstacle) const;
  /// The solid cells move with the content in a window shift (those leaving the grid are
  /// dropped); the links are dropped, to be set again at the obstacle's new place.
  void shift_solid_cells(int axis, int sign, std::vector<std::size_t> entering) {
    if (solid_cells_.empty() && entering.empty()) {
      ghost_solids_.clear(), far_solids_.clear(), links_.clear(), wall_momentum_.clear(), far_ = {};
      return;
    }
    const std::array<int, 3> extent{config_.nx, config_.ny, config_.nz};
    std::vector<std::size_t> moved;
    for (const std::size_t n : solid_cells_) {
      std::array<int, 3> c{
          static_cast<int>(n % static_cast<std::size_t>(extent[0])),
          static_cast<int>(n / static_cast<std::size_t>(extent[0]) % static_cast<std::size_t>(extent[1])),
          static_cast<int>(n / (static_cast<std::size_t>(extent[0]) * static_cast<std::size_t>(extent[1])))};
      c[static_cast<std::size_t>(axis)] -= sign;
      if (c[static_cast<std::size_t>(axis)] < 0 ||
          c[static_cast<std::size_t>(axis)] >= extent[static_cast<std::size_t>(axis)])
        continue;
      moved.push_back(linear_index(c[0], c[1], c[2]));
    }
    moved.insert(moved.end(), entering.begin(), entering.end());
    std::sort(moved.begin(), moved.end());
    set_solid_cells(std::move(moved));
  }
  void set_solid_cells(std::vector<std::size_t> cells);

  /// Closes every wall link after the kernel of the given parity and records its momentum
  /// exchange. After an even kernel f*_j(y) sits in slot opp(j) at y and the odd kernel of x will
  /// read f_opp(i)(x) from slot i at x + c_i (a solid cell); after an odd kernel f*_i(x) sits in
  /// slot i at x + c_i, f*_i(x - c_i) in slot i at x, f*_opp(i)(x) in slot opp(i) at x - c_i, and
  /// the even kernel reads f_opp(i)(x) from slot opp(i) at x. No link writes a slot another
  /// reads (writes go to solid cells after an even kernel, reads to fluid ones; after an odd
  /// one the written slot opp(i) at x would be read only by a link from x + c_i, a solid cell).
  template <bool Odd>
  void close_wall_links() {
    Real* const A = populations_.data();
    const std::ptrdiff_t count = static_cast<std::ptrdiff_t>(links_.size());
#pragma omp parallel for schedule(static) if (threaded_ && count > 4096)
    for (std::ptrdiff_t k = 0; k < count; ++k) {
      const PreparedLink& l = links_[static_cast<std::size_t>(k)];
      const int i = l.dir, o = opposite(i);
      const std::size_t in_slot = Odd ? slot(i, l.solid) : slot(o, l.fluid);
      const std::size_t out_slot = Odd ? slot(o, l.fluid) : slot(i, l.solid);
      const double f_in = static_cast<double>(A[in_slot]);
      const double f_second = l.b != 0.0 ? static_cast<double>(Odd ? A[slot(i, l.fluid)] : A[slot(o, l.second)]) : 0.0;
      const double f_opposite =
          l.c != 0.0 ? static_cast<double>(Odd ? A[slot(o, l.behind)] : A[slot(i, l.fluid)]) : 0.0;
      // The quadratic rule's third points: f*_i(x - 2c_i) and f*_opp(i)(x - c_i).
      // A link whose x - c_i is a ghost reads the one it needs from far_ (plan_far_values).
      const double far = l.far != kNoFar ? far_.values[l.far] : 0.0;
      const double f_third = l.b2 == 0.0       ? 0.0
                             : l.far != kNoFar ? far
                                               : static_cast<double>(Odd ? A[slot(i, l.behind)] : A[slot(o, l.third)]);
      const double f_opposite_behind = l.c2 == 0.0 ? 0.0
                                       : l.far != kNoFar
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

  /// Sets the solid cells to rest (stored 0), so that what streams into them from the fluid
  /// does not pile up over the run. After the odd step's links have read their slots.
  void reset_solid_cells() {
    Real* const A = populations_.data();
    for (const std::size_t n : solid_cells_) {
      const std::size_t cell = padded_of_linear(n);
      for (int q = 0; q < Q; ++q) A[slot(q, cell)] = Real(0);
    }
  }

  std::size_t padded_of_linear(std::size_t n) const { return geometry_.padded_of_linear(n); }

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
  CopyLists lists_;
  std::vector<HaloLinks> halo_;
  Eigen::Vector3d inflow_velocity_;
  // The obstacle: solid cells (flag per interior cell, allocated with the first obstacle, and
  // their linear indices in ascending order), its links and their last momentum exchange.
  std::vector<std::uint8_t> solid_flag_;
  std::vector<std::size_t> solid_cells_;
  std::vector<PreparedLink> links_;
  std::vector<Eigen::Vector3d> wall_momentum_;
  /// Solid cells of adjacent blocks in the ghost layer (padded indices, ascending): where this
  /// block's links end across a block face.
  std::vector<std::size_t> ghost_solids_;
  /// Solid cells one layer beyond the ghosts (far_key, ascending): the quadratic rule's x - 2 c_i.
  std::vector<std::size_t> far_solids_;
  WallRule obstacle_rule_ = WallRule::bouzidi;
  /// The quadratic rule's third values of links whose x - c_i is a ghost (PreparedLink::far).
  struct FarLocal {
    std::size_t value = 0, cell = 0;  ///< entry of `values`; the interior cell y (padded index)
    int population = 0;               ///< j of f*_j(y)
  };
  struct FarValues {
    std::vector<double> values;
    std::vector<FarLocal> local;  ///< those this block holds (across a periodic wrap)
    /// Per halo rank: what this block asks of it (x, y, z in its block's coordinates, j; four values
    /// each), the entry of `values` each answer fills, and what it asked of this block.
    std::vector<std::vector<double>> requests;
    std::vector<std::vector<std::size_t>> answers_to;
    std::vector<std::vector<double>> asked;
  } far_;
  /// A block's rows (y + ny z) near the faces it shares with other blocks, and the rest
  /// (split_rows).
  std::vector<int> face_rows_, interior_rows_;
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
  set_solid_cells(std::vector<std::size_t>(state.solid_cells.begin(), state.solid_cells.end()));
}

template <Lattice L, class Collision, class Real>
void AaSolver<L, Collision, Real>::set_solid_cells(std::vector<std::size_t> cells) {
  for (const std::size_t n : solid_cells_) solid_flag_[n] = 0;
  links_.clear();
  wall_momentum_.clear();
  ghost_solids_.clear();
  far_solids_.clear();
  far_ = {};
  solid_cells_ = std::move(cells);
  if (solid_cells_.empty()) return;
  if (solid_flag_.empty()) solid_flag_.assign(cell_count(), 0);
  for (const std::size_t n : solid_cells_) solid_flag_[n] = 1;
}

template <Lattice L, class Collision, class Real>
void AaSolver<L, Collision, Real>::set_obstacle(const Obstacle& obstacle) {
  std::vector<std::size_t> cells, ghosts;
  cells.reserve(obstacle.solid_cells.size());
  // A free-slip or outflow face copies populations from cells of its own layer, which would
  // carry a solid cell's scratch into the fluid; walls and inlets copy only within a cell. The
  // block that holds a cell checks it.
  const FaceKinds kinds = face_kinds(config_);
  const std::array<int, 3> extent{config_.nx, config_.ny, config_.nz};
  for (const auto& cell : obstacle.solid_cells) {
    bool ghost = false;
    const auto c = obstacle_site(cell, ghost);
    if (!c) throw std::invalid_argument("set_obstacle: a solid cell lies outside the lattice");
    const std::size_t padded = layout().index((*c)[0], (*c)[1], (*c)[2]);
    if (ghost) {
      ghosts.push_back(padded);
      continue;
    }
    cells.push_back(linear_index((*c)[0], (*c)[1], (*c)[2]));
    for (std::size_t a = 0; a < 3; ++a) {
      for (const int side : {0, 1}) {
        const Boundary kind = kinds[a][static_cast<std::size_t>(side)];
        const bool on_face = (*c)[a] == (side == 0 ? 0 : extent[a] - 1) && !has_block_beyond(a, side, true);
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
  if (obstacle.rule == WallRule::quadratic && config_.split && config_.split->thinnest_block() < 2) {
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
  obstacle_rule_ = obstacle.rule;
  links_ = prepare_links(obstacle);
  plan_far_values(obstacle);
  wall_momentum_.assign(links_.size(), Eigen::Vector3d::Zero());
}

template <Lattice L, class Collision, class Real>
void AaSolver<L, Collision, Real>::plan_far_values(const Obstacle& obstacle) {
  far_ = {};
  far_.requests.resize(halo_.size());
  far_.answers_to.resize(halo_.size());
  const BlockSplit split = config_.split.value_or(unsplit({config_.nx, config_.ny, config_.nz}));
  const std::array<int, 3> origin = split.offset(split.rank);
  for (std::size_t k = 0; k < links_.size(); ++k) {
    PreparedLink& p = links_[k];
    if (p.far != kFarUnplanned) continue;
    const auto x = resolve(obstacle.links[k].cell[0], obstacle.links[k].cell[1], obstacle.links[k].cell[2]);
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
    p.far = far_.values.size();
    far_.values.push_back(0.0);
    if (home == split.rank) {
      far_.local.push_back({p.far, layout().index(y[0], y[1], y[2]), j});
      continue;
    }
    // x - 2 c_i lies at most one cell beyond the ghosts, in an adjacent block: set_obstacle refuses
    // splits with blocks thinner than two cells.
    const std::size_t n = halo_index(home);
    far_.requests[n].insert(far_.requests[n].end(), {static_cast<double>(y[0]), static_cast<double>(y[1]),
                                                     static_cast<double>(y[2]), static_cast<double>(j)});
    far_.answers_to[n].push_back(p.far);
  }
}

template <Lattice L, class Collision, class Real>
void AaSolver<L, Collision, Real>::take_far_requests(const HaloMessages& messages) {
  check_message_count(messages, "take_far_requests");
  const std::array<int, 3> extent{config_.nx, config_.ny, config_.nz};
  for (const std::vector<double>& asked : messages.receive) {
    if (asked.size() % 4 != 0) throw std::invalid_argument("take_far_requests: a request holds four values");
    for (std::size_t n = 0; n < asked.size(); n += 4) {
      for (std::size_t a = 0; a < 3; ++a) {
        if (!(asked[n + a] >= 0.0 && asked[n + a] < extent[a])) {
          throw std::invalid_argument("take_far_requests: a requested cell lies outside the block");
        }
      }
      if (!(asked[n + 3] >= 0.0 && asked[n + 3] < Q)) {
        throw std::invalid_argument("take_far_requests: a requested population is out of range");
      }
    }
  }
  far_.asked = messages.receive;
}

template <Lattice L, class Collision, class Real>
void AaSolver<L, Collision, Real>::take_far_answers(const HaloMessages& messages) {
  check_message_count(messages, "take_far_answers");
  for (std::size_t k = 0; k < halo_.size(); ++k) {
    const std::vector<std::size_t> none;
    const std::vector<std::size_t>& to = k < far_.answers_to.size() ? far_.answers_to[k] : none;
    if (messages.receive[k].size() != to.size()) {
      throw std::invalid_argument("take_far_answers: " + std::to_string(messages.receive[k].size()) +
                                  " values from rank " + std::to_string(halo_[k].rank) + ", expected " +
                                  std::to_string(to.size()));
    }
    for (std::size_t n = 0; n < to.size(); ++n) far_.values[to[n]] = messages.receive[k][n];
  }
}

template <Lattice L, class Collision, class Real>
std::vector<typename AaSolver<L, Collision, Real>::PreparedLink> AaSolver<L, Collision, Real>::prepare_links(
    const Obstacle& obstacle) const {
  const auto count = static_cast<std::ptrdiff_t>(obstacle.links.size());
  std::vector<PreparedLink> prepared(obstacle.links.size());
  // A moving body's links are prepared every step. An exception may not leave a parallel region:
  // the first bad link's (the serial loop's) is kept and thrown after it.
  std::ptrdiff_t first_bad = count;
  std::exception_ptr error;
#pragma omp parallel for schedule(static) if (threaded_ && count > kLinksWorthThreads)
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

template <Lattice L, class Collision, class Real>
typename AaSolver<L, Collision, Real>::PreparedLink AaSolver<L, Collision, Real>::prepare_link(const WallLink& link,
                                                                                               WallRule rule) const {
  if (link.dir < 1 || link.dir >= Q) throw std::invalid_argument("set_obstacle: link direction out of range");
  if (!(link.q > 0.0 && link.q <= 1.0)) throw std::invalid_argument("set_obstacle: link fraction q outside (0, 1]");
  const auto x = resolve(link.cell[0], link.cell[1], link.cell[2]);
  const auto& c = L::set.c[link.dir];
  if (solid_at(x[0], x[1], x[2]) || site_of(x, c) != Site::solid) {
    throw std::invalid_argument("set_obstacle: a link must lead from a fluid cell to a solid one");
  }
  const bool has_second = site_of(x, {-c[0], -c[1], -c[2]}) == Site::fluid;
  const bool has_third = rule == WallRule::quadratic && has_two_fluid_cells_behind(x, c);
  const WallCoefficients k = wall_coefficients(rule, link.q, has_second, has_third);
  PreparedLink p;
  p.fluid = layout().index(x[0], x[1], x[2]);
  p.solid = static_cast<std::size_t>(static_cast<std::ptrdiff_t>(p.fluid) + layout().offset(c));
  p.behind = upstream_of(p.fluid, link.dir);
  p.second = has_second ? p.behind : p.fluid;
  p.third = p.fluid;
  p.dir = link.dir;
  p.wall_velocity = link.wall_velocity;
  p.a = k.a, p.b = k.b, p.c = k.c, p.b2 = k.b2, p.c2 = k.c2;
  p.wall = k.wall_term(moving_wall_term(L::set.w[link.dir], c, link.wall_velocity));
  if (k.reads_third) {
    const std::array<int, 3> extent{config_.nx, config_.ny, config_.nz};
    bool second_inside = true;
    for (std::size_t a = 0; a < 3; ++a) second_inside = second_inside && x[a] - c[a] >= 0 && x[a] - c[a] < extent[a];
    // A ghost's neighbour x - 2 c_i lies beyond the padded block: its value comes from its home.
    if (second_inside) {
      p.third = upstream_of(p.behind, link.dir);
    } else {
      p.far = kFarUnplanned;
    }
  }
  return p;
}

template <Lattice L, class Collision, class Real>
bool AaSolver<L, Collision, Real>::has_two_fluid_cells_behind(const std::array<int, 3>& x,
                                                              const std::array<int, 3>& c) const {
  for (const int k : {1, 2}) {
    const auto solid = solid_near({x[0] - k * c[0], x[1] - k * c[1], x[2] - k * c[2]});
    if (!solid || *solid) return false;
  }
  return true;
}

template <Lattice L, class Collision, class Real>
std::optional<bool> AaSolver<L, Collision, Real>::solid_near(std::array<int, 3> y) const {
  const std::array<int, 3> extent{config_.nx, config_.ny, config_.nz};
  int overhang = 0;  // how far beyond the block's faces, the largest over the axes
  for (std::size_t a = 0; a < 3; ++a) {
    if (y[a] >= 0 && y[a] < extent[a]) continue;
    const int side = y[a] < 0 ? 0 : 1;
    if (has_block_beyond(a, side, true)) {
      overhang = std::max(overhang, side == 0 ? -y[a] : y[a] - extent[a] + 1);
      continue;
    }
    if (config_.boundaries[a] != Boundary::periodic) return std::nullopt;
    y[a] = ((y[a] % extent[a]) + extent[a]) % extent[a];  // one block along a periodic axis
  }
  if (overhang == 0) return solid_at(y[0], y[1], y[2]);
  if (overhang == 1)
    return std::binary_search(ghost_solids_.begin(), ghost_solids_.end(), layout().index(y[0], y[1], y[2]));
  return std::binary_search(far_solids_.begin(), far_solids_.end(), far_key(y));
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
  std::vector<double>* out = onward ? &messages.send[halo_index(*onward)] : nullptr;
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
    for (const PreparedLink& l : links_) {
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
  check_message_count(messages, "end_shift");
  const int axis = pending_shift_->axis, sign = pending_shift_->sign;
  const auto a = static_cast<std::size_t>(axis);
  const std::array<int, 3> extent{config_.nx, config_.ny, config_.nz};
  std::vector<std::size_t> entering_solids;
  if (const std::optional<int> from = block_beyond(a, sign > 0 ? 1 : 0)) {
    const std::vector<double>& in = messages.receive[halo_index(*from)];
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
  shift_solid_cells(axis, sign, std::move(entering_solids));
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
  messages.send.resize(halo_.size());
  for (std::size_t k = 0; k < halo_.size(); ++k)
    pack<false>(halo_[k].send.fill, halo_[k].send.fill_shifted, messages.send[k]);
  return true;
}

template <Lattice L, class Collision, class Real>
void AaSolver<L, Collision, Real>::end_ghost_refresh(const HaloMessages& messages) {
  if (!pending_shift_) throw std::logic_error("end_ghost_refresh: no shift is waiting for its ghosts");
  check_message_count(messages, "end_ghost_refresh");
  write_received(messages, false, "end_ghost_refresh");
  restore_returns();
}

}  // namespace settle::lbm
