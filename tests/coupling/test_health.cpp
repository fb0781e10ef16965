// Numerical health checks (coupling/health.hpp) and the run loop's stop conditions, checkpoint
// hook and continuation (coupling/runner.hpp) on a small fixed sphere in a periodic box.
#include <unistd.h>

#include <algorithm>
#include <bit>
#include <cmath>
#include <cstdint>
#include <filesystem>
#include <limits>
#include <stdexcept>
#include <string>
#include <vector>

#include <fmt/core.h>
#include <gtest/gtest.h>

#include "common/error.hpp"
#include "coupling/checkpoint_state.hpp"
#include "coupling/health.hpp"
#include "coupling/runner.hpp"
#include "lbm/config.hpp"
#include "periodic_sphere.hpp"

namespace test_health {

using namespace settle::coupling;
using namespace settle::coupling::testing;

SimulationSetup small_setup() {
  PeriodicSphereOptions o;
  o.cells_per_diameter = 6.0;
  o.box_cells = 16;
  SimulationSetup s = periodic_sphere_setup(o);
  s.body_force_si = Eigen::Vector3d(1e-6, 0.0, 0.0);
  s.end_time_si = 40.0;        // steps (dt = 1)
  s.output_interval_si = 4.0;  // even steps: where set_cell_populations may write
  // Double storage: a planted density reads back to round-off (1e-12 below); float storage would
  // round each population to 7 digits.
  s.precision = settle::lbm::Precision::float64;
  return s;
}

/// Scales one cell's populations so that its density becomes `rho` (velocity unchanged): a local
/// defect the check must find.
void plant_density(Simulation& sim, double rho, int x = 3, int y = 3, int z = 3) {
  std::vector<double> f(static_cast<std::size_t>(sim.fluid().velocity_count()));
  sim.fluid().cell_populations(x, y, z, f);
  double rho0 = 0.0;
  for (double v : f) rho0 += v;
  for (double& v : f) v *= rho / rho0;
  sim.fluid().set_cell_populations(x, y, z, f);
}

TEST(Health, AFreshAndARunningSimulationAreHealthy) {
  Simulation sim(small_setup());
  EXPECT_TRUE(check_health(sim).problem.empty());
  for (int n = 0; n < 20; ++n) sim.step();
  const HealthReport r = check_health(sim);
  EXPECT_TRUE(r.problem.empty()) << r.problem;
  EXPECT_TRUE(r.finite);
  // The driven flow is slow (Re << 1): far below the speed limit.
  EXPECT_LT(r.max_lattice_speed, 1e-3);
}

TEST(Health, NaNInOneCellIsFoundAndNamed) {
  Simulation sim(small_setup());
  plant_density(sim, std::numeric_limits<double>::quiet_NaN());
  const HealthReport r = check_health(sim);
  EXPECT_FALSE(r.finite);
  EXPECT_NE(r.problem.find("NaN"), std::string::npos) << r.problem;
  EXPECT_NE(r.problem.find("numerics.cells_per_diameter"), std::string::npos) << r.problem;
}

TEST(Health, DensityOutOfRangeIsFoundAndNamed) {
  Simulation sim(small_setup());
  plant_density(sim, 1.2);
  const HealthReport r = check_health(sim);
  EXPECT_NEAR(r.max_density, 1.2, 1e-12);
  EXPECT_NE(r.problem.find("density"), std::string::npos) << r.problem;
  EXPECT_NE(r.problem.find("the largest at cell (3, 3, 3) of 16x16x16"), std::string::npos) << r.problem;
}

// The message names the cell of the larger deviation and where it lies: a low density planted
// 1 cell from the grid's y = 0 face, a smaller excess elsewhere. The sphere (d = 6 cells) sits at
// the box centre, 8 cells from the corner; cell (13, 1, 8) has its centre at (13.5, 1.5, 8.5)
// cells, so (5.5, -6.5, 0.5) / 6 = (0.92, -1.08, 0.08) diameters from the particle's centre.
TEST(Health, DensityMessageNamesTheCellOfTheLargerDeviationAndItsPlace) {
  Simulation sim(small_setup());
  plant_density(sim, 1.15, 3, 3, 3);
  plant_density(sim, 0.8, 13, 1, 8);
  const HealthReport r = check_health(sim);
  EXPECT_NE(r.problem.find("the smallest at cell (13, 1, 8) of 16x16x16, (0.92, -1.08, 0.08) diameters from the "
                           "particle's centre, 1 cells from the nearest face of the grid"),
            std::string::npos)
      << r.problem;
}

// A density defect inside a body with interior markers is attributed to the pressure those
// markers hold there (docs/coupling.md), with the settings that reduce it; the same defect in the
// open fluid, or inside a body without interior markers, keeps the general cause.
TEST(Health, DensityInsideABodyWithInteriorMarkersNamesThatCause) {
  SimulationSetup with_interior = small_setup();
  with_interior.interior_markers = true;
  Simulation sim(with_interior);
  plant_density(sim, 1.2, 7, 8, 8);  // cell centre (7.5, 8.5, 8.5): 0.12 d from the centre
  const HealthReport inside = check_health(sim);
  EXPECT_NE(inside.problem.find("(inside the particle)"), std::string::npos) << inside.problem;
  EXPECT_NE(inside.problem.find("numerics.interior_markers holds rigid"), std::string::npos) << inside.problem;

  Simulation outside_sim(with_interior);
  plant_density(outside_sim, 1.2, 1, 1, 1);
  const HealthReport outside = check_health(outside_sim);
  EXPECT_EQ(outside.problem.find("(inside the particle)"), std::string::npos) << outside.problem;
  EXPECT_EQ(outside.problem.find("interior_markers"), std::string::npos) << outside.problem;

  Simulation surface_only(small_setup());
  plant_density(surface_only, 1.2, 7, 8, 8);
  const HealthReport no_option = check_health(surface_only);
  EXPECT_NE(no_option.problem.find("(inside the particle)"), std::string::npos) << no_option.problem;
  EXPECT_EQ(no_option.problem.find("interior_markers"), std::string::npos) << no_option.problem;
}

TEST(Health, SpeedBeyondTheLimitIsFoundAndNamed) {
  Simulation sim(small_setup());
  HealthLimits strict;
  strict.max_lattice_speed = 1e-9;  // any motion at all exceeds it
  for (int n = 0; n < 5; ++n) sim.step();
  const HealthReport r = check_health(sim, strict);
  EXPECT_NE(r.problem.find("numerics.max_lattice_velocity"), std::string::npos) << r.problem;
}

// The advice follows the figure that decides: above TRT's measured cell Reynolds number
// (lbm::kTrtStableCellReynolds) without a subgrid model it names numerics.subgrid_model, and says
// that a lower lattice velocity (which moves tau, not the cell Reynolds number) does not help; with
// the model on, it names the grid, with the cells that bring the cell Reynolds number to the bound.
TEST(Health, AWakeBeyondTrtsCellReynoldsNumberNamesTheSubgridModelThenTheGrid) {
  PeriodicSphereOptions o;
  o.cells_per_diameter = 6.0;
  o.box_cells = 16;
  o.tau = 0.502;  // cell Reynolds number 3 u / (tau - 1/2) = 60 at the towing speed below: above 20
  SimulationSetup s = periodic_sphere_setup(o);
  s.motion = settle::body::MotionKind::towed;
  s.initial.velocity_si = Eigen::Vector3d(0.04, 0.0, 0.0);  // lattice units (dx = dt = 1)
  s.collision = settle::lbm::CollisionKind::trt;
  HealthLimits strict;
  strict.max_lattice_speed = -1.0;  // any fluid fails it: the cause is what is tested

  s.subgrid_model = settle::lbm::SubgridModel::none;
  Simulation plain(s);
  ASSERT_GT(plain.plan().cell_reynolds, settle::lbm::kTrtStableCellReynolds);
  const std::string without = check_health(plain, strict).problem;
  EXPECT_NE(without.find("numerics.subgrid_model = \"auto\""), std::string::npos) << without;
  EXPECT_NE(without.find("does not help"), std::string::npos) << without;

  s.subgrid_model = settle::lbm::SubgridModel::automatic;
  Simulation modelled(s);
  EXPECT_EQ(modelled.plan().subgrid_model, settle::lbm::SubgridModel::smagorinsky);
  const std::string with = check_health(modelled, strict).problem;
  EXPECT_EQ(with.find("numerics.subgrid_model"), std::string::npos) << with;
  const double cells =
      std::ceil(o.cells_per_diameter * modelled.plan().cell_reynolds / settle::lbm::kTrtStableCellReynolds);
  EXPECT_NE(with.find(fmt::format("raise numerics.cells_per_diameter (to {:.0f}", cells)), std::string::npos) << with;
}

TEST(Runner, ADivergedRunStopsWithANumericalErrorAfterWritingTheSample) {
  Simulation sim(small_setup());
  int samples = 0;
  RunCallbacks callbacks;
  callbacks.on_sample = [&](const Sample&) {
    ++samples;
    if (samples == 2) plant_density(sim, std::numeric_limits<double>::quiet_NaN());
  };
  EXPECT_THROW(run(sim, callbacks), settle::NumericalError);
  EXPECT_EQ(samples, 2);
}

// Samples every 4 steps, checkpoints every 2: the fluid turned NaN after step 6 (even: where
// populations may be set) must stop the run before the checkpoint due at step 6 is taken, though no
// sample falls there. Without the check the checkpoint of the diverged fluid would replace the last
// good one, and a restart would begin from it.
TEST(Runner, NoCheckpointIsTakenOfADivergedFluid) {
  Simulation sim(small_setup());
  int checkpoints = 0;
  bool planted = false;
  RunCallbacks callbacks;
  callbacks.checkpoint_interval_si = 2.0;
  callbacks.checkpoint_due = [&](const RunStart& state) {
    EXPECT_FALSE(planted) << "a checkpoint at step " << state.step << " of a diverged fluid";
    ++checkpoints;
  };
  callbacks.after_step = [&](double t_si, double) {
    if (std::lround(t_si) != 6) return;
    plant_density(sim, std::numeric_limits<double>::quiet_NaN());
    planted = true;
  };
  EXPECT_THROW(run(sim, callbacks), settle::NumericalError);
  EXPECT_EQ(checkpoints, 2);  // at steps 2 and 4
}

// summary.json's fluid_health: the largest deviation and speed the checks met, over every sample.
// A density defect of 5% planted at one sample (inside the limit, so the run goes on) must be the
// largest deviation of the run: the slow driven flow's own is ~1e-6.
TEST(Runner, ExtremesAreTheLargestValuesTheHealthCheckMet) {
  Simulation sim(small_setup());
  RunExtremes seen;
  RunCallbacks callbacks;
  int samples = 0;
  callbacks.on_sample = [&](const Sample&) {
    if (++samples == 3) plant_density(sim, 1.05);  // at step 8: even, where populations may be set
    const HealthReport h = check_health(sim);      // what the runner checks next, at the same state
    seen.density_deviation =
        std::max({seen.density_deviation, std::abs(h.min_density - 1.0), std::abs(h.max_density - 1.0)});
    seen.lattice_speed = std::max(seen.lattice_speed, h.max_lattice_speed);
  };
  const RunResult r = run(sim, callbacks);
  EXPECT_EQ(r.stop_reason, "end_time");
  EXPECT_EQ(r.extremes.density_deviation, seen.density_deviation);
  EXPECT_EQ(r.extremes.lattice_speed, seen.lattice_speed);
  EXPECT_NEAR(r.extremes.density_deviation, 0.05, 1e-12);
  EXPECT_GT(r.extremes.lattice_speed, 0.0);
}

TEST(Runner, StopAfterSampleEndsTheRunWithItsReason) {
  Simulation sim(small_setup());
  RunCallbacks callbacks;
  callbacks.stop_after_sample = [](const Sample& s) {
    return s.t_si >= 8.0 ? std::string("terminal_state") : std::string();
  };
  const RunResult r = run(sim, callbacks);
  EXPECT_EQ(r.stop_reason, "terminal_state");
  EXPECT_EQ(r.steps, 8);
  EXPECT_DOUBLE_EQ(r.samples.back().t_si, 8.0);
}

TEST(Runner, InterruptedEndsTheRunAfterTheCurrentStepAndSamplesIt) {
  Simulation sim(small_setup());
  RunCallbacks callbacks;
  int checks = 0;
  callbacks.interrupted = [&] { return ++checks == 7; };
  const RunResult r = run(sim, callbacks);
  EXPECT_EQ(r.stop_reason, "interrupted");
  EXPECT_EQ(r.steps, 7);
  EXPECT_DOUBLE_EQ(r.samples.back().t_si, 7.0);  // the state at the stop is the last row
}

// Checkpoints every 10 steps (dt = 1) of a 40-step run: after steps 10, 20, 30 and 40, none at the
// start; each with the loop's state at that step (samples every 4 steps: 0, 4, 8 before step 10).
TEST(Runner, CheckpointIsDueAtEachIntervalWithTheLoopState) {
  Simulation sim(small_setup());
  RunCallbacks callbacks;
  callbacks.checkpoint_interval_si = 10.0;
  std::vector<RunStart> states;
  callbacks.checkpoint_due = [&](const RunStart& state) { states.push_back(state); };
  const RunResult r = run(sim, callbacks);
  ASSERT_EQ(states.size(), 4u);
  for (std::size_t i = 0; i < states.size(); ++i) EXPECT_EQ(states[i].step, 10 * static_cast<std::int64_t>(i + 1));
  EXPECT_EQ(states[0].next_output_index, 3);
  ASSERT_EQ(states[0].samples.size(), 3u);
  EXPECT_DOUBLE_EQ(states[0].samples.back().t_si, 8.0);
  EXPECT_EQ(states[3].samples.size(), r.samples.size());  // step 40 is sampled before its checkpoint
  EXPECT_EQ(r.samples.size(), 11u);                       // the samples lent to the callback came back
}

// A wall-clock interval: a checkpoint once that much wall time has passed since the last one.
// An interval far below a step's wall time makes one due after every step (a clock that always
// advances: steady_clock), and the simulated-time interval still adds none twice.
TEST(Runner, WallClockIntervalMakesACheckpointDueOncePassed) {
  Simulation sim(small_setup());
  RunCallbacks callbacks;
  callbacks.checkpoint_wall_interval_s = 1e-12;
  callbacks.checkpoint_interval_si = 10.0;
  std::vector<std::int64_t> steps;
  callbacks.checkpoint_due = [&](const RunStart& state) { steps.push_back(state.step); };
  const RunResult r = run(sim, callbacks);
  ASSERT_EQ(steps.size(), static_cast<std::size_t>(r.steps));
  for (std::size_t i = 0; i < steps.size(); ++i) EXPECT_EQ(steps[i], static_cast<std::int64_t>(i + 1));
  // A wall interval longer than the run adds none to the simulated-time schedule.
  Simulation again(small_setup());
  callbacks.checkpoint_wall_interval_s = 1e6;
  steps.clear();
  run(again, callbacks);
  EXPECT_EQ(steps, (std::vector<std::int64_t>{10, 20, 30, 40}));
}

// An interruption hands over a checkpoint at its step whatever the interval (here none).
TEST(Runner, InterruptionHandsOverACheckpointAtItsStep) {
  Simulation sim(small_setup());
  RunCallbacks callbacks;
  int checks = 0;
  callbacks.interrupted = [&] { return ++checks == 7; };
  std::vector<std::int64_t> steps;
  callbacks.checkpoint_due = [&](const RunStart& state) { steps.push_back(state.step); };
  EXPECT_EQ(run(sim, callbacks).stop_reason, "interrupted");
  EXPECT_EQ(steps, std::vector<std::int64_t>{7});
}

// A run continued from a checkpoint (written at step 20, the run then interrupted at step 23) into a
// fresh simulation gives the uninterrupted run's result: the same samples bit for bit (time, forces,
// slip; the restart test covers the body and fluid state), no sample twice or missing, the same
// step count and summary. Exact equality: the same build and thread count in one process, and the
// restart is bit for bit (coupling/checkpoint_state.hpp).
TEST(Runner, ContinuedRunEqualsTheUninterruptedRun) {
  Simulation straight(small_setup());
  const RunResult expected = run(straight, RunCallbacks{});

  const std::filesystem::path file =
      std::filesystem::temp_directory_path() / ("settle_runner_" + std::to_string(::getpid()) + ".ckpt");
  RunStart saved;
  {
    Simulation first(small_setup());
    RunCallbacks callbacks;
    // Step 10 lies between the rows of steps 8 and 12: the interval's sums travel in the state.
    callbacks.checkpoint_interval_si = 10.0;
    callbacks.checkpoint_due = [&](const RunStart& state) {
      if (state.step != 10) return;
      saved = state;
      write_checkpoint(first, CheckpointCallerData{}, file);
    };
    int checks = 0;
    callbacks.interrupted = [&] { return ++checks == 23; };
    ASSERT_EQ(run(first, callbacks).stop_reason, "interrupted");
  }
  Simulation second(small_setup());
  SimulationCheckpoint(file).restore(second);
  std::filesystem::remove(file);
  const RunResult continued = run(second, RunCallbacks{}, saved);

  EXPECT_EQ(continued.stop_reason, "end_time");
  EXPECT_EQ(continued.steps, expected.steps);
  ASSERT_EQ(continued.samples.size(), expected.samples.size());
  for (std::size_t i = 0; i < expected.samples.size(); ++i) {
    const Sample& a = expected.samples[i];
    const Sample& b = continued.samples[i];
    EXPECT_EQ(std::bit_cast<std::uint64_t>(a.t_si), std::bit_cast<std::uint64_t>(b.t_si)) << i;
    for (int k = 0; k < 3; ++k) {
      EXPECT_EQ(std::bit_cast<std::uint64_t>(a.hydrodynamic.force_si[k]),
                std::bit_cast<std::uint64_t>(b.hydrodynamic.force_si[k]))
          << i;
      EXPECT_EQ(std::bit_cast<std::uint64_t>(a.relative_flow_si[k]),
                std::bit_cast<std::uint64_t>(b.relative_flow_si[k]))
          << i;
    }
    EXPECT_EQ(std::bit_cast<std::uint64_t>(a.slip_max_si), std::bit_cast<std::uint64_t>(b.slip_max_si)) << i;
  }
  EXPECT_EQ(continued.extremes.density_deviation, expected.extremes.density_deviation);
  EXPECT_EQ(continued.extremes.lattice_speed, expected.extremes.lattice_speed);
  const RunSummary s_expected = summarise(straight, expected);
  const RunSummary s_continued = summarise(second, continued);
  EXPECT_EQ(s_continued.drag_coefficient, s_expected.drag_coefficient);
  EXPECT_EQ(s_continued.averaged_samples, s_expected.averaged_samples);
}

// A row's wrench is the mean over the steps since the row before, so that means over rows are time
// means (runner.hpp, IntervalSums). The driven flow's start-up changes the drag from step to step,
// so a row holding its last step's force instead would miss the mean by far more than round-off
// (checked: the two differ by over 1e-3 of the force in the rows compared).
TEST(Runner, ARowHoldsTheMeanWrenchOfItsInterval) {
  Simulation sim(small_setup());
  std::vector<settle::body::Wrench> steps;  // steps[n - 1]: of step n
  RunCallbacks callbacks;
  callbacks.after_step = [&](double, double) {
    if (sim.steps() > static_cast<std::int64_t>(steps.size())) steps.push_back(sim.last_step().hydrodynamic);
  };
  const RunResult r = run(sim, callbacks);
  ASSERT_EQ(steps.size(), 40u);
  ASSERT_EQ(r.samples.size(), 11u);  // t = 0, 4, ..., 40
  double largest_gap = 0.0;
  for (std::size_t row = 1; row < r.samples.size(); ++row) {
    Eigen::Vector3d force = Eigen::Vector3d::Zero(), torque = Eigen::Vector3d::Zero();
    for (std::size_t n = 4 * (row - 1); n < 4 * row; ++n) force += steps[n].force_si, torque += steps[n].torque_si;
    force /= 4.0, torque /= 4.0;
    const Sample& s = r.samples[row];
    // Four additions and a division: a few roundings of the force's size.
    EXPECT_LT((s.hydrodynamic.force_si - force).norm(), 1e-14 * force.norm()) << row;
    EXPECT_LT((s.hydrodynamic.torque_si - torque).norm(), 1e-14 * force.norm()) << row;
    largest_gap = std::max(largest_gap, (steps[4 * row - 1].force_si - force).norm() / force.norm());
  }
  EXPECT_GT(largest_gap, 1e-3);
}

// A start that does not match the simulation's step is a programming error, refused.
TEST(Runner, StartStepMustMatchTheSimulation) {
  Simulation sim(small_setup());
  RunStart start;
  start.step = 5;
  EXPECT_THROW(run(sim, RunCallbacks{}, start), std::invalid_argument);
}

}  // namespace test_health
