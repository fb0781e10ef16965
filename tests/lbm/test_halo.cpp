// A lattice split into blocks (lbm/decomposition.hpp) whose halo messages are handed from block to
// block in one process steps exactly as the unsplit lattice: after 100 steps every population of
// every cell is the same bit for bit, for every kind of face, on both lattices and both storage
// precisions. Exact equality is the right check: a block runs the same kernel on the same values,
// and the halo only moves stored values (or evaluates an outlet's equilibrium from the same
// populations in the same order), so any difference is a missing, misplaced or misordered link.
// The message passing between processes (MPI) carries the same messages.
#include <gtest/gtest.h>

#include <algorithm>
#include <bit>
#include <cmath>
#include <cstdint>
#include <memory>
#include <string>
#include <vector>

#include "common/error.hpp"
#include "lbm/block_exchange.hpp"
#include "lbm/decomposition.hpp"
#include "lbm/solver.hpp"
#include "support/halo_cases.hpp"
#include "support/split_lattice.hpp"

namespace test_halo {

using namespace settle::lbm;
using namespace settle::test;
using halo::face_sets;
using halo::FaceSet;
using halo::initial_state;
using halo::lattice_of;

using halo::differing_populations;
using halo::SplitLattice;

struct Variant {
  LatticeKind lattice;
  Precision precision;
};

void expect_same_as_unsplit(const SolverConfig& cfg, const std::array<int, 3>& blocks, int steps) {
  auto whole = make_solver(cfg);
  whole->initialise(initial_state);
  SplitLattice split(cfg, blocks);
  for (int s = 0; s < steps; ++s) {
    whole->step();
    split.step();
    if (::testing::Test::HasFatalFailure()) return;
    // Both parities end a step: an odd count leaves the ghosts' fill in place, an even one the fold.
    if (s == steps - 2 || s == steps - 1) {
      EXPECT_EQ(differing_populations(*whole, split), 0) << "after step " << s + 1;
    }
  }
}

TEST(Halo, BlocksStepBitForBitAsTheUnsplitLatticeForEveryFaceKind) {
  const std::vector<std::array<int, 3>> splits = {{2, 1, 1}, {1, 1, 2}, {1, 2, 2}, {2, 2, 1}, {1, 1, 3}, {2, 2, 2}};
  for (const Variant v :
       {Variant{LatticeKind::D3Q19, Precision::float64}, Variant{LatticeKind::D3Q27, Precision::float32}}) {
    for (const FaceSet& faces : face_sets()) {
      for (const auto& blocks : splits) {
        SCOPED_TRACE(std::string(faces.name) + ", " + to_string(v.lattice) + " " + to_string(v.precision) +
                     ", blocks " + std::to_string(blocks[0]) + " x " + std::to_string(blocks[1]) + " x " +
                     std::to_string(blocks[2]));
        expect_same_as_unsplit(lattice_of(faces, v.lattice, v.precision), blocks, 100);
      }
    }
  }
}

// The blocks step as parallel::step takes them (tests/support/split_lattice.hpp): the rows within
// three cells of a shared face first, then the messages, then the interior rows. On the 7 x 6 x 11
// lattice above every row of a block is a face row; here the blocks are 8 or more rows deep along
// the cut axes, so interior rows run after the messages are packed, for every face kind.
TEST(Halo, TheInteriorRowsAfterTheMessagesGiveTheSameStep) {
  const std::vector<std::array<int, 3>> splits = {{1, 2, 1}, {1, 1, 2}, {1, 2, 3}};
  for (const Variant v :
       {Variant{LatticeKind::D3Q19, Precision::float64}, Variant{LatticeKind::D3Q27, Precision::float32}}) {
    for (const FaceSet& faces : face_sets()) {
      for (const auto& blocks : splits) {
        SCOPED_TRACE(std::string(faces.name) + ", " + to_string(v.lattice) + ", blocks " + std::to_string(blocks[0]) +
                     " x " + std::to_string(blocks[1]) + " x " + std::to_string(blocks[2]));
        SolverConfig cfg = lattice_of(faces, v.lattice, v.precision);
        cfg.ny = 16, cfg.nz = 24;
        expect_same_as_unsplit(cfg, blocks, 30);
      }
    }
  }
}

// Control: the comparison sees a lost message. A block that receives nothing from one neighbour
// (zeros in place of its values) must differ from the unsplit lattice.
TEST(Halo, ALostMessageIsSeen) {
  const SolverConfig cfg = lattice_of(face_sets()[0], LatticeKind::D3Q19, Precision::float64);
  auto whole = make_solver(cfg);
  whole->initialise(initial_state);
  // Step the blocks by hand, dropping what block 1 sends to block 0.
  SolverConfig c0 = cfg, c1 = cfg;
  BlockSplit s;
  s.global = {cfg.nx, cfg.ny, cfg.nz};
  s.blocks = {1, 1, 2};
  c0.split = s, c1.split = s, c1.split->rank = 1;
  c0.nz = s.extent(0)[2], c1.nz = s.extent(1)[2];
  auto b0 = make_solver(c0), b1 = make_solver(c1);
  b0->initialise(initial_state);
  b1->initialise([&](int x, int y, int z) { return initial_state(x, y, z + s.offset(1)[2]); });
  ASSERT_EQ(b0->block_exchange().halo_ranks(), std::vector<int>{1});
  ASSERT_EQ(b1->block_exchange().halo_ranks(), std::vector<int>{0});
  HaloMessages m0, m1;
  for (int step = 0; step < 2; ++step) {
    whole->step();
    b0->block_exchange().begin_step(m0);
    b1->block_exchange().begin_step(m1);
    m0.receive = {std::vector<double>(m1.send[0].size(), 0.0)};
    m1.receive = {m0.send[0]};
    b0->block_exchange().end_step(m0);
    b1->block_exchange().end_step(m1);
  }
  const int differing = halo::differing_populations(*whole, *b0, {0, 0, 0});
  EXPECT_GT(differing, 0);
}

TEST(Halo, BlockRefusesWhatWouldSkipAnExchange) {
  const SolverConfig whole = lattice_of(face_sets()[1], LatticeKind::D3Q19, Precision::float64);
  SolverConfig cfg = whole;
  cfg.split = choose_split({whole.nx, whole.ny, whole.nz}, 2, 0);
  const std::array<int, 3> n = cfg.split->extent(0);
  cfg.nx = n[0], cfg.ny = n[1], cfg.nz = n[2];
  auto block = make_solver(cfg);
  block->initialise(initial_state);
  EXPECT_THROW(block->step(), std::logic_error);       // it would skip the exchange
  EXPECT_THROW(block->shift(2, 1), std::logic_error);  // likewise
  HaloMessages none;
  EXPECT_THROW(block->block_exchange().end_shift(none), std::logic_error);  // no shift begun
  // Rank 0's lower z face is a no-slip wall of the lattice: no ghost cell of a block lies beyond.
  Obstacle obstacle;
  obstacle.solid_cells = {{1, 1, -1}};
  EXPECT_THROW(block->set_obstacle(obstacle), std::invalid_argument);
  obstacle.solid_cells = {{1, 1, n[2]}};  // the ghost of rank 1's first layer
  EXPECT_NO_THROW(block->set_obstacle(obstacle));
  EXPECT_EQ(block->solid_cell_count(), 0u);  // a ghost is not one of the block's cells
  HaloMessages wrong;                        // no message for the one neighbour
  block->block_exchange().begin_step(wrong);
  EXPECT_THROW(block->block_exchange().end_step(HaloMessages{}), std::invalid_argument);
  // A block whose extent is not its share of the split.
  cfg.nz += 1;
  EXPECT_THROW(make_solver(cfg), settle::InputError);
}

std::vector<int> halo_ranks_of(const FaceSet& faces, const std::array<int, 3>& blocks, int rank,
                               LatticeKind lattice = LatticeKind::D3Q19) {
  SolverConfig cfg = lattice_of(faces, lattice, Precision::float64);
  BlockSplit s;
  s.global = {cfg.nx, cfg.ny, cfg.nz};
  s.blocks = blocks;
  s.rank = rank;
  cfg.split = s;
  const std::array<int, 3> n = s.extent(rank);
  cfg.nx = n[0], cfg.ny = n[1], cfg.nz = n[2];
  return make_solver(cfg)->block_exchange().halo_ranks();
}

TEST(Halo, BlocksExchangeOnlyWithTheBlocksTheyShareLinksWith) {
  // Three slabs along z: with walls on z the first and last share nothing; periodic on z, they do.
  EXPECT_EQ(halo_ranks_of(face_sets()[1], {1, 1, 3}, 0), std::vector<int>{1});
  EXPECT_EQ(halo_ranks_of(face_sets()[1], {1, 1, 3}, 1), (std::vector<int>{0, 2}));
  EXPECT_EQ(halo_ranks_of(face_sets()[0], {1, 1, 3}, 0), (std::vector<int>{1, 2}));
  // 2 x 2 x 2 blocks: D3Q19 has no velocity along a body diagonal, so the block across the corner
  // (rank 7) shares no link with rank 0; D3Q27 has one.
  EXPECT_EQ(halo_ranks_of(face_sets()[1], {2, 2, 2}, 0), (std::vector<int>{1, 2, 3, 4, 5, 6}));
  EXPECT_EQ(halo_ranks_of(face_sets()[1], {2, 2, 2}, 0, LatticeKind::D3Q27), (std::vector<int>{1, 2, 3, 4, 5, 6, 7}));
}

TEST(BlockSplit, BlocksTileTheGridAndOwnTheirCells) {
  BlockSplit s;
  s.global = {7, 5, 13};
  s.blocks = {2, 1, 3};
  std::vector<int> count(static_cast<std::size_t>(s.block_count()), 0);
  for (int z = 0; z < 13; ++z)
    for (int y = 0; y < 5; ++y)
      for (int x = 0; x < 7; ++x) {
        const int r = s.owner({x, y, z});
        const auto o = s.offset(r), n = s.extent(r);
        const std::array<int, 3> c{x, y, z};
        for (std::size_t a = 0; a < 3; ++a) {
          EXPECT_GE(c[a], o[a]);
          EXPECT_LT(c[a], o[a] + n[a]);
        }
        ++count[static_cast<std::size_t>(r)];
      }
  for (int r = 0; r < s.block_count(); ++r) {
    const auto n = s.extent(r);
    EXPECT_EQ(count[static_cast<std::size_t>(r)], n[0] * n[1] * n[2]) << "rank " << r;
  }
}

TEST(BlockSplit, ChoosesTheSmallestCutAndPrefersZOnATie) {
  // 2 ranks on a long x axis: one cut of 10 x 10 cell faces across x, not 100 x 10 across y or z.
  EXPECT_EQ(choose_split({100, 10, 10}, 2, 0).blocks, (std::array<int, 3>{2, 1, 1}));
  // 4 ranks on 64 x 64 x 128: three z cuts (3 x 4096) tie with one y and one z cut (8192 + 4096);
  // z-planes are contiguous, so z wins.
  EXPECT_EQ(choose_split({64, 64, 128}, 4, 0).blocks, (std::array<int, 3>{1, 1, 4}));
  // 8 ranks on a cube: 2 x 2 x 2 (3 cuts) beats 1 x 1 x 8 (7 cuts).
  EXPECT_EQ(choose_split({32, 32, 32}, 8, 3).blocks, (std::array<int, 3>{2, 2, 2}));
  EXPECT_EQ(choose_split({32, 32, 32}, 8, 3).rank, 3);
  EXPECT_THROW(choose_split({2, 2, 2}, 9, 0), settle::InputError);
  EXPECT_THROW(choose_split({8, 8, 8}, 0, 0), settle::InputError);
}

}  // namespace test_halo
