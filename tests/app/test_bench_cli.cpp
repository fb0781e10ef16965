// Case test of `settle bench` (the real binary on a tiny box): the JSON that the README's
// throughput table is read from, and the arithmetic behind its fraction. Timings are not tested
// (speed is shown by the benchmark itself, never by a timed test).
#include <algorithm>
#include <cmath>
#include <filesystem>
#include <string>
#include <vector>

#include <gtest/gtest.h>
#include <nlohmann/json.hpp>

#include "cli_support.hpp"
#include "coupling/body_coupling.hpp"

namespace test_bench_cli {

TEST(BenchCli, EachRoundsFractionIsItsThroughputOverTheMeanOfTheProbesAroundIt) {
  const auto r = settle::test::run_settle(
      "bench", "--size 12 --steps 2 --rounds 3 --probe-gib 0.0625 --threads 1 --precision float");
  ASSERT_EQ(r.status, 0) << r.err;
  const auto j = nlohmann::json::parse(r.out);
  EXPECT_EQ(j["cells"].get<long>(), 12 * 12 * 12);
  EXPECT_EQ(j["bytes_per_cell_update"].get<int>(), (2 * 19 + 3) * 4);  // two passes of Q floats + 3 force floats
  const auto probes = j["bandwidth_probe"]["bandwidth_gbs_before_and_after_rounds"].get<std::vector<double>>();
  const auto mlups = j["mlups_per_round"].get<std::vector<double>>();
  const auto fractions = j["roofline_fraction_per_round"].get<std::vector<double>>();
  ASSERT_EQ(probes.size(), 4u);  // one before the first round and one after each
  ASSERT_EQ(mlups.size(), 3u);
  ASSERT_EQ(fractions.size(), 3u);
  std::vector<double> steady;
  for (std::size_t k = 0; k < 3; ++k) {
    const double bracket = 0.5 * (probes[k] + probes[k + 1]);
    // Same formula as the command, so only rounding separates the two.
    EXPECT_NEAR(fractions[k], mlups[k] * 1e6 * 164 * 1e-9 / bracket, 1e-12 * fractions[k]);
    if (std::abs(probes[k + 1] - probes[k]) <= 0.1 * bracket) steady.push_back(fractions[k]);
  }
  EXPECT_EQ(j["steady_rounds"].get<std::size_t>(), steady.size());
  std::vector<double> pool = steady.empty() ? fractions : steady;
  std::sort(pool.begin(), pool.end());
  const double median =
      pool.size() % 2 ? pool[pool.size() / 2] : 0.5 * (pool[pool.size() / 2 - 1] + pool[pool.size() / 2]);
  EXPECT_DOUBLE_EQ(j["roofline_fraction"].get<double>(), median);
}

// The even and odd AA steps are timed apart inside each round, so with one round the round's
// time is at least the sum of the two parities' times: its MLUPS cannot exceed their harmonic
// mean (equal numbers of steps of each parity). The margin is rounding only.
TEST(BenchCli, EvenAndOddStepThroughputsAccountForTheRound) {
  const auto r = settle::test::run_settle(
      "bench", "--size 12 --steps 4 --rounds 1 --probe-gib 0.0625 --threads 1 --precision float");
  ASSERT_EQ(r.status, 0) << r.err;
  const auto j = nlohmann::json::parse(r.out);
  const double even = j["even_step_mlups"].get<double>(), odd = j["odd_step_mlups"].get<double>();
  ASSERT_GT(even, 0.0);
  ASSERT_GT(odd, 0.0);
  const double round = j["mlups_per_round"].get<std::vector<double>>().at(0);
  EXPECT_LE(round, 2.0 / (1.0 / even + 1.0 / odd) * (1.0 + 1e-12));
}

// `settle bench --case`: the coupled step of a shipped case on a coarse grid. Every named sub-step
// is reported in step order, and the sub-steps timed inside the rounds cannot take longer than the
// rounds' own wall time (the remainder, `outside_substeps`, is the loop and the timers; negative
// only if a sub-step were booked twice or the timers were read outside the rounds). The margin
// is the clocks' rounding.
TEST(BenchCli, CaseReportsEverySubstepWithinTheStepsWallTime) {
  const std::string towed = (std::filesystem::path(SETTLE_SOURCE_DIR) / "cases" / "towed_sphere.toml").string();
  const auto r = settle::test::run_settle(
      "bench",
      "--case " + towed + " --set numerics.cells_per_diameter=6 --steps 4 --rounds 2 --probe-gib 0.0625 --threads 1");
  ASSERT_EQ(r.status, 0) << r.err;
  const auto j = nlohmann::json::parse(r.out);
  const auto cells = j["cells"].get<std::vector<long>>();
  ASSERT_EQ(cells.size(), 3u);
  EXPECT_EQ(j["cell_count"].get<long>(), cells[0] * cells[1] * cells[2]);
  EXPECT_EQ(j["coupling"], settle::coupling::to_string(settle::coupling::kDefaultCoupling));
  std::vector<std::string> names;
  double fluid_share = -1.0, outside_share = -1.0;
  for (const auto& s : j["substeps"]) {
    names.push_back(s["name"].get<std::string>());
    if (names.back() == "fluid") fluid_share = s["share"].get<double>();
    if (names.back() == "outside_substeps") outside_share = s["share"].get<double>();
  }
  // The momentum exchange's sub-steps 2 and 3 under its own names (docs/architecture.md).
  const std::vector<std::string> expected = {"body_predictor", "body_mapping",       "refill",
                                             "fluid",          "hydrodynamic_force", "body_corrector",
                                             "moving_window",  "outside_substeps"};
  EXPECT_EQ(names, expected);
  EXPECT_GE(outside_share, -1e-9);
  EXPECT_NEAR(j["non_fluid_share"].get<double>(), 1.0 - fluid_share, 1e-12);
  // With two rounds the median round is their mean, so the whole step's MLUPS count the same steps
  // over a time that contains the fluid sub-step's.
  EXPECT_GE(j["fluid_mlups"].get<double>(), j["mlups"].get<double>() * (1.0 - 1e-9));
}

// Kernel flags do not combine with --case (the case sets the grid and the model), and --set needs
// a case; the case's own errors name the key as `settle run` does.
TEST(BenchCli, CaseFlagsAreCheckedAndTheCasesErrorsNameTheKey) {
  const std::string towed = (std::filesystem::path(SETTLE_SOURCE_DIR) / "cases" / "towed_sphere.toml").string();
  const auto size = settle::test::run_settle("bench", "--case " + towed + " --size 16");
  EXPECT_NE(size.status, 0);
  EXPECT_NE(size.err.find("--size"), std::string::npos) << size.err;
  const auto set = settle::test::run_settle("bench", "--set numerics.cells_per_diameter=6");
  EXPECT_NE(set.status, 0);
  EXPECT_NE(set.err.find("--case"), std::string::npos) << set.err;
  const auto key = settle::test::run_settle("bench", "--case " + towed + " --set numerics.cells_per_diameter=0.5");
  EXPECT_NE(key.status, 0);
  EXPECT_NE(key.err.find("cells_per_diameter"), std::string::npos) << key.err;
}

}  // namespace test_bench_cli
