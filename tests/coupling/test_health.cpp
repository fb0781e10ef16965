// Numerical health checks (coupling/health.hpp) and the run loop's stop conditions
// (coupling/runner.hpp) on a small fixed sphere in a periodic box.
#include <cmath>
#include <limits>
#include <vector>

#include <gtest/gtest.h>

#include "common/error.hpp"
#include "coupling/health.hpp"
#include "coupling/runner.hpp"
#include "periodic_sphere.hpp"

namespace {

using namespace settle::coupling;
using namespace settle::coupling::testing;

SimulationSetup small_setup() {
  PeriodicSphereOptions o;
  o.cells_per_diameter = 6.0;
  o.box_cells = 16;
  SimulationSetup s = periodic_sphere_setup(o);
  s.body_force_si = Eigen::Vector3d(1e-6, 0.0, 0.0);
  s.end_time_si = 40.0;  // steps (dt = 1)
  s.output_interval_si = 4.0;  // even steps: where set_cell_populations may write
  return s;
}

/// Scales one cell's populations so that its density becomes `rho` (velocity unchanged): a local
/// defect the check must find.
void plant_density(Simulation& sim, double rho) {
  std::vector<double> f(static_cast<std::size_t>(sim.fluid().velocity_count()));
  sim.fluid().cell_populations(3, 3, 3, f);
  double rho0 = 0.0;
  for (double v : f) rho0 += v;
  for (double& v : f) v *= rho / rho0;
  sim.fluid().set_cell_populations(3, 3, 3, f);
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
}

TEST(Health, SpeedBeyondTheLimitIsFoundAndNamed) {
  Simulation sim(small_setup());
  HealthLimits strict;
  strict.max_lattice_speed = 1e-9;  // any motion at all exceeds it
  for (int n = 0; n < 5; ++n) sim.step();
  const HealthReport r = check_health(sim, strict);
  EXPECT_NE(r.problem.find("numerics.max_lattice_velocity"), std::string::npos) << r.problem;
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

TEST(Runner, StopAfterSampleEndsTheRunWithItsReason) {
  Simulation sim(small_setup());
  RunCallbacks callbacks;
  callbacks.stop_after_sample = [](const Sample& s) { return s.t_si >= 8.0 ? std::string("terminal_state") : std::string(); };
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

}  // namespace
