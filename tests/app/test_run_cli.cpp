// Case tests of `settle run`: the real binary (SETTLE_BINARY) on tiny cases; the output files
// of DESIGN.md section 3 (exact CSV header, summary keys, resolved case) and the refusal of bad
// input with exit status 2 and a message naming the key.
#include <sys/wait.h>
#include <unistd.h>

#include <cmath>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <sstream>
#include <string>
#include <vector>

#include <gtest/gtest.h>
#include <nlohmann/json.hpp>

#include "cli_support.hpp"

namespace {

namespace fs = std::filesystem;

using settle::test::read_text;
using settle::test::scratch;
using Result = settle::test::CliResult;

Result run_settle(const std::string& arguments) { return settle::test::run_settle("run", arguments); }

std::string case_file(const std::string& name) { return std::string(SETTLE_SOURCE_DIR) + "/cases/" + name; }

const char* kHeader =
    "t,x,y,z,ux,uy,uz,wx,wy,wz,wbx,wby,wbz,psi,theta,gamma,psi_r,theta_r,gamma_r,euler_set,Fx,Fy,Fz,Tx,Ty,Tz,Re";

void expect_run_directory(const fs::path& dir, bool coefficients) {
  ASSERT_TRUE(fs::exists(dir / "timeseries.csv"));
  ASSERT_TRUE(fs::exists(dir / "summary.json"));
  ASSERT_TRUE(fs::exists(dir / "case.resolved.toml"));
  std::ifstream csv(dir / "timeseries.csv");
  std::string header;
  std::getline(csv, header);
  // The DESIGN columns exactly and in order; extra columns may only follow.
  EXPECT_EQ(header.substr(0, std::string(kHeader).size()), kHeader);
  EXPECT_TRUE(header.size() == std::string(kHeader).size() || header[std::string(kHeader).size()] == ',');
  int rows = 0;
  for (std::string line; std::getline(csv, line);) ++rows;
  EXPECT_GE(rows, 2);  // t = 0 and the end at least

  const auto summary = nlohmann::json::parse(read_text(dir / "summary.json"));
  for (const char* key : {"terminal_velocity", "terminal_vertical_velocity", "reynolds", "drag_coefficient", "galileo",
                          "regime", "cells", "dx", "dt", "tau", "steps", "wall_seconds", "mlups", "timing"})
    EXPECT_TRUE(summary.contains(key)) << key;
  for (const char* step : {"body_predictor", "markers", "forcing", "fluid", "hydrodynamic_force", "body_corrector",
                           "moving_window"})
    EXPECT_TRUE(summary["timing"].contains(step)) << step;
  if (coefficients) {
    EXPECT_TRUE(summary.contains("lift_coefficient"));
    EXPECT_TRUE(summary.contains("torque_coefficient"));
  }
  EXPECT_GT(summary["steps"].get<long>(), 0);
  EXPECT_TRUE(std::isfinite(summary["drag_coefficient"].get<double>()));
  EXPECT_NE(read_text(dir / "case.resolved.toml").find("# [derived]"), std::string::npos);
}

TEST(RunCli, FixedSphereCaseWritesTheContractFiles) {
  const fs::path dir = scratch("fixed");
  const Result r = run_settle(case_file("periodic_sphere_array.toml") + " -o " + dir.string() +
                              " --set numerics.cells_per_diameter=8 --set run.end_time=0.05 --threads 1");
  ASSERT_EQ(r.status, 0) << r.err;
  expect_run_directory(dir, true);
  // The driven flow pushes the fixed sphere along +x: the drag is positive (a sign check of
  // the whole chain, body force -> fluid -> markers -> hydrodynamic force).
  const auto summary = nlohmann::json::parse(read_text(dir / "summary.json"));
  EXPECT_GT(summary["drag_coefficient"].get<double>(), 0.0);
  fs::remove_all(dir);
}

TEST(RunCli, DefaultFreeSettlingCaseRunsAFewSteps) {
  const fs::path dir = scratch("default");
  const Result r = run_settle("-o " + dir.string() + " --set run.end_time=0.005 --threads 1");
  ASSERT_EQ(r.status, 0) << r.err;
  expect_run_directory(dir, false);
  // A particle heavier than water starts to sink: after 20 steps its velocity points down.
  const auto summary = nlohmann::json::parse(read_text(dir / "summary.json"));
  EXPECT_GT(summary["terminal_vertical_velocity"].get<double>(), 0.0);
  fs::remove_all(dir);
}

TEST(RunCli, UnknownKeyExitsTwoNamingIt) {
  const Result r = run_settle("-o " + scratch("bad").string() + " --set numerics.cells_per_diametre=8");
  EXPECT_EQ(r.status, 2);
  // The schema names a key as "[table] key" in this message.
  EXPECT_NE(r.err.find("cells_per_diametre"), std::string::npos) << r.err;
}

TEST(RunCli, TowedCaseWithoutVelocityExitsTwoNamingTheKey) {
  const Result r = run_settle("-o " + scratch("towed").string() + " --set 'particle.motion=\"towed\"'");
  EXPECT_EQ(r.status, 2);
  EXPECT_NE(r.err.find("particle.towing_velocity"), std::string::npos) << r.err;
}

TEST(RunCli, UnderResolvedCaseIsRefusedBeforeRunning) {
  // A 1 mm sphere towed at 5 m/s (Re = 5000) with 8 cells per diameter cannot meet the Mach
  // and tau bounds together.
  const Result r = run_settle(case_file("towed_sphere.toml") + " -o " + scratch("fast").string() +
                              " --set particle.towing_velocity=[0,0,-5] --set numerics.cells_per_diameter=8");
  EXPECT_EQ(r.status, 2);
  EXPECT_NE(r.err.find("numerics.cells_per_diameter"), std::string::npos) << r.err;
}

}  // namespace
