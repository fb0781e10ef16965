#pragma once
// The blocks of a split lattice stepped together in one process (tests/lbm/test_halo*.cpp): each
// block's messages go to the blocks named in its halo_ranks() (lbm/block_exchange.hpp), as an MPI
// exchange would deliver them. A test may tamper with the messages in transit (a control that must be seen).
#include <gtest/gtest.h>

#include <algorithm>
#include <array>
#include <functional>
#include <memory>
#include <vector>

#include "lbm/block_exchange.hpp"
#include "lbm/decomposition.hpp"
#include "lbm/solver.hpp"
#include "support/halo_cases.hpp"

namespace settle::test::halo {

class SplitLattice {
 public:
  /// Rewrites the message `from` sends to `to` before it is delivered.
  using Tamper = std::function<void(int from, int to, std::vector<double>& message)>;

  SplitLattice(const lbm::SolverConfig& whole, const std::array<int, 3>& blocks) {
    split_.global = {whole.nx, whole.ny, whole.nz};
    split_.blocks = blocks;
    for (int r = 0; r < split_.block_count(); ++r) {
      lbm::SolverConfig cfg = whole;
      cfg.split = split_;
      cfg.split->rank = r;
      const std::array<int, 3> n = split_.extent(r);
      cfg.nx = n[0], cfg.ny = n[1], cfg.nz = n[2];
      solvers_.push_back(lbm::make_solver(cfg));
      const std::array<int, 3> o = split_.offset(r);
      solvers_.back()->initialise([o](int x, int y, int z) { return initial_state(x + o[0], y + o[1], z + o[2]); });
    }
    messages_.resize(solvers_.size());
  }

  /// One step of every block as parallel::step takes it: the face rows and the messages, then the
  /// interior while the messages are (here: have been) delivered, then the rest.
  void step() {
    const bool far = solvers_.front()->block_exchange().exchanges_far_values();
    std::vector<lbm::HaloMessages> far_messages(solvers_.size());
    if (far) {
      for (std::size_t r = 0; r < solvers_.size(); ++r) solvers_[r]->block_exchange().far_requests(far_messages[r]);
      deliver(far_messages);
      for (std::size_t r = 0; r < solvers_.size(); ++r)
        solvers_[r]->block_exchange().take_far_requests(far_messages[r]);
    }
    for (std::size_t r = 0; r < solvers_.size(); ++r) solvers_[r]->block_exchange().begin_step_faces(messages_[r]);
    deliver(messages_);
    for (std::size_t r = 0; r < solvers_.size(); ++r) solvers_[r]->block_exchange().step_interior();
    if (far) {
      for (std::size_t r = 0; r < solvers_.size(); ++r) solvers_[r]->block_exchange().far_answers(far_messages[r]);
      deliver(far_messages);
      for (std::size_t r = 0; r < solvers_.size(); ++r) solvers_[r]->block_exchange().take_far_answers(far_messages[r]);
    }
    for (std::size_t r = 0; r < solvers_.size(); ++r) solvers_[r]->block_exchange().end_step(messages_[r]);
  }

  /// The moving window across the blocks; the blocks' masses summed in rank order.
  lbm::ShiftMass shift(int axis, int sign, const Tamper& tamper = {}) {
    lbm::ShiftMass total;
    for (std::size_t r = 0; r < solvers_.size(); ++r) {
      const lbm::ShiftMass m = solvers_[r]->block_exchange().begin_shift(axis, sign, messages_[r]);
      total.left += m.left, total.entered += m.entered;
    }
    deliver(messages_, tamper);
    int refresh = 0;
    for (std::size_t r = 0; r < solvers_.size(); ++r)
      refresh += solvers_[r]->block_exchange().end_shift(messages_[r]) ? 1 : 0;
    // Every block of a split needs the ghost exchange at an odd parity, none at an even one.
    EXPECT_TRUE(refresh == 0 || refresh == static_cast<int>(solvers_.size())) << refresh << " blocks ask for it";
    if (refresh > 0) {
      deliver(messages_);
      for (std::size_t r = 0; r < solvers_.size(); ++r) solvers_[r]->block_exchange().end_ghost_refresh(messages_[r]);
    }
    return total;
  }

  const lbm::BlockSplit& split() const { return split_; }
  const lbm::Solver& block(int r) const { return *solvers_[static_cast<std::size_t>(r)]; }
  lbm::Solver& block(int r) { return *solvers_[static_cast<std::size_t>(r)]; }
  int block_count() const { return static_cast<int>(solvers_.size()); }

 private:
  void deliver(std::vector<lbm::HaloMessages>& messages, const Tamper& tamper = {}) {
    for (std::size_t r = 0; r < solvers_.size(); ++r) {
      const std::vector<int> from = solvers_[r]->block_exchange().halo_ranks();
      messages[r].receive.resize(from.size());
      for (std::size_t k = 0; k < from.size(); ++k) {
        const std::vector<int> theirs = solvers_[static_cast<std::size_t>(from[k])]->block_exchange().halo_ranks();
        const auto at = std::find(theirs.begin(), theirs.end(), static_cast<int>(r));
        ASSERT_NE(at, theirs.end()) << "rank " << from[k] << " does not list rank " << r << " back";
        messages[r].receive[k] =
            messages[static_cast<std::size_t>(from[k])].send[static_cast<std::size_t>(at - theirs.begin())];
        if (tamper) tamper(from[k], static_cast<int>(r), messages[r].receive[k]);
      }
    }
  }

  lbm::BlockSplit split_;
  std::vector<std::unique_ptr<lbm::Solver>> solvers_;
  std::vector<lbm::HaloMessages> messages_;
};

// Populations that differ in any bit between the blocks and the unsplit lattice.
inline int differing_populations(const lbm::Solver& whole, const SplitLattice& split) {
  int differing = 0;
  for (int r = 0; r < split.block_count(); ++r)
    differing += differing_populations(whole, split.block(r), split.split().offset(r));
  return differing;
}

}  // namespace settle::test::halo
