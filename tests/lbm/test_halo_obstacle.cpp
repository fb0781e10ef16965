// A body's walls and the moving window on a split lattice (lbm/decomposition.hpp): a sphere of
// solid cells with interpolated bounce-back links, placed across block faces and moving, and window
// shifts along and across the split axes at both parities, step exactly as on the unsplit lattice.
// Exact equality is the right check for the same reason as in test_halo.cpp: the blocks run the
// same arithmetic on the same values, and a link that reads or writes the wrong slot (a ghost that
// was not refreshed, a returned population lost in a shift) changes bits.
#include <gtest/gtest.h>

#include <array>
#include <cmath>
#include <map>
#include <optional>
#include <span>
#include <string>
#include <tuple>
#include <vector>

#include "lbm/block_exchange.hpp"
#include "lbm/decomposition.hpp"
#include "lbm/solver.hpp"
#include "support/halo_cases.hpp"
#include "support/sphere_obstacle.hpp"
#include "support/split_lattice.hpp"

namespace test_halo_obstacle {

using namespace settle::lbm;
using namespace settle::test;
using halo::FaceSet;
using halo::SplitLattice;

using halo::block_obstacle;
using halo::Sphere;
using halo::whole_obstacle;

void set_everywhere(Solver& whole, SplitLattice& split, const Obstacle& obstacle) {
  whole.set_obstacle(obstacle);
  for (int r = 0; r < split.block_count(); ++r) split.block(r).set_obstacle(block_obstacle(obstacle, split.split(), r));
}

// The cells a shift uncovered (solid before, fluid after the obstacle is set again) refilled at
// rest with the wall's velocity, on both lattices, as a coupling would.
void refill(Solver& whole, SplitLattice& split, const std::vector<std::array<int, 3>>& was_solid, const Sphere& s) {
  for (const auto& c : was_solid) {
    if (whole.is_solid(c[0], c[1], c[2])) continue;
    const Eigen::Vector3d u = s.velocity + s.spin.cross(Eigen::Vector3d(c[0], c[1], c[2]) - s.centre);
    whole.refill_cell(c, 1.0, u, std::nullopt);
    const int r = split.split().owner(c);
    const auto o = split.split().offset(r);
    split.block(r).refill_cell({c[0] - o[0], c[1] - o[1], c[2] - o[2]}, 1.0, u, std::nullopt);
  }
}

// Links' momenta that differ in any bit, matched by (global cell, direction).
int differing_wall_momenta(const Solver& whole, const Obstacle& obstacle, const SplitLattice& split) {
  std::map<std::tuple<int, int, int, int>, Eigen::Vector3d> by_link;
  for (std::size_t k = 0; k < obstacle.links.size(); ++k) {
    const auto& l = obstacle.links[k];
    by_link[{l.cell[0], l.cell[1], l.cell[2], l.dir}] = whole.wall_momentum()[k];
  }
  int differing = 0;
  for (int r = 0; r < split.block_count(); ++r) {
    const Obstacle part = block_obstacle(obstacle, split.split(), r);
    const auto o = split.split().offset(r);
    for (std::size_t k = 0; k < part.links.size(); ++k) {
      const auto& l = part.links[k];
      const Eigen::Vector3d& expected = by_link.at({l.cell[0] + o[0], l.cell[1] + o[1], l.cell[2] + o[2], l.dir});
      const Eigen::Vector3d& got = split.block(r).wall_momentum()[k];
      for (int a = 0; a < 3; ++a) differing += halo::bits(expected[a]) != halo::bits(got[a]);
    }
  }
  return differing;
}

struct Shift {
  int after_step, axis, sign;
};

// The far values (the quadratic rule's third values held by another block) the blocks ask for.
std::size_t far_values_asked(SplitLattice& split) {
  std::size_t asked = 0;
  for (int r = 0; r < split.block_count(); ++r) {
    HaloMessages m;
    split.block(r).block_exchange().far_requests(m);
    for (const auto& values : m.send) asked += values.size() / 4;
  }
  return asked;
}

// Steps both lattices, shifting the window after the given steps and setting the sphere again at
// its place in the window (the body held by the window, the fluid moving past it). Adds the far
// values asked for at the start to `far_asked`.
void expect_same_as_unsplit(const SolverConfig& cfg, const std::array<int, 3>& blocks, const Sphere& sphere,
                            const std::vector<Shift>& shifts, int steps, WallRule rule, std::size_t& far_asked) {
  auto whole = make_solver(cfg);
  whole->initialise(halo::initial_state);
  SplitLattice split(cfg, blocks);
  const auto velocities = velocity_set(cfg.lattice);
  Obstacle obstacle = whole_obstacle(sphere, cfg, velocities);
  obstacle.rule = rule;
  ASSERT_GT(obstacle.links.size(), 50u);
  set_everywhere(*whole, split, obstacle);
  far_asked += far_values_asked(split);
  std::size_t next_shift = 0;
  for (int s = 1; s <= steps; ++s) {
    whole->step();
    split.step();
    if (::testing::Test::HasFatalFailure()) return;
    ASSERT_EQ(differing_wall_momenta(*whole, obstacle, split), 0) << "after step " << s;
    if (next_shift < shifts.size() && shifts[next_shift].after_step == s) {
      const Shift& sh = shifts[next_shift++];
      const auto was_solid = whole->solid_cell_list();
      const ShiftMass expected = whole->shift(sh.axis, sh.sign);
      const ShiftMass got = split.shift(sh.axis, sh.sign);
      // The blocks' shares add up in another order than the unsplit sum over the layer: equal to
      // round-off, relative 1e-13 for sums of ~100 terms of order 1 in double.
      EXPECT_NEAR(got.left, expected.left, 1e-13 * expected.left) << "shift after step " << s;
      EXPECT_EQ(got.entered, expected.entered);
      EXPECT_EQ(halo::differing_populations(*whole, split), 0) << "right after the shift after step " << s;
      set_everywhere(*whole, split, obstacle);
      refill(*whole, split, was_solid, sphere);
    }
    if (s == steps - 1 || s == steps) {
      EXPECT_EQ(halo::differing_populations(*whole, split), 0) << "after step " << s;
    }
  }
}

// The sphere straddles the block faces of every split below (x = 3, y = 3, z = 3, 5 and 7 on the
// 7 x 6 x 11 lattice) and stays two cells clear of the lattice's faces.
Sphere straddling() { return {Eigen::Vector3d(3.1, 2.85, 5.2), 1.8}; }

// With the quadratic rule a link whose second node is a ghost reads its third value from the block
// that holds it (BlockExchange::exchanges_far_values): the same value the unsplit lattice reads.
TEST(HaloObstacle, BlocksWithABodyStepAndShiftBitForBitAsTheUnsplitLattice) {
  // Shifts at both parities (after an odd and an even step count), along the split axes and across
  // them, both directions.
  const std::vector<Shift> shifts = {{7, 2, 1}, {12, 2, -1}, {19, 0, 1}, {26, 1, -1}, {33, 2, 1}, {40, 0, -1}};
  const std::vector<std::array<int, 3>> splits = {{1, 1, 2}, {2, 1, 1}, {1, 2, 2}, {1, 1, 3}, {2, 2, 2}};
  // The check must cover links whose third value another block holds, on every split; the linear
  // rules ask for none.
  std::map<std::array<int, 3>, std::size_t> far_asked;
  std::size_t linear_asked = 0;
  for (const auto& [lattice, precision] :
       {std::pair{LatticeKind::D3Q19, Precision::float64}, std::pair{LatticeKind::D3Q27, Precision::float32}}) {
    for (const FaceSet& faces : halo::face_sets()) {
      for (const auto& blocks : splits) {
        for (const WallRule rule : {WallRule::bouzidi, WallRule::quadratic, WallRule::central_linear}) {
          SCOPED_TRACE(std::string(faces.name) + ", " + to_string(lattice) + " " + to_string(precision) + ", " +
                       to_string(rule) + ", blocks " + std::to_string(blocks[0]) + " x " + std::to_string(blocks[1]) +
                       " x " + std::to_string(blocks[2]));
          std::size_t& asked = rule == WallRule::quadratic ? far_asked[blocks] : linear_asked;
          expect_same_as_unsplit(halo::lattice_of(faces, lattice, precision), blocks, straddling(), shifts, 48, rule,
                                 asked);
        }
      }
    }
  }
  EXPECT_EQ(linear_asked, 0u);
  for (const auto& blocks : splits)
    EXPECT_GT(far_asked[blocks], 0u) << blocks[0] << " x " << blocks[1] << " x " << blocks[2];
}

// Control: the populations a wall returned into a ghost must travel with the shift at an odd
// parity. Dropping those that cross into the next block (the tail of the layer message) must be
// seen.
TEST(HaloObstacle, ALostReturnedPopulationIsSeen) {
  const SolverConfig cfg = halo::lattice_of(halo::face_sets()[0], LatticeKind::D3Q19, Precision::float64);
  auto whole = make_solver(cfg);
  whole->initialise(halo::initial_state);
  SplitLattice split(cfg, {1, 1, 2});
  // Rank 0 holds z = 0-4, rank 1 z = 5-10; the sphere's upper cap at z = 4, so that links from
  // rank 1's first layer end in rank 0's cells (their populations returned into rank 1's ghosts),
  // and a shift along +z moves that layer into rank 0, where those cells are its own.
  const Sphere sphere{Eigen::Vector3d(3.1, 2.85, 3.0), 1.8};
  const Obstacle obstacle = whole_obstacle(sphere, cfg, velocity_set(cfg.lattice));
  set_everywhere(*whole, split, obstacle);
  whole->step();
  split.step();  // one step: an odd parity, the ghosts hold the walls' returned populations
  const std::size_t layer_values = 20u * static_cast<std::size_t>(cfg.nx * cfg.ny);
  int truncated = 0;
  whole->shift(2, 1);
  split.shift(2, 1, [&](int, int, std::vector<double>& m) {
    if (m.size() > layer_values) m.resize(layer_values), ++truncated;
  });
  ASSERT_GT(truncated, 0) << "no returned population crossed a block face";
  whole->step();
  split.step();
  EXPECT_GT(halo::differing_populations(*whole, split), 0);
}

// On a periodic lattice of one block the quadratic rule reaches across the wrap: a sphere moved by a
// whole number of cells so that it straddles the wrap on every axis, with the fluid moved with it,
// steps exactly as in the middle of the lattice (the kernels and the links do the same arithmetic on
// the same values). A rule that fell back to the linear one where x - c_i or x - 2 c_i is a periodic
// ghost would change bits.
TEST(HaloObstacle, TheQuadraticRuleAcrossAPeriodicWrapIsTheRuleAwayFromIt) {
  SolverConfig cfg = halo::lattice_of(halo::face_sets()[0], LatticeKind::D3Q19, Precision::float64);
  cfg.nx = 12, cfg.ny = 11, cfg.nz = 13;
  const std::array<int, 3> n{cfg.nx, cfg.ny, cfg.nz}, move{6, 5, 7};
  const auto moved = [&](std::array<int, 3> c) {
    for (std::size_t a = 0; a < 3; ++a) c[a] = (c[a] + move[a]) % n[a];
    return c;
  };
  const Sphere sphere{Eigen::Vector3d(6.1, 5.35, 6.2), 2.3};
  Obstacle middle = whole_obstacle(sphere, cfg, velocity_set(cfg.lattice));
  middle.rule = WallRule::quadratic;
  Obstacle across = middle;
  for (auto& c : across.solid_cells) c = moved(c);
  for (auto& l : across.links) l.cell = moved(l.cell);
  auto a = make_solver(cfg), b = make_solver(cfg);
  a->initialise(halo::initial_state);
  b->initialise([&](int x, int y, int z) {
    return halo::initial_state((x - move[0] + n[0]) % n[0], (y - move[1] + n[1]) % n[1], (z - move[2] + n[2]) % n[2]);
  });
  a->set_obstacle(middle);
  b->set_obstacle(across);
  std::vector<double> fa(19), fb(19);
  for (int step = 1; step <= 6; ++step) {
    a->step();
    b->step();
    int differing = 0;
    for (int z = 0; z < n[2]; ++z)
      for (int y = 0; y < n[1]; ++y)
        for (int x = 0; x < n[0]; ++x) {
          const auto m = moved({x, y, z});
          a->cell_populations(x, y, z, fa);
          b->cell_populations(m[0], m[1], m[2], fb);
          for (int i = 0; i < 19; ++i) differing += halo::bits(fa[i]) != halo::bits(fb[i]);
        }
    ASSERT_EQ(differing, 0) << "after step " << step;
  }
}

// A block one cell thick cannot hand over a cell two behind a link: every block refuses the quadratic
// rule (none may wait for another's exchange), the linear rule is taken.
TEST(HaloObstacle, TheQuadraticRuleIsRefusedByEveryBlockWhenOneIsOneCellThick) {
  const SolverConfig cfg = halo::lattice_of(halo::face_sets()[0], LatticeKind::D3Q19, Precision::float64);
  SplitLattice split(cfg, {4, 1, 1});  // x: 7 cells in blocks of 1, 2, 2 and 2
  ASSERT_EQ(split.split().thinnest_block(), 1);
  Obstacle obstacle = whole_obstacle(straddling(), cfg, velocity_set(cfg.lattice));
  for (int r = 0; r < split.block_count(); ++r) {
    EXPECT_NO_THROW(split.block(r).set_obstacle(block_obstacle(obstacle, split.split(), r))) << "block " << r;
  }
  obstacle.rule = WallRule::quadratic;
  for (int r = 0; r < split.block_count(); ++r) {
    EXPECT_THROW(split.block(r).set_obstacle(block_obstacle(obstacle, split.split(), r)), std::invalid_argument)
        << "block " << r;
  }
}

}  // namespace test_halo_obstacle
