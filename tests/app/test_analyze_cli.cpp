// Case tests of `settle analyze`: the real binary (SETTLE_BINARY) on a real short run of the
// default case made viscous enough (Ga = 3) to reach its terminal state in 0.2 s of simulated
// time (about 2 s of wall time), and on broken run directories, which must be refused with exit
// status 2, a message naming the file, column or flag, and summary.json left as it was.
#include <algorithm>
#include <cmath>
#include <filesystem>
#include <fstream>
#include <sstream>
#include <string>
#include <vector>

#include <gtest/gtest.h>
#include <nlohmann/json.hpp>

#include "cli_support.hpp"

namespace test_analyze_cli {

namespace fs = std::filesystem;
using json = nlohmann::json;
using settle::test::read_text;
using settle::test::run_settle;
using settle::test::scratch;

void write_text(const fs::path& path, const std::string& text) {
  std::ofstream out(path, std::ios::trunc);
  out << text;
}

std::string replaced(std::string text, const std::string& from, const std::string& to) {
  const std::size_t at = text.find(from);
  if (at != std::string::npos) text.replace(at, from.size(), to);
  return text;
}

// One run shared by the tests: the default case (a prolate spheroid of aspect ratio 2 released
// 0.5 rad from vertical, rho_p/rho_f = 1.1) in a fluid 15 times more viscous than water, so
// that Re = 0.35 and the response time is 9 ms, in the default case's earlier window (6 d_eq wide,
// 3 from the axis): at this Reynolds number the walls' hold on the flow sets how fast the speed
// settles, and in today's 8 d_eq window it still creeps by more than the detector's 1% at 0.2 s.
class AnalyzeCli : public ::testing::Test {
 protected:
  static void SetUpTestSuite() {
    run_dir_ = scratch("analyze_run");
    fs::remove_all(run_dir_);
    const auto r = run_settle("run", "-o " + run_dir_.string() +
                                         " --set fluid.dynamic_viscosity=0.015 --set run.end_time=0.2"
                                         " --set 'domain.size=[7.56e-3,7.56e-3,15.12e-3]'"
                                         " --set 'particle.position=[3.78e-3,3.78e-3,7.56e-3]'"
                                         " --set run.output_interval=0.002 --threads 1");
    run_status_ = r.status;
    run_err_ = r.err;
  }
  static void TearDownTestSuite() { fs::remove_all(run_dir_); }

  void SetUp() override { ASSERT_EQ(run_status_, 0) << run_err_; }

  // A copy of the run directory that a test may break.
  static fs::path copy_of_run(const std::string& name) {
    const fs::path dir = scratch(name);
    fs::remove_all(dir);
    fs::copy(run_dir_, dir);
    return dir;
  }

  static fs::path run_dir_;
  static int run_status_;
  static std::string run_err_;
};

fs::path AnalyzeCli::run_dir_;
int AnalyzeCli::run_status_ = -1;
std::string AnalyzeCli::run_err_;

// Mean of a CSV column over the rows with t >= t0 (uniform output interval: the plain mean and
// the analysis' trapezoidal one differ only through the two end rows).
double column_mean(const fs::path& csv_path, const std::string& name, double t0) {
  std::ifstream csv(csv_path);
  std::string header;
  std::getline(csv, header);
  std::vector<std::string> names;
  std::stringstream header_stream(header);
  for (std::string field; std::getline(header_stream, field, ',');) names.push_back(field);
  const auto column = static_cast<std::size_t>(std::find(names.begin(), names.end(), name) - names.begin());
  double sum = 0.0;
  int count = 0;
  for (std::string line; std::getline(csv, line);) {
    std::vector<double> values;
    std::stringstream row(line);
    for (std::string field; std::getline(row, field, ',');) values.push_back(std::stod(field));
    if (values[0] < t0) continue;
    sum += values[column];
    ++count;
  }
  return sum / count;
}

TEST_F(AnalyzeCli, ViscousRunReachesASteadyObliqueTerminalState) {
  const fs::path dir = copy_of_run("analyze_ok");
  const json before = json::parse(read_text(dir / "summary.json"));
  const auto r = run_settle("analyze", dir.string());
  ASSERT_EQ(r.status, 0) << r.err;
  EXPECT_NE(r.out.find("terminal state   reached"), std::string::npos) << r.out;

  const json after = json::parse(read_text(dir / "summary.json"));
  // Every field of settle run is kept; the run's own numbers are untouched.
  for (const auto& [key, value] : before.items()) EXPECT_TRUE(after.contains(key)) << key;
  for (const char* key : {"cells", "dx", "dt", "tau", "steps", "wall_seconds", "mlups", "timing", "stop_reason"})
    EXPECT_EQ(after[key], before[key]) << key;

  EXPECT_TRUE(after["terminal_state"]["reached"].get<bool>());
  EXPECT_EQ(after["averaging"]["basis"], "terminal_window");
  // A tilted prolate spheroid in slow flow keeps its tilt and glides steadily: the resistance
  // along its axis is smaller than across it, so it drifts toward its lower end (-x for the
  // default case's tilt about +y; Happel and Brenner 1965, ch. 5).
  EXPECT_EQ(after["regime"], "steady_oblique") << after["regime_reason"];
  EXPECT_LT(after["terminal_velocity_vector"][0].get<double>(), 0.0);

  // The terminal vertical velocity is the mean of -uz over the averaged rows. The analysis'
  // trapezoidal mean and the plain mean differ only in the weight of the two end rows (1/40 of
  // the total each), and the velocity varies over the terminal window by less than the
  // criterion's 1%: they agree to 2.5e-4; 1e-3 is the bound used.
  const double start = after["averaging"]["start_time"].get<double>();
  const double vertical = after["terminal_vertical_velocity"].get<double>();
  EXPECT_NEAR(vertical, -column_mean(dir / "timeseries.csv", "uz", start), 1e-3 * vertical);
  // Momentum balance at the terminal state: the mean hydrodynamic force balances the net
  // weight. What is left is the body's mean acceleration over the window, below tol U / W, i.e.
  // 0.2% of the net weight, plus the force's fluctuation: 1% bounds both.
  const double cd = after["drag_coefficient"].get<double>();
  EXPECT_NEAR(after["drag_coefficient_from_force"].get<double>(), cd, 0.01 * cd);
  EXPECT_GT(cd, 0.0);

  // --json prints the same fields, and analysing again changes nothing (deterministic).
  const auto again = run_settle("analyze", dir.string() + " --json");
  ASSERT_EQ(again.status, 0) << again.err;
  const json printed = json::parse(again.out);
  EXPECT_EQ(printed["regime"], after["regime"]);
  EXPECT_EQ(json::parse(read_text(dir / "summary.json")), after);
  fs::remove_all(dir);
}

// Without the shared run (a plain test, so the fixture's run is not made for it).
TEST(AnalyzeCliShortRun, TooShortForTheDetectorIsNotClassified) {
  const fs::path dir = scratch("analyze_short");
  fs::remove_all(dir);
  // Coarse (5 cells per diameter): what the detector lacks is rows, not resolution.
  const auto run = run_settle(
      "run", "-o " + dir.string() + " --set run.end_time=0.02 --set numerics.cells_per_diameter=5 --threads 1");
  ASSERT_EQ(run.status, 0) << run.err;
  const auto r = run_settle("analyze", dir.string());
  ASSERT_EQ(r.status, 0) << r.err;
  const json summary = json::parse(read_text(dir / "summary.json"));
  EXPECT_EQ(summary["regime"], "not classified");
  EXPECT_EQ(summary["averaging"]["basis"], "second_half");
  EXPECT_FALSE(summary["terminal_state"]["reached"].get<bool>());
  fs::remove_all(dir);
}

// A run that failed or was stopped leaves no summary.json (its completion mark): its rows are
// analysed all the same, and nothing is written (a summary.json would mark it finished). The same
// rows give the same analysis, to the last bit, as the finished run's summary.json holds.
TEST_F(AnalyzeCli, AFailedRunsFolderIsAnalysedAsFarAsItsSeriesGoes) {
  const fs::path dir = copy_of_run("analyze_failed");
  const json finished = json::parse(read_text(dir / "summary.json"));
  fs::remove(dir / "summary.json");
  const auto r = run_settle("analyze", dir.string() + " --json");
  ASSERT_EQ(r.status, 0) << r.err;
  EXPECT_NE(r.err.find("summary.json: missing: the run did not finish"), std::string::npos) << r.err;
  EXPECT_FALSE(fs::exists(dir / "summary.json"));
  const json fields = json::parse(r.out);
  EXPECT_EQ(fields["late_mean_vertical_velocity"], finished["late_mean_vertical_velocity"]);
  EXPECT_EQ(fields["terminal_state"]["reached"], finished["terminal_state"]["reached"]);
  const auto report = run_settle("analyze", dir.string());
  ASSERT_EQ(report.status, 0) << report.err;
  EXPECT_NE(report.out.find("  result           "), std::string::npos) << report.out;
  fs::remove_all(dir);
}

// Runs `settle analyze` on a broken copy and checks the refusal and that nothing was written.
void expect_refused(const fs::path& dir, const std::string& arguments, const std::string& named) {
  const std::string summary_before = fs::exists(dir / "summary.json") ? read_text(dir / "summary.json") : "";
  const auto r = run_settle("analyze", arguments);
  EXPECT_EQ(r.status, 2) << r.err;
  EXPECT_NE(r.err.find(named), std::string::npos) << r.err;
  if (fs::exists(dir / "summary.json")) {
    EXPECT_EQ(read_text(dir / "summary.json"), summary_before);
  }
}

TEST_F(AnalyzeCli, BrokenRunDirectoriesAreRefusedNamingTheCulprit) {
  expect_refused(scratch("no_such_dir"), scratch("no_such_dir").string(), "no_such_dir: not a directory");

  const fs::path no_csv = copy_of_run("analyze_no_csv");
  fs::remove(no_csv / "timeseries.csv");
  expect_refused(no_csv, no_csv.string(), "timeseries.csv: missing");

  const fs::path no_uz = copy_of_run("analyze_no_uz");
  write_text(no_uz / "timeseries.csv", replaced(read_text(no_uz / "timeseries.csv"), ",uz,", ",vz,"));
  expect_refused(no_uz, no_uz.string(), "missing column 'uz'");

  const fs::path bad_json = copy_of_run("analyze_bad_json");
  write_text(bad_json / "summary.json", "{\"steps\": 3,");
  expect_refused(bad_json, bad_json.string(), "summary.json: not valid JSON");

  const fs::path towed = copy_of_run("analyze_towed");
  write_text(towed / "case.resolved.toml", replaced(read_text(towed / "case.resolved.toml"), "motion = \"free\"",
                                                    "motion = \"towed\"\ntowing_velocity = [0.0, 0.0, -0.01]"));
  expect_refused(towed, towed.string(), "particle.motion");

  expect_refused(no_uz, no_uz.string() + " --tolerance 2", "--tolerance: must be in (0, 1)");
  expect_refused(no_uz, no_uz.string() + " --window abc", "--window: expected a finite number");
  for (const auto& dir : {no_csv, no_uz, bad_json, towed}) fs::remove_all(dir);
}

}  // namespace test_analyze_cli
