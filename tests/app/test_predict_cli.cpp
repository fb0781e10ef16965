// Case tests of `settle predict`: the real binary (SETTLE_BINARY) on flags and case files,
// checked against the Stokes closed form, the force balance, closed-form shadows, the JSON
// contract (law, terminal_velocity, reynolds, drag_coefficient, in_range for each law) and its
// handling of bad input (exit status 2 and a message naming the flag or key).
#include <cmath>
#include <filesystem>
#include <fstream>
#include <numbers>
#include <ostream>
#include <string>

#include <gtest/gtest.h>
#include <nlohmann/json.hpp>

#include "cli_support.hpp"

namespace test_predict_cli {

namespace fs = std::filesystem;
using nlohmann::json;
using settle::test::scratch;
using std::numbers::pi;

struct Result : settle::test::CliResult {
  json parsed() const { return json::parse(out); }
};

Result run_predict(const std::string& arguments) { return {settle::test::run_settle("predict", arguments)}; }

const char* const kLaws[] = {"schiller_naumann",  "clift_grace_weber", "haider_levenspiel", "ganser",
                             "holzer_sommerfeld", "bagheri_bonadonna", "dietrich"};

const json& law(const json& list, const std::string& name) {
  for (const json& entry : list) {
    if (entry["law"] == name) return entry;
  }
  throw std::runtime_error("no law " + name);
}

double descriptor(const json& entry, const char* name) { return entry["descriptors"][name].get<double>(); }

TEST(PredictCli, JsonListHasEveryLawWithTheContractKeys) {
  const Result r = run_predict(
      "--shape spheroid --diameter 1e-3 --aspect-ratio 2.5 --density 1050 "
      "--fluid-density 998.2 --viscosity 1e-3 --json");
  ASSERT_EQ(r.status, 0) << r.err;
  const json list = r.parsed();
  ASSERT_TRUE(list.is_array());
  ASSERT_EQ(list.size(), std::size(kLaws));
  for (std::size_t i = 0; i < list.size(); ++i) {
    EXPECT_EQ(list[i]["law"], kLaws[i]);
    for (const char* key : {"terminal_velocity", "reynolds", "drag_coefficient", "in_range", "range", "reason"}) {
      EXPECT_TRUE(list[i].contains(key)) << kLaws[i] << " " << key;
    }
    EXPECT_TRUE(list[i]["in_range"].is_boolean());
  }
  // Sphere laws on a spheroid of sphericity 0.885: flagged, with the reason.
  EXPECT_FALSE(law(list, "schiller_naumann")["in_range"].get<bool>());
  EXPECT_NE(law(list, "schiller_naumann")["reason"].get<std::string>().find("sphericity"), std::string::npos);
  EXPECT_TRUE(law(list, "haider_levenspiel")["in_range"].get<bool>());
}

TEST(PredictCli, SmallSphereMeetsStokesAndTheForceBalance) {
  // d = 2 um glass bead in water: U_s = (rho_p - rho_f) g d^2 / (18 mu) = 3.6e-6 m/s, Re = 7e-6.
  // The largest first correction among the C_D laws is Hoelzer-Sommerfeld's 3 sqrt(Re)/24 =
  // 3.3e-4, so U/U_s = 1/(1 + delta) lies within 5e-4 of 1. Dietrich's fit starts at D* = 0.05
  // (here D* = 1.3e-4) and is only required to say so.
  const double d = 2e-6, rho_p = 2650.0, rho_f = 998.2, mu = 1e-3, g = 9.81;
  const Result r =
      run_predict("--shape sphere --diameter 2e-6 --density 2650 --fluid-density 998.2 --viscosity 1e-3 --json");
  ASSERT_EQ(r.status, 0) << r.err;
  const double stokes = (rho_p - rho_f) * g * d * d / (18.0 * mu);
  const double archimedes = (rho_p - rho_f) * g * d * d * d * rho_f / (mu * mu);
  for (const json& entry : r.parsed()) {
    const std::string name = entry["law"];
    const double u = entry["terminal_velocity"].get<double>(), re = entry["reynolds"].get<double>();
    const double cd = entry["drag_coefficient"].get<double>();
    // Printed with 17 digits, the numbers round-trip exactly; the solver balances to ~1e-15.
    EXPECT_NEAR(cd * re * re / (4.0 / 3.0 * archimedes), 1.0, 1e-12) << name;
    EXPECT_NEAR(re, rho_f * u * d / mu, 1e-12 * re) << name;
    if (name == "dietrich") {
      EXPECT_FALSE(entry["in_range"].get<bool>());
      continue;
    }
    EXPECT_NEAR(u / stokes, 1.0, 5e-4) << name;
  }
}

TEST(PredictCli, TableListsEveryLaw) {
  const Result r = run_predict(
      "--shape cylinder --diameter 2e-3 --length 0.5e-3 --density 2500 --fluid-density 998.2 "
      "--viscosity 1e-3");
  ASSERT_EQ(r.status, 0) << r.err;
  EXPECT_NE(r.out.find("U (m/s)"), std::string::npos);
  EXPECT_NE(r.out.find("in range"), std::string::npos);
  for (const char* name : kLaws) EXPECT_NE(r.out.find(std::string("\n") + name + " "), std::string::npos) << name;
  // A disk falls broadside along its axis: the table says so.
  EXPECT_NE(r.out.find("orientation broadside (fall along body (0.000, 0.000, 1.000))"), std::string::npos) << r.out;
}

TEST(PredictCli, CaseFileUsesItsFluidParticleAndInitialAttitude) {
  const fs::path dir = scratch("predict_case");
  fs::create_directories(dir);
  // No [domain]: the case need not be runnable for a prediction.
  std::ofstream(dir / "case.toml") << "[fluid]\ndensity = 998.2\ndynamic_viscosity = 1.0e-3\n\n"
                                      "[particle]\nshape = \"spheroid\"\ndiameter = 1.0e-3\naspect_ratio = 2.5\n"
                                      "density = 1050.0\neuler = [0.0, 0.5, 0.0]\n";
  const Result from_case = run_predict((dir / "case.toml").string() + " --orientation initial --json");
  const Result from_flags = run_predict(
      "--shape spheroid --diameter 1e-3 --aspect-ratio 2.5 --density 1050 "
      "--fluid-density 998.2 --viscosity 1e-3 --orientation initial --euler 0,0.5,0 --json");
  fs::remove_all(dir);
  ASSERT_EQ(from_case.status, 0) << from_case.err;
  ASSERT_EQ(from_flags.status, 0) << from_flags.err;
  EXPECT_EQ(from_case.parsed(), from_flags.parsed());
  // Gravity meets the symmetry axis at 0.5 rad: the shadow is pi a sqrt(a^2 cos^2 + c^2 sin^2)
  // (a = 0.5 mm, c = 1.25 mm), and Ganser's d_n / d_v = sqrt(shadow / (pi d_v^2 / 4)).
  const double a = 0.5e-3, c = 1.25e-3;
  const double shadow = pi * a * std::sqrt(a * a * std::pow(std::cos(0.5), 2) + c * c * std::pow(std::sin(0.5), 2));
  const double section = pi / 4 * std::pow(2.5e-9, 2.0 / 3.0);
  const json ganser = law(from_case.parsed(), "ganser");
  EXPECT_NEAR(descriptor(ganser, "projected_to_volume_diameter"), std::sqrt(shadow / section), 1e-12);
  EXPECT_EQ(ganser["orientation"], "initial");
}

struct BadInput {
  const char* label;
  std::string arguments;  // after "settle predict"; CASE stands for a case file with `toml` inside
  std::string toml;
  const char* message;
};

void PrintTo(const BadInput& b, std::ostream* os) { *os << b.label; }

class PredictCliRefusal : public ::testing::TestWithParam<BadInput> {};

TEST_P(PredictCliRefusal, ExitsWithStatus2AndNamesTheProblem) {
  std::string arguments = GetParam().arguments;
  const fs::path case_file = scratch(std::string(GetParam().label) + ".toml");
  if (!GetParam().toml.empty()) {
    std::ofstream(case_file) << GetParam().toml;
    arguments.replace(arguments.find("CASE"), 4, case_file.string());
  }
  const Result r = run_predict(arguments);
  fs::remove(case_file);
  EXPECT_EQ(r.status, 2) << r.err;
  EXPECT_NE(r.err.find(GetParam().message), std::string::npos) << r.err;
  EXPECT_TRUE(r.out.empty());
}

const std::string kWater = " --fluid-density 998.2 --viscosity 1e-3";
const std::string kSphere = "--shape sphere --diameter 1e-3 ";
const std::string kCaseSphere = "[particle]\nshape = \"sphere\"\ndiameter = 1.0e-3\n";

INSTANTIATE_TEST_SUITE_P(
    Inputs, PredictCliRefusal,
    ::testing::Values(
        BadInput{"no_density", kSphere + kWater, "", "--density: required without a case file"},
        BadInput{"no_viscosity", kSphere + "--density 2650 --fluid-density 998.2", "",
                 "--viscosity: required without a case file"},
        BadInput{"negative_diameter", "--shape sphere --diameter -1 --density 2650" + kWater, "",
                 "--diameter: must be finite and > 0, got -1"},
        BadInput{"tiny_sphere", "--shape sphere --diameter 1e-200 --density 2500" + kWater, "",
                 "--diameter: 1e-200 m is too small"},
        BadInput{"zero_gravity", kSphere + "--density 2650 --gravity 0" + kWater, "", "--gravity: must be > 0, got 0"},
        BadInput{"neutral", kSphere + "--density 998.2" + kWater, "", "--density: must differ from --fluid-density"},
        BadInput{"orientation", kSphere + "--density 2650 --orientation sideways" + kWater, "",
                 "--orientation: expected broadside, initial or mean, got 'sideways'"},
        BadInput{"roundness", kSphere + "--density 2650 --powers-roundness 7" + kWater, "",
                 "--powers-roundness: must be in [0, 6], got 7"},
        BadInput{"euler_without_initial", kSphere + "--density 2650 --euler 0,1,0" + kWater, "",
                 "--euler: only used with --orientation initial"},
        BadInput{"short_euler", kSphere + "--density 2650 --orientation initial --euler 0,1" + kWater, "",
                 "--euler: expected 3 comma-separated numbers"},
        BadInput{"flags_and_case", "CASE --density 2000", kCaseSphere,
                 "--density: cannot be combined with a case file"},
        BadInput{"case_neutral", "CASE", "[fluid]\ndensity = 1000.0\n\n" + kCaseSphere + "density = 1000.0\n",
                 "particle.density: must differ from fluid.density"},
        BadInput{"case_no_gravity", "CASE",
                 "[fluid]\ngravity = [0.0, 0.0, 0.0]\n\n" + kCaseSphere + "density = 2500.0\n",
                 "fluid.gravity: must be non-zero"},
        BadInput{"case_unknown_key", "CASE", kCaseSphere + "colour = \"red\"\n", "unknown key [particle] colour"},
        BadInput{"case_bad_shape", "CASE", "[particle]\nshape = \"spheroid\"\ndiameter = 1.0e-3\naspect_ratio = 0.0\n",
                 "[particle] aspect_ratio = 0.0: must be in"}),
    [](const auto& param_info) { return std::string(param_info.param.label); });

TEST(PredictCli, HelpDescribesTheFlags) {
  const Result r = run_predict("--help");
  EXPECT_EQ(r.status, 0);
  for (const char* flag : {"--shape", "--diameter", "--density", "--fluid-density", "--viscosity", "--gravity",
                           "--orientation", "--euler", "--powers-roundness", "--json"}) {
    EXPECT_NE(r.out.find(flag), std::string::npos) << flag;
  }
}

}  // namespace test_predict_cli
