#pragma once
// The in-place AA-pattern solver (Bailey, Myre, Walsh, Lilja & Saar 2009,
// doi:10.1109/ICPP.2009.37), templated over lattice, collision and storage type so that the
// hot loop sees compile-time constants. See docs/lbm.md for the scheme; in short, with
// A[q][x] the stored value of direction q at padded cell x and g = f - w (collision.hpp):
//  - even step: g_i(x) = A[i][x]; collide; A[opp(i)][x] = g*_i(x). No neighbour access.
//  - odd step: g_i(x) = A[opp(i)][x - c_i]; collide; A[i][x + c_i] = g*_i(x).
// After an odd step A[i][x] = g_i(x) again (the natural layout). Boundaries are handled by
// the two copy lists of lbm/grid.hpp between steps, so the interior kernel has no branch.
#include <omp.h>

#include <algorithm>
#include <cmath>
#include <cstdlib>
#include <cstring>
#include <limits>
#include <memory>
#include <new>
#include <stdexcept>
#include <string>

#include "lbm/collision.hpp"
#include "lbm/grid.hpp"
#include "lbm/lattice.hpp"
#include "lbm/solver.hpp"

namespace settle::lbm {

/// A page-aligned, uninitialised array of trivially copyable T.
template <class T>
class AlignedArray {
 public:
  AlignedArray() = default;
  explicit AlignedArray(std::size_t count) : size_(count) {
    const std::size_t bytes = (count * sizeof(T) + 4095) / 4096 * 4096;
    data_.reset(static_cast<T*>(std::aligned_alloc(4096, std::max<std::size_t>(bytes, 4096))));
    if (!data_) throw std::bad_alloc();
  }
  T* data() { return data_.get(); }
  const T* data() const { return data_.get(); }
  std::size_t size() const { return size_; }
  T& operator[](std::size_t i) { return data_[i]; }
  const T& operator[](std::size_t i) const { return data_[i]; }

 private:
  struct Free {
    void operator()(T* p) const { std::free(p); }
  };
  std::unique_ptr<T[], Free> data_;
  std::size_t size_ = 0;
};

template <Lattice L, class Collision, class Real>
class AaSolver final : public Solver {
 public:
  static constexpr int Q = L::Q;
  /// Arithmetic type of the collision: float storage is computed in float. The stored
  /// values are f - w (collision.hpp), so float arithmetic keeps the same ~7 significant
  /// digits of the deviations that float storage keeps, at half the vector work (the float
  /// kernel is otherwise compute-bound on AVX-512; see docs/lbm.md).
  using Arith = Real;

  explicit AaSolver(const SolverConfig& config)
      : config_(config),
        layout_(make_layout(config.nx, config.ny, config.nz, sizeof(Real), Q)),
        populations_(layout_.pop_stride * Q),
        forced_flag_(cell_count(), 0),
        lists_(build_copy_lists<L>(layout_, config.boundaries)) {
    for (auto& component : force_) component = AlignedArray<Real>(cell_count());
    rates_ = config.collision == CollisionKind::trt
                 ? trt_rates(config.tau, config.magic)
                 : RelaxationRates{1.0 / config.tau, 1.0 / config.tau};
    zero_fill();
  }

  const SolverConfig& config() const override { return config_; }
  std::int64_t step_count() const override { return steps_; }
  int velocity_count() const override { return Q; }

  void step() override {
    if (odd_parity()) {
      run_kernel<true>();
      apply(lists_.fold);
    } else {
      run_kernel<false>();
      apply(lists_.fill);
    }
    ++steps_;
  }

  void initialise(const InitialField& field) override {
    steps_ = 0;
    const int nx = config_.nx, ny = config_.ny, nz = config_.nz;
#pragma omp parallel for collapse(2) schedule(static) if (threaded_)
    for (int z = 0; z < nz; ++z) {
      for (int y = 0; y < ny; ++y) {
        for (int x = 0; x < nx; ++x) {
          const CellState state = field(x, y, z);
          const double F[3] = {total_force(0, x, y, z), total_force(1, x, y, z),
                               total_force(2, x, y, z)};
          // Stored momentum rho u - F/2, so that Guo's velocity (sum f c + F/2)/rho is u.
          const double rho = state.density;
          const double u[3] = {state.velocity.x() - 0.5 * F[0] / rho,
                               state.velocity.y() - 0.5 * F[1] / rho,
                               state.velocity.z() - 0.5 * F[2] / rho};
          const std::size_t cell = layout_.index(x, y, z);
          for (int i = 0; i < Q; ++i) {
            populations_[slot(i, cell)] = static_cast<Real>(
                shifted_equilibrium<L>(i, rho - 1.0, rho, u[0], u[1], u[2]));
          }
        }
      }
    }
  }

  ShiftMass shift(int axis, int sign) override;

  double total_mass() const override {
    // Sum over the interior slots: at an even parity these are the post-streaming
    // populations of each cell, at an odd parity the post-collision ones; streaming (with
    // the copy lists) is a permutation of populations, so both give sum(rho).
    double shifted_sum = 0.0;
    const int ny = config_.ny, nz = config_.nz;
#pragma omp parallel for collapse(2) reduction(+ : shifted_sum) schedule(static) if (threaded_)
    for (int z = 0; z < nz; ++z) {
      for (int y = 0; y < ny; ++y) shifted_sum += row_sum(y, z);
    }
    return static_cast<double>(cell_count()) + shifted_sum;
  }

  CellState cell_state(int x, int y, int z) const override {
    double g[Q];
    gather_shifted(resolve(x, y, z), g);
    const auto F = cell_force(x, y, z);
    const auto m = macroscopic<L>(g, F.data());
    return {m.rho, Eigen::Vector3d(m.ux, m.uy, m.uz)};
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
    if (odd_parity()) {
      throw std::logic_error("set_cell_populations: only at an even step count (AA parity)");
    }
    if (f.size() < static_cast<std::size_t>(Q)) {
      throw std::invalid_argument("set_cell_populations: span holds fewer than Q values");
    }
    const auto c = resolve(x, y, z);
    const std::size_t cell = layout_.index(c[0], c[1], c[2]);
    for (int i = 0; i < Q; ++i) populations_[slot(i, cell)] = static_cast<Real>(f[i] - L::set.w[i]);
  }

  std::vector<double> density_field() const override {
    std::vector<double> rho(cell_count());
    for_each_cell_moments([&](std::size_t n, const Macroscopic<L>& m) { rho[n] = m.rho; });
    return rho;
  }

  VectorField velocity_field() const override {
    VectorField u{std::vector<double>(cell_count()), std::vector<double>(cell_count()),
                  std::vector<double>(cell_count())};
    for_each_cell_moments([&](std::size_t n, const Macroscopic<L>& m) {
      u.x[n] = m.ux;
      u.y[n] = m.uy;
      u.z[n] = m.uz;
    });
    return u;
  }

  FieldExtrema extrema() const override {
    const int nx = config_.nx, ny = config_.ny, nz = config_.nz;
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
        for (int x = 0; x < nx; ++x) {
          double g[Q];
          gather_shifted({x, y, z}, g);
          const double F[3] = {total_force(0, x, y, z), total_force(1, x, y, z), total_force(2, x, y, z)};
          const Macroscopic<L> m = macroscopic<L>(g, F);
          const double u2 = m.ux * m.ux + m.uy * m.uy + m.uz * m.uz;
          // A NaN fails every comparison: test finiteness explicitly.
          row.finite = row.finite && std::isfinite(m.rho) && std::isfinite(u2);
          if (m.rho < row.min_density) row.min_density = m.rho, row.min_density_cell = {x, y, z};
          if (m.rho > row.max_density) row.max_density = m.rho, row.max_density_cell = {x, y, z};
          if (u2 > max_u2) max_u2 = u2, row.max_speed_cell = {x, y, z};
        }
        row.max_speed = std::sqrt(max_u2);
      }
    }
    return reduce_rows(rows);
  }

  /// Row-ordered reduction of extrema(); starts from the rest state (density 1, speed 0) as the
  /// single-pass version did, so an all-rest field reports its first cell.
  static FieldExtrema reduce_rows(const std::vector<FieldExtrema>& rows) {
    FieldExtrema e;
    for (const FieldExtrema& row : rows) {
      e.finite = e.finite && row.finite;
      if (row.min_density < e.min_density) e.min_density = row.min_density, e.min_density_cell = row.min_density_cell;
      if (row.max_density > e.max_density) e.max_density = row.max_density, e.max_density_cell = row.max_density_cell;
      if (row.max_speed > e.max_speed) e.max_speed = row.max_speed, e.max_speed_cell = row.max_speed_cell;
    }
    return e;
  }

  void add_force(int x, int y, int z, const Eigen::Vector3d& force) override {
    const std::size_t n = mark_forced(x, y, z);
    for (int a = 0; a < 3; ++a) force_[a][n] = static_cast<Real>(force_[a][n] + force[a]);
  }
  void set_force(int x, int y, int z, const Eigen::Vector3d& force) override {
    const std::size_t n = mark_forced(x, y, z);
    for (int a = 0; a < 3; ++a) force_[a][n] = static_cast<Real>(force[a]);
  }
  Eigen::Vector3d force(int x, int y, int z) const override {
    const auto c = resolve(x, y, z);
    const std::size_t n = linear_index(c[0], c[1], c[2]);
    return {static_cast<double>(force_[0][n]), static_cast<double>(force_[1][n]),
            static_cast<double>(force_[2][n])};
  }
  void clear_forces() override {
    for (const std::size_t n : forced_cells_) {
      for (auto& component : force_) component[n] = Real(0);
      forced_flag_[n] = 0;
    }
    forced_cells_.clear();
  }
  std::size_t forced_cell_count() const override { return forced_cells_.size(); }

  std::size_t bytes_per_cell_update() const override { return (2 * Q + 3) * sizeof(Real); }

  FluidState export_state() const override {
    FluidState state;
    state.layout = state_layout();
    state.step_count = steps_;
    state.populations = std::as_bytes(std::span<const Real>(populations_.data(), populations_.size()));
    state.forced_cells.reserve(forced_cells_.size());
    state.forced_values.reserve(3 * forced_cells_.size());
    for (const std::size_t n : forced_cells_) {
      state.forced_cells.push_back(n);
      for (const auto& component : force_) state.forced_values.push_back(static_cast<double>(component[n]));
    }
    return state;
  }

  void import_state(const FluidState& state) override;

 private:
  bool odd_parity() const { return (steps_ & 1) != 0; }
  std::size_t slot(int q, std::size_t cell) const {
    return static_cast<std::size_t>(q) * layout_.pop_stride + cell;
  }

  void zero_fill() {
    Real* data = populations_.data();
    const std::size_t count = populations_.size();
    // Parallel first touch: pages land near the threads that stream them.
#pragma omp parallel for schedule(static) if (threaded_)
    for (std::size_t k = 0; k < count; ++k) data[k] = Real(0);
    for (auto& component : force_) {
      Real* f = component.data();
      const std::size_t n = component.size();
#pragma omp parallel for schedule(static) if (threaded_)
      for (std::size_t k = 0; k < n; ++k) f[k] = Real(0);
    }
  }

  /// The hot loop: one AA step over all interior cells. Rows of x are contiguous in every
  /// population array (the odd step's neighbour offsets are constant along a row), so the
  /// x loop in collide_row is a vectorised loop of unit-stride loads and stores; the lattice
  /// constants fold at compile time. Vectorisation checked with -fopt-info-vec-optimized
  /// ("loop vectorized using 64 byte vectors" for every instantiation with SETTLE_NATIVE) and
  /// zmm instructions in the disassembly, see docs/lbm.md.
  template <bool Odd>
  void run_kernel() {
    Real* const base = populations_.data();
    const int ny = config_.ny, nz = config_.nz, nx = config_.nx;
    const double body[3] = {config_.body_force.x(), config_.body_force.y(),
                            config_.body_force.z()};
    const RelaxationRates rates = rates_;
    const Real* const fx = force_[0].data();
    const Real* const fy = force_[1].data();
    const Real* const fz = force_[2].data();
    std::ptrdiff_t offsets[Q];
    for (int i = 0; i < Q; ++i) offsets[i] = layout_.offset(L::set.c[i]);
    const std::size_t stride = layout_.pop_stride;
#pragma omp parallel for collapse(2) schedule(static) if (threaded_)
    for (int z = 0; z < nz; ++z) {
      for (int y = 0; y < ny; ++y) {
        const std::size_t row = layout_.index(0, y, z);
        Real* src[Q];
        Real* dst[Q];
        for (int i = 0; i < Q; ++i) {
          if constexpr (Odd) {
            src[i] = base + static_cast<std::size_t>(opposite(i)) * stride + row - offsets[i];
            dst[i] = base + static_cast<std::size_t>(i) * stride + row + offsets[i];
          } else {
            src[i] = base + static_cast<std::size_t>(i) * stride + row;
            dst[i] = base + static_cast<std::size_t>(opposite(i)) * stride + row;
          }
        }
        const std::size_t force_row =
            static_cast<std::size_t>(nx) * (static_cast<std::size_t>(y) +
                                            static_cast<std::size_t>(ny) * static_cast<std::size_t>(z));
        collide_row(src, dst, fx + force_row, fy + force_row, fz + force_row, nx, body, rates);
      }
    }
  }

  static void collide_row(Real* const (&src)[Q], Real* const (&dst)[Q],
                          const Real* __restrict fx, const Real* __restrict fy,
                          const Real* __restrict fz, int n, const double (&body)[3],
                          const RelaxationRates& rates) {
    // Local copies of the row pointers: loop-invariant scalars the vectoriser can use as
    // bases of unit-stride accesses (through the reference it reloads them per element).
    Real* in[Q];
    Real* out[Q];
    for (int i = 0; i < Q; ++i) {
      in[i] = src[i];
      out[i] = dst[i];
    }
    // Lanes are independent: in either parity, the slots a cell reads are exactly the slots
    // it writes, and no two cells share a slot, so `ivdep` (no loop-carried dependence) is
    // true. (`omp simd` made GCC 12 keep the row pointers in memory and give up.)
    const Arith body_x = static_cast<Arith>(body[0]), body_y = static_cast<Arith>(body[1]),
                body_z = static_cast<Arith>(body[2]);
#pragma GCC ivdep
    for (int x = 0; x < n; ++x) {
      Arith g[Q];
#pragma GCC unroll 32
      for (int i = 0; i < Q; ++i) g[i] = static_cast<Arith>(in[i][x]);
      const Arith F[3] = {body_x + static_cast<Arith>(fx[x]), body_y + static_cast<Arith>(fy[x]),
                          body_z + static_cast<Arith>(fz[x])};
      Collision::template collide<L, Arith>(g, F, rates);
#pragma GCC unroll 32
      for (int i = 0; i < Q; ++i) out[i][x] = static_cast<Real>(g[i]);
    }
  }

  void apply(const std::vector<CopyEntry>& list) {
    Real* const data = populations_.data();
    const std::size_t count = list.size();
    const CopyEntry* const entries = list.data();
#pragma omp parallel for schedule(static) if (threaded_)
    for (std::size_t k = 0; k < count; ++k) data[entries[k].dst] = data[entries[k].src];
  }

  /// Interior coordinates after wrapping periodic axes; throws for others out of range.
  std::array<int, 3> resolve(int x, int y, int z) const {
    std::array<int, 3> c{x, y, z};
    const std::array<int, 3> extent{config_.nx, config_.ny, config_.nz};
    for (int a = 0; a < 3; ++a) {
      if (c[a] >= 0 && c[a] < extent[a]) continue;
      if (config_.boundaries[a] != Boundary::periodic) {
        throw std::out_of_range("lbm cell query: coordinate " + std::to_string(c[a]) +
                                " outside [0, " + std::to_string(extent[a]) + ") on axis " +
                                std::to_string(a));
      }
      c[a] = ((c[a] % extent[a]) + extent[a]) % extent[a];
    }
    return c;
  }

  /// Shifted post-streaming populations g_i(x) of interior cell c at the current parity.
  void gather_shifted(const std::array<int, 3>& c, double* g) const {
    const std::size_t cell = layout_.index(c[0], c[1], c[2]);
    if (odd_parity()) {
      for (int i = 0; i < Q; ++i) {
        const std::size_t upstream = static_cast<std::size_t>(
            static_cast<std::ptrdiff_t>(cell) - layout_.offset(L::set.c[i]));
        g[i] = static_cast<double>(populations_[slot(opposite(i), upstream)]);
      }
    } else {
      for (int i = 0; i < Q; ++i) g[i] = static_cast<double>(populations_[slot(i, cell)]);
    }
  }

  std::array<double, 3> cell_force(int x, int y, int z) const {
    const auto c = resolve(x, y, z);
    return {total_force(0, c[0], c[1], c[2]), total_force(1, c[0], c[1], c[2]),
            total_force(2, c[0], c[1], c[2])};
  }

  double total_force(int axis, int x, int y, int z) const {
    return config_.body_force[axis] + static_cast<double>(force_[axis][linear_index(x, y, z)]);
  }

  template <class Visit>
  void for_each_cell_moments(Visit&& visit) const {
    const int nx = config_.nx, ny = config_.ny, nz = config_.nz;
#pragma omp parallel for collapse(2) schedule(static) if (threaded_)
    for (int z = 0; z < nz; ++z) {
      for (int y = 0; y < ny; ++y) {
        for (int x = 0; x < nx; ++x) {
          double g[Q];
          gather_shifted({x, y, z}, g);
          const double F[3] = {total_force(0, x, y, z), total_force(1, x, y, z),
                               total_force(2, x, y, z)};
          visit(linear_index(x, y, z), macroscopic<L>(g, F));
        }
      }
    }
  }

  double row_sum(int y, int z) const {
    double sum = 0.0;
    const std::size_t row = layout_.index(0, y, z);
    for (int q = 0; q < Q; ++q) {
      const Real* p = populations_.data() + slot(q, row);
      for (int x = 0; x < config_.nx; ++x) sum += static_cast<double>(p[x]);
    }
    return sum;
  }

  std::size_t mark_forced(int x, int y, int z) {
    const auto c = resolve(x, y, z);
    const std::size_t n = linear_index(c[0], c[1], c[2]);
    if (!forced_flag_[n]) {
      forced_flag_[n] = 1;
      forced_cells_.push_back(n);
    }
    return n;
  }

  StateLayout state_layout() const {
    return {config_.nx,   config_.ny, config_.nz,  Q,
            static_cast<std::uint32_t>(sizeof(Real)), layout_.x_begin, layout_.sx, layout_.sxy,
            layout_.pop_stride, populations_.size()};
  }

  SolverConfig config_;
  GridLayout layout_;
  AlignedArray<Real> populations_;
  std::array<AlignedArray<Real>, 3> force_;
  std::vector<std::uint8_t> forced_flag_;
  std::vector<std::size_t> forced_cells_;
  CopyLists lists_;
  RelaxationRates rates_;
  std::int64_t steps_ = 0;
  /// Below ~16 k cells a step costs less than waking the OpenMP team (and far less than a
  /// barrier on an oversubscribed machine), so small grids run on the calling thread.
  bool threaded_ = cell_count() >= 16384;
};

template <Lattice L, class Collision, class Real>
void AaSolver<L, Collision, Real>::import_state(const FluidState& state) {
  // Everything is checked before anything is written, so a refused state leaves the solver as it was.
  if (!(state.layout == state_layout())) {
    throw std::invalid_argument("import_state: the state was saved from a solver with another grid, lattice, "
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
  std::vector<std::uint8_t> seen(cell_count(), 0);
  for (const std::uint64_t n : state.forced_cells) {
    if (n >= cell_count() || seen[n]) {
      throw std::invalid_argument("import_state: forced cell index " + std::to_string(n) + " out of range or repeated");
    }
    seen[n] = 1;
  }

  std::memcpy(populations_.data(), state.populations.data(), state.populations.size());
  steps_ = state.step_count;
  clear_forces();
  for (std::size_t k = 0; k < state.forced_cells.size(); ++k) {
    const auto n = static_cast<std::size_t>(state.forced_cells[k]);
    forced_flag_[n] = 1;
    forced_cells_.push_back(n);
    for (std::size_t a = 0; a < 3; ++a) force_[a][n] = static_cast<Real>(state.forced_values[3 * k + a]);
  }
}

template <Lattice L, class Collision, class Real>
ShiftMass AaSolver<L, Collision, Real>::shift(int axis, int sign) {
  if (axis < 0 || axis > 2) throw std::invalid_argument("shift: axis must be 0, 1 or 2");
  if (sign != 1 && sign != -1) throw std::invalid_argument("shift: sign must be +1 or -1");
  const std::array<int, 3> extent{config_.nx, config_.ny, config_.nz};
  const int n_axis = extent[axis];
  // The window moves by `sign`: new cell k holds old cell k + sign. The layer at k = 0
  // (sign -1: k = n - 1) of the old content leaves; the opposite layer enters at rest.
  const int leaving = sign > 0 ? 0 : n_axis - 1;
  const auto cell_of = [&](int k, int u, int v) {
    std::array<int, 3> c{};
    c[axis] = k;
    c[(axis + 1) % 3] = u;
    c[(axis + 2) % 3] = v;
    return layout_.index(c[0], c[1], c[2]);
  };
  const int nu = extent[(axis + 1) % 3], nv = extent[(axis + 2) % 3];
  double leaving_sum = 0.0;
  for (int v = 0; v < nv; ++v) {
    for (int u = 0; u < nu; ++u) {
      const std::size_t cell = cell_of(leaving, u, v);
      for (int q = 0; q < Q; ++q) leaving_sum += static_cast<double>(populations_[slot(q, cell)]);
    }
  }
  const double layer_cells = static_cast<double>(nu) * static_cast<double>(nv);
  // Layers along an axis are contiguous blocks of the padded grid (a cell along x, a row of sx
  // elements along y, a plane of sxy along z), so the shift is a memmove of whole blocks per
  // population array: sequential traffic instead of strided walks. Ghost cells inside the
  // moved blocks move too; they are stale at an even parity and rebuilt below at an odd one.
  const std::array<std::size_t, 3> block{1, layout_.sx, layout_.sxy};
  const std::size_t layer = block[axis];
  // Blocks that hold the layers: one per (y, z) row for x, one per plane for y, one for z.
  std::vector<std::size_t> starts;
  if (axis == 0) {
    for (int z = 0; z < config_.nz; ++z)
      for (int y = 0; y < config_.ny; ++y) starts.push_back(layout_.index(0, y, z));
  } else if (axis == 1) {
    // A row's sx elements counted from its ghost x = -1 hold the whole row, both ghosts included
    // (grid.hpp: sx >= nx + 2); counted from the line start they would not when nx + 2 < sx + x_begin.
    for (int z = 0; z < config_.nz; ++z) starts.push_back(layout_.index(-1, 0, z));
  } else {
    starts.push_back(layout_.index(-1, -1, 0));
  }
  const std::size_t moved = layer * static_cast<std::size_t>(n_axis - 1);
  Real* const data = populations_.data();
  const std::ptrdiff_t block_count = static_cast<std::ptrdiff_t>(starts.size());
#pragma omp parallel for collapse(2) schedule(static) if (threaded_)
  for (int q = 0; q < Q; ++q) {
    for (std::ptrdiff_t b = 0; b < block_count; ++b) {
      Real* const first = data + static_cast<std::size_t>(q) * layout_.pop_stride + starts[b];
      if (sign > 0) {
        std::memmove(first, first + layer, moved * sizeof(Real));
        std::fill(first + moved, first + moved + layer, Real(0));  // rest at rho = 1 (shifted storage)
      } else {
        std::memmove(first + layer, first, moved * sizeof(Real));
        std::fill(first, first + layer, Real(0));
      }
    }
  }
  // At an odd parity the ghost slots hold copies of the old interior: rebuild them.
  if (odd_parity()) apply(lists_.fill);
  return {layer_cells + leaving_sum, layer_cells};
}

}  // namespace settle::lbm
