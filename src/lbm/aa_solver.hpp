#pragma once
// The fluid solver of one block: lbm::Solver, and the exchange protocol of a split lattice
// (lbm/block_exchange.hpp), as a composition of the parts of lbm/ (docs/lbm.md, "Files"), templated
// over lattice, collision and storage type:
//  - BlockGeometry: where the block's cells lie (extent, padded layout, adjacent blocks);
//  - AaPopulations, ForceField, AaKernel: the population array with its parity, the per-cell
//    force, and the kernel with the relaxation rates;
//  - CopyLists (lbm/grid.hpp): the lattice's faces, applied after each kernel;
//  - BlockObstacle: the solid cells and wall links (wall rules in lbm/wall_rules.hpp);
//  - BlockHalo: the messages to and from the adjacent blocks (lbm/block_halo.hpp);
//  - WindowShift, BlockFields: the moving window, and the moments read from and written to cells.
// This file holds the order of a step; each part holds its own state.
#include <cstring>
#include <span>
#include <stdexcept>
#include <string>
#include <vector>

#include "lbm/aa_kernel.hpp"
#include "lbm/aa_populations.hpp"
#include "lbm/block_exchange.hpp"
#include "lbm/block_fields.hpp"
#include "lbm/block_geometry.hpp"
#include "lbm/block_halo.hpp"
#include "lbm/block_obstacle.hpp"
#include "lbm/force_field.hpp"
#include "lbm/grid.hpp"
#include "lbm/lattice.hpp"
#include "lbm/solver.hpp"
#include "lbm/window_shift.hpp"

namespace settle::lbm {

template <Lattice L, class Collision, class Real>
class AaSolver final : public Solver, public BlockExchange {
 public:
  static constexpr int Q = L::Q;

  explicit AaSolver(const SolverConfig& config)
      : config_(config),
        geometry_(config, sizeof(Real), Q),
        populations_(geometry_),
        forces_(geometry_.cell_count(), geometry_.threaded()),
        kernel_(config, geometry_.threaded()),
        block_lists_(build_block_lists<L>(geometry_.layout(), geometry_.face_kinds(), geometry_.split())),
        halo_(std::move(block_lists_.halo), geometry_),
        obstacle_(geometry_),
        inflow_velocity_(config.inflow_velocity),
        shift_({geometry_, populations_, obstacle_, halo_, block_lists_.local, inflow_velocity_}),
        fields_(geometry_, populations_, forces_, obstacle_, config.body_force) {
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
    run_kernel(halo_.face_rows());
    halo_.pack(populations_, inflow_velocity_, messages);
  }
  void step_interior() override {
    run_kernel(halo_.interior_rows());
    apply_copy_lists();
  }
  std::vector<std::size_t> halo_receive_counts() const override { return halo_.receive_counts(odd_parity()); }
  void end_step(const HaloMessages& messages) override {
    halo_.check_message_count(messages, "end_step");
    halo_.write_received(populations_, messages, odd_parity(), "end_step");
    end_local();
  }
  bool exchanges_far_values() const override { return !halo_.empty() && obstacle_.rule() == WallRule::quadratic; }
  void far_requests(HaloMessages& messages) const override { obstacle_.far_values().requests(messages, halo_.size()); }
  void take_far_requests(const HaloMessages& messages) override {
    halo_.check_message_count(messages, "take_far_requests");
    obstacle_.far_values().take_requests(messages, geometry_.extent(), Q);
  }
  void far_answers(HaloMessages& messages) const override {
    obstacle_.far_values().answers(messages, halo_.size(), populations_);
  }
  void take_far_answers(const HaloMessages& messages) override {
    halo_.check_message_count(messages, "take_far_answers");
    obstacle_.far_values().take_answers(messages, halo_.ranks());
  }
  ShiftMass begin_shift(int axis, int sign, HaloMessages& messages) override {
    return shift_.begin(axis, sign, messages);
  }
  bool end_shift(HaloMessages& messages) override { return shift_.end(messages); }
  void end_ghost_refresh(const HaloMessages& messages) override { shift_.end_ghost_refresh(messages); }

  ShiftMass shift(int axis, int sign) override {
    if (!halo_.empty()) {
      throw std::logic_error(
          "shift: a block of a split lattice shifts by begin_shift and end_shift around its exchanges");
    }
    HaloMessages none;
    const ShiftMass mass = shift_.begin(axis, sign, none);
    shift_.end(none);
    return mass;
  }

  // --- cells and fields (BlockFields)
  void initialise(const InitialField& field) override {
    populations_.set_step_count(0);
    fields_.initialise(field);
  }
  double total_mass() const override { return fields_.total_mass(); }
  CellState cell_state(int x, int y, int z) const override { return fields_.cell_state(x, y, z); }
  void box_states(const std::array<int, 3>& origin, const std::array<int, 3>& extent, double* density,
                  const std::array<double*, 3>& velocity) const override {
    fields_.box_states(origin, extent, density, velocity);
  }
  void cell_populations(int x, int y, int z, std::span<double> f) const override { fields_.populations(x, y, z, f); }
  void set_cell_populations(int x, int y, int z, std::span<const double> f) override {
    fields_.set_populations(x, y, z, f);
  }
  double non_equilibrium(int x, int y, int z, std::span<double> f_neq) const override {
    return fields_.non_equilibrium(x, y, z, f_neq);
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
  std::vector<double> density_field() const override { return fields_.density_field(); }
  VectorField velocity_field() const override { return fields_.velocity_field(); }
  FieldExtrema extrema() const override { return fields_.extrema(); }

  // --- the per-cell force (ForceField)
  void add_force(int x, int y, int z, const Eigen::Vector3d& force) override { forces_.add(index_of(x, y, z), force); }
  void set_force(int x, int y, int z, const Eigen::Vector3d& force) override { forces_.set(index_of(x, y, z), force); }
  Eigen::Vector3d force(int x, int y, int z) const override { return forces_.at(index_of(x, y, z)); }
  void clear_forces() override { forces_.clear(); }
  std::size_t forced_cell_count() const override { return forces_.cells().size(); }

  void set_inflow_velocity(const Eigen::Vector3d& velocity) override {
    if (!velocity.allFinite() || velocity.norm() >= 0.3) {
      throw std::invalid_argument("set_inflow_velocity: must be finite with magnitude below 0.3");
    }
    inflow_velocity_ = velocity;
  }
  const Eigen::Vector3d& inflow_velocity() const override { return inflow_velocity_; }

  // --- the obstacle (BlockObstacle)
  void set_obstacle(const Obstacle& obstacle) override { obstacle_.set(obstacle, halo_.ranks()); }
  bool is_solid(int x, int y, int z) const override {
    const auto c = geometry_.resolve(x, y, z);
    return obstacle_.solid_at(c[0], c[1], c[2]);
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

  // --- checkpoints
  FluidState export_state() const override;
  void import_state(const FluidState& state) override;

 private:
  bool odd_parity() const { return populations_.odd_parity(); }
  std::size_t index_of(int x, int y, int z) const {
    const auto c = geometry_.resolve(x, y, z);
    return geometry_.linear_index(c[0], c[1], c[2]);
  }

  // A step is the kernel and the copies of the block's own faces (begin_local), the exchange with
  // adjacent blocks when split, and the rest (end_local). Walls inside the grid close last: after
  // an odd kernel once the fold (own faces and messages) has brought home what crossed a face,
  // after an even one once the fill has written the ghosts, so that a link may read its second
  // node from a ghost and write its returning population into one (BlockObstacle::close).
  void begin_local() {
    if (odd_parity()) {
      kernel_.template run<true>(populations_, forces_);
    } else {
      kernel_.template run<false>(populations_, forces_);
    }
    apply_copy_lists();
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
  void run_kernel(const std::vector<int>& rows) {
    if (odd_parity()) {
      kernel_.template run_rows<true>(populations_, forces_, rows);
    } else {
      kernel_.template run_rows<false>(populations_, forces_, rows);
    }
  }
  /// The fold after an odd kernel, the fill after an even one (lbm/grid.hpp).
  void apply_copy_lists() {
    const CopyLists& lists = block_lists_.local;
    if (odd_parity()) {
      populations_.template apply<true>(lists.fold, lists.fold_shifted, inflow_velocity_);
    } else {
      populations_.template apply<false>(lists.fill, lists.fill_shifted, inflow_velocity_);
    }
  }

  StateLayout state_layout() const {
    const GridLayout& layout = geometry_.layout();
    return {config_.nx,
            config_.ny,
            config_.nz,
            Q,
            static_cast<std::uint32_t>(sizeof(Real)),
            layout.x_begin,
            layout.sx,
            layout.sxy,
            layout.pop_stride,
            populations_.size()};
  }

  SolverConfig config_;
  BlockGeometry geometry_;
  AaPopulations<L, Real> populations_;
  ForceField<Real> forces_;
  AaKernel<L, Collision, Real> kernel_;
  BlockLists block_lists_;  ///< the copy lists of the block's own faces (`local`); `halo` moved to halo_
  BlockHalo<L, Real> halo_;
  BlockObstacle<L, Real> obstacle_;
  Eigen::Vector3d inflow_velocity_;
  WindowShift<L, Real> shift_;
  BlockFields<L, Real> fields_;
};

template <Lattice L, class Collision, class Real>
FluidState AaSolver<L, Collision, Real>::export_state() const {
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

}  // namespace settle::lbm
