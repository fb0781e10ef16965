// Golden numbers of the shipped cases: each case in cases/ runs five coupled steps through the
// real binary (SETTLE_BINARY) on a coarse grid, and the time step, the relaxation time, the body's
// state and the hydrodynamic force after those steps must equal the values stored in
// tests/data/golden_cases.json. A change that moves results, by design or by accident, fails here;
// when the change is meant, regenerate the file as its "about" entry says and review the diff.
//
// Why these tolerances. The release (GCC) and sanitizer (clang) builds compile the same code for
// baseline x86-64 without -ffast-math and without FMA instructions, so both keep the order of every
// floating-point operation, and the coupled step is bit for bit independent of the thread count
// (every parallel loop writes disjoint cells, docs/coupling.md); the stored values are therefore
// reproduced exactly, and the tolerances only leave room for round-off that a legitimate change of
// the compiler or of libm could add.
#include <algorithm>
#include <filesystem>
#include <string>
#include <vector>

#include <fmt/format.h>
#include <gtest/gtest.h>
#include <Eigen/Core>
#include <nlohmann/json.hpp>

#include "cli_support.hpp"

namespace test_golden_cases {

namespace fs = std::filesystem;
using nlohmann::json;

// dt and tau follow from the case's numbers by a few dozen operations (and a bisection for the
// expected speed that ends at relative 1e-10, always after the same iterations): round-off of
// order 1e-15.
constexpr double kUnitsRelativeTolerance = 1e-12;
// Five coupled steps sum forces over markers and cells in a fixed order; a changed rounding of
// one operation moves them by about 1e-15 relative to the largest term of a sum, and the forces
// cancel to a few digits (marker forces against the fluid momentum inside the body), so 1e-9 of
// the vector's size leaves six orders of magnitude of margin while a change of the model, the
// coupling or the units moves these numbers by far more (1e-6 and above).
constexpr double kStateRelativeTolerance = 1e-9;

fs::path source_dir() { return fs::path(SETTLE_SOURCE_DIR); }

const json& golden() {
  static const json stored = json::parse(settle::test::read_text(source_dir() / "tests/data/golden_cases.json"));
  return stored;
}

std::vector<std::string> shipped_case_names() {
  std::vector<std::string> names;
  for (const auto& entry : fs::directory_iterator(source_dir() / "cases"))
    if (entry.path().extension() == ".toml") names.push_back(entry.path().stem().string());
  std::sort(names.begin(), names.end());
  return names;
}

Eigen::Vector3d vector_of(const json& values) {
  return {values.at(0).get<double>(), values.at(1).get<double>(), values.at(2).get<double>()};
}

// One row's three columns starting at `first` (e.g. "ux" for ux, uy, uz).
Eigen::Vector3d columns_of(const std::vector<double>& row, const std::vector<std::string>& header,
                           const std::string& first) {
  const std::size_t i = settle::test::column(header, first);
  return {row.at(i), row.at(i + 1), row.at(i + 2)};
}

// A vector is compared as a whole, |measured - expected| <= tolerance |expected|: a component
// that is zero by symmetry (the sideways velocity of a sphere falling straight) is then held to
// the size of the vector, not to its own round-off.
void expect_vector_near(const Eigen::Vector3d& measured, const Eigen::Vector3d& expected, const std::string& what) {
  EXPECT_LE((measured - expected).norm(), kStateRelativeTolerance * expected.norm())
      << what << ": measured " << measured.transpose() << ", stored " << expected.transpose();
}

class GoldenCase : public ::testing::TestWithParam<std::string> {};

TEST_P(GoldenCase, FiveStepsReproduceTheStoredNumbers) {
  const std::string name = GetParam();
  ASSERT_TRUE(golden().at("cases").contains(name))
      << "cases/" << name << ".toml has no golden numbers: add them with scripts/update_golden_cases.py";
  const json& expected = golden().at("cases").at(name);

  std::string arguments = (source_dir() / "cases" / (name + ".toml")).string();
  const fs::path dir = settle::test::scratch("golden_" + name);
  arguments += " -o " + dir.string() + " --threads 2 --quiet";
  // Quoted for the shell that runs the command: a TOML string keeps its double quotes.
  for (const auto& setting : golden().at("common_set")) arguments += " --set '" + setting.get<std::string>() + "'";
  for (const auto& setting : expected.at("set")) arguments += " --set '" + setting.get<std::string>() + "'";
  arguments += fmt::format(" --set run.end_time={:.17g}", expected.at("end_time").get<double>());
  const auto run = settle::test::run_settle("run", arguments);
  ASSERT_EQ(run.status, 0) << run.err;

  const json summary = json::parse(settle::test::read_text(dir / "summary.json"));
  const double dt = expected.at("dt").get<double>(), tau = expected.at("tau").get<double>();
  // A changed dt also changes the number of steps to the stored end time: it is checked first.
  ASSERT_NEAR(summary.at("dt").get<double>(), dt, kUnitsRelativeTolerance * dt);
  EXPECT_NEAR(summary.at("tau").get<double>(), tau, kUnitsRelativeTolerance * tau);
  ASSERT_EQ(summary.at("steps").get<long>(), expected.at("steps").get<long>());

  std::vector<std::string> header;
  const auto rows = settle::test::read_rows(dir / "timeseries.csv", header);
  ASSERT_GE(rows.size(), 2u);
  const auto& first = rows.front();
  const auto& last = rows.back();
  // The displacement since t = 0 rather than the position: its tolerance is then relative to how
  // far the body moved, not to where the case put it.
  expect_vector_near(columns_of(last, header, "x") - columns_of(first, header, "x"),
                     vector_of(expected.at("displacement")), name + " displacement (m)");
  expect_vector_near(columns_of(last, header, "ux"), vector_of(expected.at("velocity")), name + " velocity (m/s)");
  expect_vector_near(columns_of(last, header, "wx"), vector_of(expected.at("angular_velocity")),
                     name + " angular velocity (rad/s, inertial)");
  expect_vector_near(columns_of(last, header, "Fx"), vector_of(expected.at("force")), name + " hydrodynamic force (N)");
  fs::remove_all(dir);
}

INSTANTIATE_TEST_SUITE_P(Cases, GoldenCase, ::testing::ValuesIn(shipped_case_names()),
                         [](const ::testing::TestParamInfo<std::string>& case_info) { return case_info.param; });

}  // namespace test_golden_cases
