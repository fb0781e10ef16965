// The CI-sized free-settling case: the real binary, a sphere released from rest, run to
// the terminal state it detects itself; physical behaviour checked against the standard drag
// curve and the symmetry of the start. And the same time series with one and with two threads.
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

namespace test_free_settling_cli {

namespace fs = std::filesystem;

using settle::test::read_text;
using settle::test::scratch;
using settle::test::write_scratch_case;

// A glass-like sphere (rho_p/rho_f = 2) of 1 mm in a liquid four times as viscous as water:
// Re ~ 16, Ga ~ 25, steady and axisymmetric (a sphere's wake stays axisymmetric below Re ~ 210).
// 8 cells per diameter; free-slip side walls 8 d apart and a window following the sphere with
// 5 d of liquid ahead.
const char* kSphereCase = R"toml(
[fluid]
density = 1000.0
dynamic_viscosity = 4.0e-3
gravity = [0.0, 0.0, -9.81]
[particle]
shape = "sphere"
diameter = 1.0e-3
density = 2000.0
position = [4.0e-3, 4.0e-3, 6.0e-3]
[domain]
size = [8.0e-3, 8.0e-3, 16.0e-3]
walls = { x = "free-slip", y = "free-slip", z = "no-slip" }
follow_particle = true
[numerics]
cells_per_diameter = 8
[run]
end_time = 3.0
stop_at_terminal = true
output_interval = 0.002
)toml";

struct Row {
  double t, ux, uy, uz, wx, wy, wz;
};

std::vector<Row> read_rows(const fs::path& csv_path) {
  std::ifstream csv(csv_path);
  std::string line;
  std::getline(csv, line);  // header: t,x,y,z,ux,uy,uz,wx,wy,wz,...
  std::vector<Row> rows;
  while (std::getline(csv, line)) {
    std::stringstream fields(line);
    std::vector<double> v;
    for (std::string cell; std::getline(fields, cell, ',') && v.size() < 10;) v.push_back(std::stod(cell));
    rows.push_back({v[0], v[4], v[5], v[6], v[7], v[8], v[9]});
  }
  return rows;
}

TEST(FreeSettling, SphereReachesTheStandardDragCurveAndStaysSymmetric) {
  const fs::path dir = scratch("free_sphere");
  const fs::path case_path = write_scratch_case("free_sphere", kSphereCase);
  // One thread: CTest runs two tests at a time on CI's two cores (thread invariance is the next test's).
  const auto r = settle::test::run_settle("run", case_path.string() + " -o " + dir.string() + " --threads 1 --quiet");
  fs::remove(case_path);
  ASSERT_EQ(r.status, 0) << r.err;
  const auto summary = nlohmann::json::parse(read_text(dir / "summary.json"));
  ASSERT_EQ(summary["stop_reason"], "terminal_state");

  // The terminal velocity against the standard drag curve of Clift, Grace and Weber (1978) as
  // `settle predict` solves it for this sphere (summary.json carries its ratio to the run). The
  // CI criterion is 10%. Expected deviation: the drag error of 8 cells per diameter
  // (towed sphere, Re = 20: C_D +6.9% at 8 cells, docs/validation.md, i.e. about -3.4% in U) and
  // the confinement of the 8 d box (a few %); measured -4.5% (and -7.1% from Schiller-Naumann).
  double clift_ratio = 0.0;
  for (const auto& law : summary["correlations"])
    if (law["law"] == "clift_grace_weber") clift_ratio = law["ratio_to_run"].get<double>();
  ASSERT_GT(clift_ratio, 0.0);
  EXPECT_NEAR(1.0 / clift_ratio, 1.0, 0.10);

  // A sphere released from rest on the axis of a symmetric box, below the wake's first
  // instability (Re ~ 210): the flow is axisymmetric, so no rotation and no sideways motion beyond
  // what the discretisation's own asymmetry gives (the Fibonacci marker set has no mirror plane):
  // measured 4.8e-4 U/d and 1.7e-4 U (4.9e-4 and 1.7e-4 with double storage). The bound of 5e-3 is ten times that and still an order of
  // magnitude below a real loss of symmetry (the oblique regime past Ga = 155 drifts at several
  // percent of U: Uhlmann and Dusek 2014), so a torque or lateral force of the wrong sign or size
  // in the coupling would show.
  const double u = summary["terminal_vertical_velocity"].get<double>();
  const double d = summary["equivalent_diameter"].get<double>();
  double largest_rotation = 0.0, largest_lateral = 0.0;
  for (const Row& row : read_rows(dir / "timeseries.csv")) {
    largest_rotation = std::max(largest_rotation, std::hypot(row.wx, row.wy, row.wz) * d / u);
    largest_lateral = std::max(largest_lateral, std::hypot(row.ux, row.uy) / u);
  }
  EXPECT_LT(largest_rotation, 5e-3);
  EXPECT_LT(largest_lateral, 5e-3);
  fs::remove_all(dir);
}

// The coupled step's sums run serially in a fixed order and the fluid kernel updates every cell
// independently of how the cells are shared among threads: one and two threads must write the
// same bytes (no tolerance: a difference means an order-dependent reduction crept in).
TEST(FreeSettling, OneAndTwoThreadsWriteTheSameTimeSeries) {
  const fs::path one = scratch("threads_one"), two = scratch("threads_two");
  const std::string common =
      " --set numerics.cells_per_diameter=6 --set run.end_time=0.02 --set run.output_interval=0 --quiet";
  const auto first = settle::test::run_settle("run", "-o " + one.string() + common + " --threads 1");
  ASSERT_EQ(first.status, 0) << first.err;
  const auto second = settle::test::run_settle("run", "-o " + two.string() + common + " --threads 2");
  ASSERT_EQ(second.status, 0) << second.err;
  const std::string series = read_text(one / "timeseries.csv");
  EXPECT_GT(std::count(series.begin(), series.end(), '\n'), 50);  // every step of 0.02 s
  EXPECT_EQ(series, read_text(two / "timeseries.csv"));
  fs::remove_all(one);
  fs::remove_all(two);
}

}  // namespace test_free_settling_cli
