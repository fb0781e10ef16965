// Case tests of fluid presets through the real binary: `settle run` with the preset chosen by --set
// writes the preset and the values it used to case.resolved.toml and runs with them (summary.json),
// and `settle predict` on a case with the preset sees the same fluid.
#include <cmath>
#include <filesystem>
#include <fstream>
#include <string>

#include <fmt/format.h>
#include <gtest/gtest.h>
#include <nlohmann/json.hpp>

#include "cli_support.hpp"
#include "io/case_schema.hpp"
#include "io/fluid_presets.hpp"
#include "io/schema.hpp"

namespace test_fluid_preset_cli {

namespace fs = std::filesystem;

using settle::test::read_text;
using settle::test::run_settle;
using settle::test::scratch;

// A 1 mm sphere, 10 % denser than water, in a 6 x 6 x 12 d window that follows it, 6 cells per
// diameter: a few steps take well under a second. No fluid density or viscosity: the preset sets them.
constexpr const char* kTinyCase = R"toml([fluid]
gravity = [0.0, 0.0, -9.81]
{}
[particle]
shape = "sphere"
diameter = 1.0e-3
density = 1100.0
position = [3.0e-3, 3.0e-3, 6.0e-3]

[domain]
size = [6.0e-3, 6.0e-3, 12.0e-3]
follow_particle = true

[numerics]
cells_per_diameter = 6

[run]
end_time = 2.0e-3
output_interval = 1.0e-3
)toml";

fs::path write_case(const std::string& name, const std::string& fluid_lines) {
  const fs::path path = scratch(name);
  std::ofstream(path) << fmt::format(kTinyCase, fluid_lines);
  return path;
}

TEST(FluidPresetCli, RunWithWaterAt40CUsesAndRecordsThePresetsValues) {
  const fs::path case_path = write_case("preset_case.toml", "");
  const fs::path dir = scratch("preset_run");
  const auto r = run_settle("run", case_path.string() + " -o " + dir.string() +
                                       " --set 'fluid.preset=\"water\"' --set fluid.temperature=40 --threads 1");
  ASSERT_EQ(r.status, 0) << r.err;
  const settle::io::FluidProperties water = settle::io::water_properties(40.0);

  // The resolved case names the preset and its temperature, and holds the values used at full
  // precision (they read back bit for bit).
  const std::string resolved = read_text(dir / "case.resolved.toml");
  const settle::io::CaseValues v = settle::io::parse_case(settle::io::case_schema(), resolved, "case.resolved.toml");
  EXPECT_EQ(v.string("fluid.preset"), "water");
  EXPECT_EQ(v.real("fluid.temperature"), 40.0);
  EXPECT_EQ(v.real("fluid.density"), water.density_si);
  EXPECT_EQ(v.real("fluid.dynamic_viscosity"), water.dynamic_viscosity_si);
  EXPECT_EQ(resolved.find("density = 998.2"), std::string::npos) << resolved;

  // The run used them: Ga = sqrt(|rho_p / rho_f - 1| g d^3) / nu with nu = mu / rho_f of the
  // preset (1e-12: the same closed form evaluated twice, rounding only). The 20 C defaults
  // would give Ga = 31.6 instead of 49.6.
  const auto summary = nlohmann::json::parse(read_text(dir / "summary.json"));
  const double nu = water.dynamic_viscosity_si / water.density_si;
  const double galileo = std::sqrt(std::abs(1100.0 / water.density_si - 1.0) * 9.81 * 1e-9) / nu;
  EXPECT_NEAR(summary["galileo"].get<double>() / galileo, 1.0, 1e-12);
  EXPECT_GT(summary["steps"].get<long>(), 0);
  // No explicit fluid value replaced the preset's, so nothing to warn about.
  for (const auto& w : summary["warnings"]) EXPECT_EQ(w.get<std::string>().find("fluid."), std::string::npos) << w;
  fs::remove_all(dir);
  fs::remove(case_path);
}

TEST(FluidPresetCli, PredictSeesThePresetsFluid) {
  const fs::path case_path = write_case(
      "preset_predict.toml", "preset = \"glycerol-water\"\ntemperature = 20.0\nglycerol_mass_fraction = 0.5");
  const auto r = run_settle("predict", case_path.string());
  ASSERT_EQ(r.status, 0) << r.err;
  // predict prints rho_f with 6 and mu with 4 significant digits.
  const settle::io::FluidProperties mix = settle::io::glycerol_water_properties(0.5, 20.0);
  const std::string fluid =
      fmt::format("fluid rho_f = {:.6g} kg/m^3, mu = {:.4g} Pa s", mix.density_si, mix.dynamic_viscosity_si);
  EXPECT_NE(r.out.find(fluid), std::string::npos) << fluid << "\n" << r.out;
  fs::remove(case_path);
}

TEST(FluidPresetCli, TemperatureWithoutAPresetExitsTwoNamingTheKey) {
  const fs::path case_path = write_case("preset_refused.toml", "temperature = 20.0");
  const auto r = run_settle("run", case_path.string() + " -o " + scratch("preset_refused_run").string());
  EXPECT_EQ(r.status, 2);
  EXPECT_NE(r.err.find("fluid.temperature"), std::string::npos) << r.err;
  EXPECT_FALSE(fs::exists(scratch("preset_refused_run")));
  fs::remove(case_path);
}

}  // namespace test_fluid_preset_cli
