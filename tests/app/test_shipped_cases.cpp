// Case tests of the shipped cases (cases/*.toml, docs/cases.md): every case file loads, passes
// the preflight checks at its own default resolution and runs five coupled steps through the real
// binary (SETTLE_BINARY); the STL grain (cases/grain.stl) is watertight and `settle shape` reads
// back the figures its generator (scripts/make_grain_stl.py) computed independently.
//
// The full runs are far too long for CI (minutes each); docs/cases.md gives their measured wall
// times and results, and scripts/validate_tencate.sh runs the ten Cate comparison.
#include <algorithm>
#include <cmath>
#include <filesystem>
#include <fstream>
#include <numbers>
#include <sstream>
#include <string>
#include <vector>

#include <fmt/format.h>
#include <gtest/gtest.h>
#include <toml++/toml.h>
#include <nlohmann/json.hpp>

#include "cli_support.hpp"

namespace test_shipped_cases {

namespace fs = std::filesystem;

using settle::test::column;
using settle::test::read_rows;
using settle::test::read_text;
using settle::test::scratch;

fs::path cases_dir() { return fs::path(SETTLE_SOURCE_DIR) / "cases"; }

// The cases docs/cases.md describes (ten Cate E1-E4, the non-spherical set, the STL grain); the
// test below runs every *.toml in cases/, these must be among them.
const std::vector<std::string> kDocumentedCases = {
    "tencate_E1",  "tencate_E2", "tencate_E3", "tencate_E4", "prolate_spheroid", "oblate_spheroid", "disk",
    "disk_zigzag", "cylinder",   "cube",       "grain"};

std::vector<std::string> shipped_case_names() {
  std::vector<std::string> names;
  for (const auto& entry : fs::directory_iterator(cases_dir()))
    if (entry.path().extension() == ".toml") names.push_back(entry.path().stem().string());
  std::sort(names.begin(), names.end());
  return names;
}

nlohmann::json read_summary(const fs::path& dir) { return nlohmann::json::parse(read_text(dir / "summary.json")); }

class ShippedCase : public ::testing::TestWithParam<std::string> {};

TEST(ShippedCases, TheDocumentedCasesAndTheGrainMeshAreShipped) {
  const std::vector<std::string> names = shipped_case_names();
  for (const std::string& name : kDocumentedCases)
    EXPECT_NE(std::find(names.begin(), names.end(), name), names.end()) << "cases/" << name << ".toml is missing";
  EXPECT_TRUE(fs::exists(cases_dir() / "grain.stl"));
}

// A case that holds its body until particle.release_time brings it to speed over some hundreds of
// steps (particle.hold_ramp_time), which five steps cannot do gently; here it starts free from rest
// instead, as the other free bodies do (its time step then follows from its estimated terminal
// speed), and the bound below holds for it too. tests/coupling/test_release.cpp tests the hold and
// its ramp.
const std::string kFreeFromRest =
    " --set particle.release_time=0 --set particle.hold_ramp_time=0 --set 'particle.velocity=[0, 0, 0]'";

// One step to learn the case's own dt (and to check that its default configuration passes the
// preflight: grid, clearance of the walls, memory), then five steps with a row per step.
TEST_P(ShippedCase, RunsFiveStepsAtItsDefaultResolution) {
  const std::string name = GetParam();
  const std::string file = (cases_dir() / (name + ".toml")).string();
  const fs::path probe = scratch(name + "_probe"), dir = scratch(name);
  const bool held = toml::parse_file(file)["particle"]["release_time"].value_or(0.0) > 0.0;
  const std::string start = held ? kFreeFromRest : "";

  const auto first =
      settle::test::run_settle("run", file + " -o " + probe.string() + " --set run.end_time=1e-12 --threads 2" + start);
  ASSERT_EQ(first.status, 0) << first.err;
  const double dt = read_summary(probe).at("dt").get<double>();
  fs::remove_all(probe);
  ASSERT_GT(dt, 0.0);

  // 4.5 dt: the run takes the steps needed to reach the end time, 5 (coupling/time_control.hpp).
  const auto run = settle::test::run_settle(
      "run", file + " -o " + dir.string() +
                 fmt::format(" --set run.end_time={:.17g} --set run.output_interval=0 --threads 2", 4.5 * dt) + start);
  ASSERT_EQ(run.status, 0) << run.err;
  ASSERT_TRUE(fs::exists(dir / "timeseries.csv"));
  ASSERT_TRUE(fs::exists(dir / "summary.json"));
  ASSERT_TRUE(fs::exists(dir / "case.resolved.toml"));

  const nlohmann::json summary = read_summary(dir);
  EXPECT_EQ(summary.at("steps").get<long>(), 5);
  EXPECT_EQ(summary.at("stop_reason").get<std::string>(), "end_time");
  EXPECT_DOUBLE_EQ(summary.at("dt").get<double>(), dt);  // the same case gives the same dt

  std::vector<std::string> header;
  const auto rows = read_rows(dir / "timeseries.csv", header);
  ASSERT_EQ(rows.size(), 6u);  // t = 0 and one row per step (output_interval = 0)
  for (const auto& row : rows) {
    ASSERT_EQ(row.size(), header.size());
    for (const double value : row) ASSERT_TRUE(std::isfinite(value)) << name;
  }

  const toml::table resolved = toml::parse_file((dir / "case.resolved.toml").string());
  if (resolved["particle"]["motion"].value_or(std::string()) == "free") {
    // Every free shipped particle is denser than its fluid and starts from rest. Newton's law gives
    // a bound that holds whatever the fluid does: the fluid's force on a body accelerating from
    // rest opposes the motion (added mass, history and drag all resist it), so after t its sinking
    // speed lies between 0 and that of the buoyant body alone, (1 - rho_f / rho_p) g t. An
    // unstable coupling (the near-neutral ten Cate E1 has rho_p / rho_f = 1.15) breaks it.
    const double rho_p = resolved["particle"]["density"].value_or(0.0);
    const double rho_f = resolved["fluid"]["density"].value_or(0.0);
    const double g = -resolved["fluid"]["gravity"][2].value_or(0.0);
    const auto& last = rows.back();
    const double t = last[column(header, "t")];
    const double sinking = -last[column(header, "uz")];
    EXPECT_GT(sinking, 0.0) << name;
    EXPECT_LT(sinking, (1.0 - rho_f / rho_p) * g * t) << name;
  }
  fs::remove_all(dir);
}

INSTANTIATE_TEST_SUITE_P(Cases, ShippedCase, ::testing::ValuesIn(shipped_case_names()),
                         [](const ::testing::TestParamInfo<std::string>& case_info) { return case_info.param; });

// Figures printed by `python3 scripts/make_grain_stl.py` for the file it wrote: computed with numpy
// from the float32 vertices in the file (divergence theorem), independently of settle's mesh code.
constexpr double kGrainVolume = 0.523598774;
constexpr double kGrainArea = 3.505657368;
constexpr double kGrainMoments[3] = {4.067273004e-02, 6.673530275e-02, 7.998680246e-02};  // unit density
constexpr double kGrainWidths[3] = {1.435482621, 1.061005026, 0.759553790};               // along the file axes

TEST(ShippedGrain, ShapeReadsTheMeshBackWithTheGeneratorsFigures) {
  const auto r = settle::test::run_settle("shape", "--mesh " + (cases_dir() / "grain.stl").string());
  // Exit 0: the reader refuses open, non-manifold or inconsistently oriented meshes (exit 2).
  ASSERT_EQ(r.status, 0) << r.err;
  const nlohmann::json shape = nlohmann::json::parse(r.out);
  // No notes: one outward shell (an inward mesh would be reversed, several shells noted).
  EXPECT_TRUE(shape.at("notes").empty()) << shape.at("notes").dump();

  // The generator prints 9-10 significant digits; both sides work in double from the same float32
  // vertices, so they agree to the printed rounding (half a unit of the last digit).
  EXPECT_NEAR(shape.at("volume").get<double>(), kGrainVolume, 5e-10);
  EXPECT_NEAR(shape.at("surface_area").get<double>(), kGrainArea, 5e-10);
  for (int i = 0; i < 3; ++i) EXPECT_NEAR(shape.at("principal_moments")[i].get<double>(), kGrainMoments[i], 5e-12) << i;
  // The generator scaled the grain to d_eq = 1; float32 vertices move the volume by ~1e-8.
  EXPECT_NEAR(shape.at("equivalent_diameter").get<double>(), 1.0, 1e-8);

  // The generator turned the principal axes onto the file axes, so settle's principal extents are
  // the widths along x, y, z, up to the axes' misalignment left by float32 rounding (~1e-8 rad,
  // times the size: 1e-7 covers it).
  for (int i = 0; i < 3; ++i) EXPECT_NEAR(shape.at("principal_extents")[i].get<double>(), kGrainWidths[i], 1e-7) << i;
  const double L = kGrainWidths[0], I = kGrainWidths[1], S = kGrainWidths[2];
  // Shape factors from those extents and the area (definitions in docs/shapes.md), to the same 1e-7.
  EXPECT_NEAR(shape.at("elongation").get<double>(), I / L, 1e-7);
  EXPECT_NEAR(shape.at("flatness").get<double>(), S / I, 1e-7);
  EXPECT_NEAR(shape.at("corey_shape_factor").get<double>(), S / std::sqrt(L * I), 1e-7);
  // Wadell: pi d_eq^2 / A with d_eq = (6 V / pi)^(1/3); the printed V and A carry 1e-9 each.
  const double d_eq = std::cbrt(6.0 * kGrainVolume / std::numbers::pi);
  EXPECT_NEAR(shape.at("sphericity").get<double>(), std::numbers::pi * d_eq * d_eq / kGrainArea, 2e-9);

  // A grain, not a sphere: Wadell's sphericity is below 1 (the isoperimetric inequality), and the
  // Corey factor lies in the range of Dietrich's 1982 fit for natural sediment (>= 0.2).
  EXPECT_LT(shape.at("sphericity").get<double>(), 1.0);
  EXPECT_GT(shape.at("corey_shape_factor").get<double>(), 0.2);
}

TEST(ShippedGrain, TheCaseScalesTheMeshToHalfAMillimetre) {
  // The case names the mesh relative to itself and scales it by 5e-4 m per file unit.
  const auto r = settle::test::run_settle("shape", (cases_dir() / "grain.toml").string());
  ASSERT_EQ(r.status, 0) << r.err;
  const nlohmann::json shape = nlohmann::json::parse(r.out);
  // d_eq = 1 file unit (to 1e-8, above) times the scale.
  EXPECT_NEAR(shape.at("equivalent_diameter").get<double>(), 5.0e-4, 5.0e-4 * 1e-8);
  // Mass with the case's density: rho V = 2650 (pi / 6) (5e-4)^3, to the same relative 3e-8 (V ~ d^3).
  const double mass = 2650.0 * std::numbers::pi / 6.0 * std::pow(5.0e-4, 3);
  EXPECT_NEAR(shape.at("mass").get<double>(), mass, mass * 3e-8);
}

}  // namespace test_shipped_cases
