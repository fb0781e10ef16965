// The halo across MPI ranks (run under mpirun by CTest with 1, 2 and 4 processes): every way of
// splitting the lattice over this many ranks, each rank stepping its block with its messages sent
// through the communicator, must leave every population of its block bit for bit equal to the
// unsplit lattice's, which each rank also steps. The same check as tests/lbm/test_halo.cpp, whose
// messages are handed over in one process: here they travel between processes.
#include <gtest/gtest.h>

#include <array>
#include <string>
#include <vector>

#include "lbm/decomposition.hpp"
#include "lbm/solver.hpp"
#include "parallel/communicator.hpp"
#include "support/halo_cases.hpp"

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

// Differing populations of this rank's block after each of the last two of `steps` steps (an odd
// and an even count: both parities' copies are checked).
std::array<int, 2> run_block(const lbm::SolverConfig& whole_config, const std::array<int, 3>& blocks, int steps) {
  parallel::Communicator& world = parallel::world();
  lbm::SolverConfig cfg = whole_config;
  lbm::BlockSplit split;
  split.global = {whole_config.nx, whole_config.ny, whole_config.nz};
  split.blocks = blocks;
  split.rank = world.rank();
  cfg.split = split;
  const std::array<int, 3> n = split.extent(split.rank), o = split.offset(split.rank);
  cfg.nx = n[0], cfg.ny = n[1], cfg.nz = n[2];
  auto block = lbm::make_solver(cfg);
  block->initialise([o](int x, int y, int z) { return halo::initial_state(x + o[0], y + o[1], z + o[2]); });
  auto whole = lbm::make_solver(whole_config);
  whole->initialise(halo::initial_state);
  lbm::HaloMessages messages;
  const std::vector<int> neighbours = block->halo_ranks();
  std::array<int, 2> differing{-1, -1};
  for (int s = 0; s < steps; ++s) {
    whole->step();
    block->begin_step(messages);
    world.exchange(neighbours, messages.send, messages.receive);
    block->end_step(messages);
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
