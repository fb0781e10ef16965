// The coupled step on a split lattice (docs/parallel.md): a spheroid settling with either coupling,
// its window following it, run on 2, 3 and 4 ranks (threads of this program, through the same
// communicator interface MPI processes use) must give the same body state after every step and the
// same populations at the end as the one-process run, bit for bit. Exact equality is the right
// check: the blocks step the fluid exactly (tests/lbm/test_halo_obstacle.cpp); the momentum
// exchange's refill reads the same neighbours' values and its link momenta are added in the
// one-process order; the immersed boundary runs the same forcing on the same box, gathered whole
// on every rank. Any difference is a missing link, a misplaced cell or a reordered sum.
#include <gtest/gtest.h>

#include <algorithm>
#include <bit>
#include <cmath>
#include <cstdint>
#include <limits>
#include <memory>
#include <mutex>
#include <string>
#include <vector>

#include "body/shape_factory.hpp"
#include "common/error.hpp"
#include "coupling/simulation.hpp"
#include "support/default_setup.hpp"
#include "support/halo_cases.hpp"
#include "support/thread_communicator.hpp"

namespace test_split_simulation {

using namespace settle;
using namespace settle::coupling;

// A tilted prolate spheroid settling and turning in a column (d_eq = 8 cells, tau = 1, lattice-like
// SI units: dx = dt = 1), periodic sides and walls on z, the window following it: 24 x 24 x 40
// cells, the body across the middle of every split the ranks below choose, the window shifting
// about every 30 steps.
SimulationSetup settling_spheroid() {
  SimulationSetup s = settle::test::default_setup();
  body::ShapeSpec spec;
  spec.shape = "spheroid";
  spec.aspect_ratio = 2.0;
  spec.diameter = 8.0 / std::cbrt(2.0);
  s.shape = std::shared_ptr<const body::Shape>(body::make_shape(spec));
  s.motion = body::MotionKind::free;
  s.coupling = CouplingKind::momentum_exchange;
  s.particle_density_si = 1.5;
  s.fluid_density_si = 1.0;
  s.dynamic_viscosity_si = 1.0 / 6.0;
  s.gravity_si = Eigen::Vector3d(0.0, 0.0, -8.0e-3);
  s.domain_size_si = Eigen::Vector3d(24.0, 24.0, 40.0);
  s.boundaries = {lbm::Boundary::periodic, lbm::Boundary::periodic, lbm::Boundary::no_slip};
  s.follow_particle = true;
  s.cells_per_diameter = 8.0;
  s.tau = 1.0;
  s.max_lattice_velocity = 0.15;  // as tests/coupling/test_restart.cpp: lets the case through
  s.initial.position_si = Eigen::Vector3d(12.0, 12.3, 20.4);
  s.initial.velocity_si = Eigen::Vector3d(0.004, -0.002, -0.03);
  s.initial.attitude = attitude::Attitude::from_set1(0.2, 0.9, 0.1);
  s.initial.angular_velocity_b_si = Eigen::Vector3d(0.0, 0.002, 0.001);
  return s;
}

constexpr int kSteps = 120;

// What every step leaves: the body's state and the wrench it received, as raw bits.
std::vector<std::uint64_t> record(const Simulation& sim) {
  std::vector<std::uint64_t> bits;
  const auto add = [&bits](const Eigen::Vector3d& v) {
    for (int a = 0; a < 3; ++a) bits.push_back(std::bit_cast<std::uint64_t>(v[a]));
  };
  const auto& state = sim.body().state();
  add(state.position_si);
  add(state.velocity_si);
  add(state.angular_velocity_b_si);
  add(state.attitude.angles());
  add(sim.last_step().hydrodynamic.force_si);
  add(sim.last_step().hydrodynamic.torque_si);
  add(sim.frame().window_origin_si);
  return bits;
}

struct StepRecords {
  std::vector<std::vector<std::uint64_t>> steps;
};

void expect_split_runs_as_one_process(CouplingKind coupling, lbm::WallRule rule = lbm::WallRule::bouzidi) {
  SimulationSetup setup = settling_spheroid();
  setup.coupling = coupling;
  setup.wall_rule = rule;
  // The covered cells' torque is gathered from every rank and added in one order: on here, so
  // that the check covers that sum too (it only adds to the torque the links give).
  setup.covered_cell_torque = coupling == CouplingKind::momentum_exchange;
  Simulation whole(setup);
  StepRecords reference;
  int shifts = 0;
  for (int s = 0; s < kSteps; ++s) {
    const Eigen::Vector3d before = whole.frame().window_origin_si;
    whole.step();
    shifts += whole.frame().window_origin_si != before ? 1 : 0;
    reference.steps.push_back(record(whole));
  }
  ASSERT_GE(shifts, 2) << "the window must shift for the check to cover it";
  if (coupling == CouplingKind::momentum_exchange) {
    ASSERT_GT(whole.fluid().solid_cell_count(), 100u);
  } else {
    ASSERT_GT(whole.fluid().forced_cell_count(), 300u);
  }
  // The superficial velocity (a fixed body's far field) is summed per block, then over the ranks:
  // the same terms in another grouping, so it may differ by the rounding of a reordered sum of n
  // terms, at most (n - 1) eps sum |terms| (Higham 2002, Accuracy and Stability of Numerical
  // Algorithms, 2nd ed., eq. 4.4). The terms are the N cells' velocities and, with the immersed
  // boundary, at most N corrections alpha u no larger than them: n < 2 N, sum |terms| <= 2 sum |u|.
  // The mean divides by N.
  const lbm::VectorField u = whole.fluid().velocity_field();
  double sum_of_speeds = 0.0;
  for (std::size_t n = 0; n < u.x.size(); ++n) sum_of_speeds += std::abs(u.x[n]) + std::abs(u.y[n]) + std::abs(u.z[n]);
  const double reordering_bound =
      4.0 * std::numeric_limits<double>::epsilon() * whole.units().velocity_si(sum_of_speeds);
  const Eigen::Vector3d superficial = whole.superficial_velocity_si();

  for (const int ranks : {2, 3, 4}) {
    SCOPED_TRACE(std::to_string(ranks) + " ranks");
    test::ThreadRanks threads(ranks);
    std::mutex report;
    std::vector<int> first_differing_step(static_cast<std::size_t>(ranks), -1);
    std::vector<int> differing_populations(static_cast<std::size_t>(ranks), -1);
    std::vector<std::array<int, 3>> blocks(static_cast<std::size_t>(ranks));
    std::vector<double> superficial_difference(static_cast<std::size_t>(ranks), -1.0);
    threads.run([&](parallel::Communicator& communicator) {
      Simulation part(setup, communicator);
      int first = -1;
      for (int s = 0; s < kSteps; ++s) {
        part.step();
        if (first < 0 && record(part) != reference.steps[static_cast<std::size_t>(s)]) first = s + 1;
      }
      const lbm::BlockSplit& split = *part.fluid().config().split;
      const int differing = test::halo::differing_populations(whole.fluid(), part.fluid(), split.offset(split.rank));
      const double superficial_off = (part.superficial_velocity_si() - superficial).norm();
      std::lock_guard lock(report);
      superficial_difference[static_cast<std::size_t>(split.rank)] = superficial_off;
      first_differing_step[static_cast<std::size_t>(split.rank)] = first;
      differing_populations[static_cast<std::size_t>(split.rank)] = differing;
      blocks[static_cast<std::size_t>(split.rank)] = split.blocks;
    });
    for (int r = 0; r < ranks; ++r) {
      const auto& b = blocks[static_cast<std::size_t>(r)];
      SCOPED_TRACE("rank " + std::to_string(r) + " of blocks " + std::to_string(b[0]) + " x " + std::to_string(b[1]) +
                   " x " + std::to_string(b[2]));
      EXPECT_EQ(first_differing_step[static_cast<std::size_t>(r)], -1) << "first step that differs";
      EXPECT_EQ(differing_populations[static_cast<std::size_t>(r)], 0);
      EXPECT_LE(superficial_difference[static_cast<std::size_t>(r)], reordering_bound);
      EXPECT_GE(superficial_difference[static_cast<std::size_t>(r)], 0.0);
    }
  }
}

TEST(SplitSimulation, TheMomentumExchangeOnTwoThreeAndFourRanksMovesBitForBitAsInOneProcess) {
  expect_split_runs_as_one_process(CouplingKind::momentum_exchange);
}

// The quadratic wall rule reads two cells behind a link, beyond a block's halo: those values come from
// the block that holds them (lbm::BlockExchange::exchanges_far_values), so the split changes nothing.
TEST(SplitSimulation, TheQuadraticWallRuleOnTwoThreeAndFourRanksMovesBitForBitAsInOneProcess) {
  expect_split_runs_as_one_process(CouplingKind::momentum_exchange, lbm::WallRule::quadratic);
}

// 23 ranks cut the 40 cells along z into blocks of one and two cells: the quadratic rule's far value
// of a link on a one-cell block lies two blocks away, so every rank must refuse the case alike (a
// refusal on some ranks only would leave the others waiting in an exchange) and name the key. The
// linear rule, which reads no far values, builds the same split: the control that the refusal is
// the rule's.
TEST(SplitSimulation, TheQuadraticRuleIsRefusedOnEveryRankOfASplitWithBlocksOneCellThick) {
  constexpr int kRanks = 23;
  for (const lbm::WallRule rule : {lbm::WallRule::quadratic, lbm::WallRule::bouzidi}) {
    SCOPED_TRACE(lbm::to_string(rule));
    SimulationSetup setup = settling_spheroid();
    setup.wall_rule = rule;
    test::ThreadRanks threads(kRanks);
    std::mutex report;
    std::vector<std::string> errors;
    int thinnest = -1;
    threads.run([&](parallel::Communicator& communicator) {
      std::string error;
      int block_thickness = -1;
      try {
        const Simulation part(setup, communicator);
        block_thickness = part.fluid().config().split->thinnest_block();
      } catch (const InputError& e) {
        error = e.what();
      }
      std::lock_guard lock(report);
      errors.push_back(error);
      thinnest = std::max(thinnest, block_thickness);
    });
    ASSERT_EQ(errors.size(), static_cast<std::size_t>(kRanks));
    for (const std::string& e : errors) {
      if (rule == lbm::WallRule::quadratic) {
        EXPECT_NE(e.find("numerics.wall_rule"), std::string::npos) << e;
        EXPECT_NE(e.find("\"bouzidi\""), std::string::npos) << e;
      } else {
        EXPECT_EQ(e, "");
      }
    }
    if (rule == lbm::WallRule::bouzidi) {
      EXPECT_EQ(thinnest, 1);  // the split is the thin one
    }
  }
}

TEST(SplitSimulation, TheImmersedBoundaryOnTwoThreeAndFourRanksMovesBitForBitAsInOneProcess) {
  expect_split_runs_as_one_process(CouplingKind::immersed_boundary);
}

}  // namespace test_split_simulation
