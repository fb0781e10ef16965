// The halo across MPI ranks (run under mpirun by CTest with 1, 2 and 4 processes): every way of
// splitting the lattice over this many ranks, each rank stepping its block with its messages sent
// through the communicator, must leave every population of its block bit for bit equal to the
// unsplit lattice's, which each rank also steps. The same check as tests/lbm/test_halo.cpp, whose
// messages are handed over in one process: here they travel between processes.
#include <gtest/gtest.h>

#include <algorithm>
#include <array>
#include <cmath>
#include <iterator>
#include <memory>
#include <string>
#include <utility>
#include <vector>

#include "lbm/decomposition.hpp"
#include "lbm/solver.hpp"
#include "parallel/communicator.hpp"
#include "parallel/lattice_steps.hpp"
#include "support/halo_cases.hpp"
#include "support/sphere_obstacle.hpp"

namespace test_mpi_halo {

using namespace settle;
using namespace settle::test;

// Every factorisation of `ranks` into blocks per axis that leaves each block a cell at least.
std::vector<std::array<int, 3>> splits_of(int ranks, const std::array<int, 3>& global) {
  std::vector<std::array<int, 3>> splits;
  for (int bz = 1; bz <= ranks; ++bz)
    for (int by = 1; by <= ranks; ++by)
      for (int bx = 1; bx <= ranks; ++bx)
        if (bx * by * bz == ranks && bx <= global[0] && by <= global[1] && bz <= global[2])
          splits.push_back({bx, by, bz});
  return splits;
}

lbm::SolverConfig block_config(const lbm::SolverConfig& whole_config, const std::array<int, 3>& blocks, int rank) {
  lbm::SolverConfig cfg = whole_config;
  lbm::BlockSplit split;
  split.global = {whole_config.nx, whole_config.ny, whole_config.nz};
  split.blocks = blocks;
  split.rank = rank;
  cfg.split = split;
  const std::array<int, 3> n = split.extent(split.rank);
  cfg.nx = n[0], cfg.ny = n[1], cfg.nz = n[2];
  return cfg;
}

// This rank's block of the split and the whole lattice, both started from the same flow.
struct BlockAndWhole {
  std::array<int, 3> offset;
  std::unique_ptr<lbm::Solver> block, whole;
};

BlockAndWhole start(const lbm::SolverConfig& whole_config, const std::array<int, 3>& blocks) {
  const int rank = parallel::world().rank();
  const lbm::SolverConfig cfg = block_config(whole_config, blocks, rank);
  const std::array<int, 3> o = cfg.split->offset(rank);
  BlockAndWhole s{o, lbm::make_solver(cfg), lbm::make_solver(whole_config)};
  s.block->initialise([o](int x, int y, int z) { return halo::initial_state(x + o[0], y + o[1], z + o[2]); });
  s.whole->initialise(halo::initial_state);
  return s;
}

// Differing populations of this rank's block after each of the last two of `steps` steps (an odd
// and an even count: both parities' copies are checked).
std::array<int, 2> run_block(const lbm::SolverConfig& whole_config, const std::array<int, 3>& blocks, int steps) {
  parallel::Communicator& world = parallel::world();
  auto [o, block, whole] = start(whole_config, blocks);
  std::array<int, 2> differing{-1, -1};
  for (int s = 0; s < steps; ++s) {
    whole->step();
    parallel::step(*block, world);  // the face rows, the messages posted, the interior, the rest
    if (s >= steps - 2)
      differing[static_cast<std::size_t>(s - (steps - 2))] = halo::differing_populations(*whole, *block, o);
  }
  return differing;
}

TEST(MpiHalo, EverySplitOverTheseRanksStepsBitForBitAsTheUnsplitLattice) {
  const int ranks = parallel::world().size();
  for (const auto& variant : {std::pair{lbm::LatticeKind::D3Q19, lbm::Precision::float64},
                              std::pair{lbm::LatticeKind::D3Q27, lbm::Precision::float32}}) {
    for (const halo::FaceSet& faces : halo::face_sets()) {
      const lbm::SolverConfig cfg = halo::lattice_of(faces, variant.first, variant.second);
      for (const auto& blocks : splits_of(ranks, {cfg.nx, cfg.ny, cfg.nz})) {
        SCOPED_TRACE(std::string(faces.name) + ", " + lbm::to_string(variant.first) + ", blocks " +
                     std::to_string(blocks[0]) + " x " + std::to_string(blocks[1]) + " x " + std::to_string(blocks[2]) +
                     ", rank " + std::to_string(parallel::world().rank()));
        EXPECT_EQ(run_block(cfg, blocks, 100), (std::array<int, 2>{0, 0}));
      }
    }
  }
}

// A moving sphere of solid cells with Bouzidi links across the block faces, and window shifts at
// both parities along every axis (parallel::step and parallel::shift), against the unsplit lattice:
// the check of tests/lbm/test_halo_obstacle.cpp with the messages between processes (with the
// quadratic rule, its far values too). Returns the differing populations at the end and the largest
// relative difference of the shifts' mass.
std::pair<int, double> run_block_with_body(const lbm::SolverConfig& whole_config, const std::array<int, 3>& blocks,
                                           lbm::WallRule rule) {
  parallel::Communicator& world = parallel::world();
  auto [o, block, whole] = start(whole_config, blocks);
  const halo::Sphere sphere{Eigen::Vector3d(3.1, 2.85, 5.2), 1.8};
  lbm::Obstacle obstacle = halo::whole_obstacle(sphere, whole_config, lbm::velocity_set(whole_config.lattice));
  obstacle.rule = rule;
  const lbm::Obstacle part = halo::block_obstacle(obstacle, *block->config().split, world.rank());
  whole->set_obstacle(obstacle);
  block->set_obstacle(part);
  struct Shift {
    int after_step, axis, sign;
  };
  const Shift shifts[] = {{7, 2, 1}, {12, 2, -1}, {19, 0, 1}, {26, 1, -1}, {33, 2, 1}};
  double mass_error = 0.0;
  std::size_t next = 0;
  for (int s = 1; s <= 40; ++s) {
    whole->step();
    parallel::step(*block, world);
    if (next < std::size(shifts) && shifts[next].after_step == s) {
      const lbm::ShiftMass expected = whole->shift(shifts[next].axis, shifts[next].sign);
      const lbm::ShiftMass got = parallel::shift(*block, shifts[next].axis, shifts[next].sign, world);
      mass_error = std::max(mass_error, std::abs(got.left - expected.left) / expected.left);
      ++next;
      whole->set_obstacle(obstacle);
      block->set_obstacle(part);
    }
  }
  return {halo::differing_populations(*whole, *block, o), mass_error};
}

TEST(MpiHalo, ABodyAndTheMovingWindowAcrossRanksStepBitForBitAsTheUnsplitLattice) {
  const int ranks = parallel::world().size();
  for (const halo::FaceSet& faces : halo::face_sets()) {
    const lbm::SolverConfig cfg = halo::lattice_of(faces, lbm::LatticeKind::D3Q19, lbm::Precision::float64);
    for (const auto& blocks : splits_of(ranks, {cfg.nx, cfg.ny, cfg.nz})) {
      for (const lbm::WallRule rule : {lbm::WallRule::bouzidi, lbm::WallRule::quadratic}) {
        // The quadratic rule refuses blocks one cell thick (tests/lbm/test_halo_obstacle.cpp).
        if (rule == lbm::WallRule::quadratic && block_config(cfg, blocks, 0).split->thinnest_block() < 2) continue;
        SCOPED_TRACE(std::string(faces.name) + ", " + lbm::to_string(rule) + ", blocks " + std::to_string(blocks[0]) +
                     " x " + std::to_string(blocks[1]) + " x " + std::to_string(blocks[2]) + ", rank " +
                     std::to_string(parallel::world().rank()));
        const auto [differing, mass_error] = run_block_with_body(cfg, blocks, rule);
        EXPECT_EQ(differing, 0);
        // The blocks' shares of a layer's mass add up in another order than the unsplit sum: equal
        // to round-off (relative 1e-13 for ~100 terms of order 1 in double).
        EXPECT_LT(mass_error, 1e-13);
      }
    }
  }
}

// The rank-ordered sum: every rank adds the same parts in the same order, so all hold the same
// bits; the parts are exact in double, so the sum is exactly n (n + 1) / 2 and n.
TEST(MpiHalo, SumsInRankOrderAndGathersEveryRanksPart) {
  parallel::Communicator& world = parallel::world();
  const int n = world.size(), r = world.rank();
  const std::vector<double> sum = parallel::sum_in_rank_order(world, {r + 1.0, 1.0});
  EXPECT_EQ(sum, (std::vector<double>{n * (n + 1) / 2.0, static_cast<double>(n)}));
  // Parts of different lengths: rank k sends k values k.
  const std::vector<std::vector<double>> parts = world.gather_all(std::vector<double>(static_cast<std::size_t>(r), r));
  ASSERT_EQ(parts.size(), static_cast<std::size_t>(n));
  for (int k = 0; k < n; ++k)
    EXPECT_EQ(parts[static_cast<std::size_t>(k)], std::vector<double>(static_cast<std::size_t>(k), k));
  // The same to rank 0 alone.
  const std::vector<std::vector<double>> at_root =
      world.gather_to_root(std::vector<double>(static_cast<std::size_t>(r), r));
  EXPECT_EQ(at_root.size(), r == 0 ? static_cast<std::size_t>(n) : 0u);
  for (std::size_t k = 0; k < at_root.size(); ++k)
    EXPECT_EQ(at_root[k], std::vector<double>(k, static_cast<double>(k)));
}

}  // namespace test_mpi_halo

// MPI starts before the tests and ends after them; only rank 0 prints the report, and mpirun
// returns non-zero when any rank does.
int main(int argc, char** argv) {
  ::testing::InitGoogleTest(&argc, argv);
  settle::parallel::Communicator& world = settle::parallel::world();
  if (world.rank() != 0) {
    ::testing::TestEventListeners& listeners = ::testing::UnitTest::GetInstance()->listeners();
    delete listeners.Release(listeners.default_result_printer());
  }
  return RUN_ALL_TESTS();
}
