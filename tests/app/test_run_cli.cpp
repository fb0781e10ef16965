// Case tests of `settle run`: the real binary (SETTLE_BINARY) on tiny cases; the output files
// that are contracts (docs/architecture.md, "Contracts": exact CSV header, summary keys, resolved case) and the refusal of bad
// input with exit status 2 and a message naming the key.
#include <signal.h>
#include <sys/wait.h>
#include <unistd.h>

#include <algorithm>
#include <cctype>
#include <cmath>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <map>
#include <regex>
#include <sstream>
#include <string>
#include <vector>

#include <gtest/gtest.h>
#include <Eigen/Geometry>
#include <nlohmann/json.hpp>

#include "cli_support.hpp"

namespace test_run_cli {

namespace fs = std::filesystem;

using settle::test::read_text;
using settle::test::scratch;
using Result = settle::test::CliResult;

Result run_settle(const std::string& arguments) { return settle::test::run_settle("run", arguments); }

// Appended in place: GCC 12 took `std::string(...) + "/cases/" + name` for a copy past the
// temporary's end (-Warray-bounds) once this file grew.
std::string case_file(const std::string& name) {
  std::string path = SETTLE_SOURCE_DIR;
  path += "/cases/";
  path += name;
  return path;
}

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
  // Both callers' cases couple by the momentum exchange, whose sub-steps 2 and 3 are its own.
  for (const char* step :
       {"body_predictor", "body_mapping", "refill", "fluid", "hydrodynamic_force", "body_corrector", "moving_window"})
    EXPECT_TRUE(summary["timing"].contains(step)) << step;
  if (coefficients) {
    EXPECT_TRUE(summary.contains("lift_coefficient"));
    EXPECT_TRUE(summary.contains("torque_coefficient"));
  }
  EXPECT_GT(summary["steps"].get<long>(), 0);
  EXPECT_TRUE(std::isfinite(summary["drag_coefficient"].get<double>()));
  EXPECT_NE(read_text(dir / "case.resolved.toml").find("# [derived]"), std::string::npos);
  // The build that wrote the run, as `settle --version` names it: a 40-digit commit or "unknown".
  const std::string commit = summary["settle_commit"].get<std::string>();
  EXPECT_TRUE(commit == "unknown" || std::regex_match(commit, std::regex("[0-9a-f]{40}"))) << commit;
  const std::string version = summary["settle_version"].get<std::string>();
  EXPECT_NE(settle::test::run_settle("--version", "").out.find(version + " (commit " + commit + ")"),
            std::string::npos);
  EXPECT_EQ(
      read_text(dir / "case.resolved.toml").rfind("# written by settle " + version + " (commit " + commit + ")\n", 0),
      0u);
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
  const Result r =
      run_settle("-o " + dir.string() + " --set run.end_time=0.005 --set run.output_interval=0.0005 --threads 1");
  ASSERT_EQ(r.status, 0) << r.err;
  expect_run_directory(dir, false);
  // A particle heavier than water starts to sink: after 20 steps its velocity points down. It is
  // still accelerating (the terminal test needs two windows of 5 response times, far more than
  // 5 ms), so nothing is called terminal: the console says "not terminal", summary.json has no
  // terminal velocity and gives the late mean with its trend (speeding up).
  const auto summary = nlohmann::json::parse(read_text(dir / "summary.json"));
  EXPECT_FALSE(summary["terminal_state"]["reached"].get<bool>());
  EXPECT_TRUE(summary["terminal_velocity"].is_null());
  EXPECT_TRUE(summary["terminal_vertical_velocity"].is_null());
  EXPECT_GT(summary["late_mean_vertical_velocity"].get<double>(), 0.0);
  EXPECT_GT(summary["late_velocity_trend"].get<double>(), 0.0);
  EXPECT_NE(r.err.find("not terminal: mean velocity along g over the second half"), std::string::npos) << r.err;
  EXPECT_EQ(r.err.find("terminal velocity along g"), std::string::npos) << r.err;
  fs::remove_all(dir);
}

// particle.lock_rotation reaches the body: the default case's tilted spheroid sinks with its
// attitude and a zero angular velocity in every row, while the fluid's torque on it (which turns
// it when free) is measured and written.
TEST(RunCli, ALockedBodySinksWithoutTurningWhileItsTorqueIsMeasured) {
  const fs::path dir = scratch("locked");
  const Result r = run_settle("-o " + dir.string() +
                              " --set particle.lock_rotation=true --set run.end_time=0.005 --set run.output_interval=0"
                              " --threads 1");
  ASSERT_EQ(r.status, 0) << r.err;
  std::vector<std::string> header;
  const auto rows = settle::test::read_rows(dir / "timeseries.csv", header);
  ASSERT_GE(rows.size(), 10u);
  double largest_torque = 0.0;
  for (const auto& row : rows) {
    for (const char* angle : {"psi", "theta", "gamma"})
      EXPECT_EQ(row[settle::test::column(header, angle)], rows[0][settle::test::column(header, angle)]) << angle;
    for (const char* rate : {"wx", "wy", "wz"}) EXPECT_EQ(row[settle::test::column(header, rate)], 0.0) << rate;
    for (const char* torque : {"Tx", "Ty", "Tz"})
      largest_torque = std::max(largest_torque, std::abs(row[settle::test::column(header, torque)]));
  }
  EXPECT_LT(rows.back()[settle::test::column(header, "uz")], 0.0);  // it sinks
  EXPECT_GT(largest_torque, 0.0);
  fs::remove_all(dir);
}

// The resolved case is a complete case: running it again must be accepted and give the same
// result. Exact equality of the CSV holds because the resolved file carries every value at round-trip
// precision and one thread makes the run deterministic.
TEST(RunCli, ResolvedCaseRunsAgainWithTheSameResult) {
  const fs::path first = scratch("resolved_first"), second = scratch("resolved_second");
  const Result r = run_settle("-o " + first.string() + " --set run.end_time=0.0025 --threads 1");
  ASSERT_EQ(r.status, 0) << r.err;
  // The default case is a spheroid: particle.scale (mesh only) must not be written as if given.
  EXPECT_EQ(read_text(first / "case.resolved.toml").find("\nscale ="), std::string::npos);  // a key of its own
  const Result again = run_settle((first / "case.resolved.toml").string() + " -o " + second.string() + " --threads 1");
  ASSERT_EQ(again.status, 0) << again.err;
  EXPECT_EQ(read_text(first / "timeseries.csv"), read_text(second / "timeseries.csv"));
  fs::remove_all(first);
  fs::remove_all(second);
}

// A mesh run carries its mesh: the STL is copied into the run directory and the resolved case names
// the copy, so that the run directory alone runs again (and settle analyze reads it) wherever the
// case file went.
TEST(RunCli, MeshRunDirectoryHoldsItsMeshAndRunsAgain) {
  const fs::path first = scratch("mesh_first"), second = scratch("mesh_second");
  const Result r = run_settle(case_file("grain.toml") + " -o " + first.string() +
                              " --set numerics.cells_per_diameter=6 --set run.end_time=1e-4 --threads 1");
  ASSERT_EQ(r.status, 0) << r.err;
  EXPECT_EQ(read_text(first / "particle_mesh.stl"), read_text(case_file("grain.stl")));
  EXPECT_NE(read_text(first / "case.resolved.toml").find("file = \"particle_mesh.stl\""), std::string::npos);
  const Result again = run_settle((first / "case.resolved.toml").string() + " -o " + second.string() + " --threads 1");
  ASSERT_EQ(again.status, 0) << again.err;
  EXPECT_EQ(read_text(first / "timeseries.csv"), read_text(second / "timeseries.csv"));
  fs::remove_all(first);
  fs::remove_all(second);
}

// The preflight says from when the terminal state can be detected: two windows of 5 response
// times tau_p = (rho_p + rho_f / 2) U_t / ((rho_p - rho_f) g) after the release
// (analysis/terminal_state.hpp), and warns when run.end_time comes before. The default case's
// spheroid (d_eq = (8 a^2 c)^(1/3) = 2^(1/3) mm, rho_p = 1100) in a fluid of 1 Pa s settles at
// Re ~ 1e-4, where U_t is Stokes' (rho_p - rho_f) g d^2 / (18 mu) and tau_p becomes
// (rho_p + rho_f / 2) d^2 / (18 mu): 0.141 ms, so detectable from 1.41 ms. The estimate's
// Schiller-Naumann factor differs from Stokes' by 0.15 Re^0.687 = 3e-4 there, and the line
// prints 4 digits (5e-4): 2e-3 relative covers both.
TEST(RunCli, ThePreflightSaysFromWhenTheTerminalStateIsDetectableAndWarnsOfAShortRun) {
  const double rho_p = 1100.0, rho_f = 998.2, mu = 1.0, d = std::cbrt(2.0) * 1e-3;
  const double earliest = 10.0 * (rho_p + 0.5 * rho_f) * d * d / (18.0 * mu);
  const std::string base = "--dry-run --set fluid.dynamic_viscosity=1 --threads 1 -o " + scratch("outlook").string();
  const Result short_run = run_settle(base + " --set run.end_time=5e-4");
  ASSERT_EQ(short_run.status, 0) << short_run.err;
  const std::smatch found = [&] {
    std::smatch m;
    std::regex_search(short_run.err, m, std::regex("terminal state: detectable from t = ([0-9.e+-]+) s on"));
    return m;
  }();
  ASSERT_EQ(found.size(), 2u) << short_run.err;
  EXPECT_NEAR(std::stod(found[1].str()) / earliest, 1.0, 2e-3) << short_run.err;
  EXPECT_NE(short_run.err.find("run.end_time: 0.0005 s is too short to detect a terminal state"), std::string::npos)
      << short_run.err;
  EXPECT_NE(short_run.out.find("terminal state: detectable from"), std::string::npos) << short_run.out;
  const Result long_run = run_settle(base + " --set run.end_time=2e-3");
  ASSERT_EQ(long_run.status, 0) << long_run.err;
  EXPECT_EQ(long_run.err.find("too short to detect"), std::string::npos) << long_run.err;
}

// Unit slips the schema cannot see (every key is SI): a diameter of 2 (mm written as m) and a
// density of 2.65 (g/cm^3 written as kg/m^3) are named with the value likely meant, before the
// preflight (which refuses the 2 m spheroid as wider than the 10 mm domain: status 2). The
// physical inputs are printed at the start; a case without particle.density is refused.
TEST(RunCli, AUnitSlipIsNamedWithTheValueLikelyMeant) {
  const std::string base = "--dry-run --threads 1 -o " + scratch("slip").string();
  const Result metres = run_settle(base + " --set particle.diameter=2");
  EXPECT_EQ(metres.status, 2) << metres.err;
  // The default spheroid, aspect ratio 2: d_eq = 2^(1/3) x 2 m = 2.52 m.
  EXPECT_NE(metres.err.find("particle: a 2.52 m particle (volume-equivalent diameter)? Lengths are in metres; if you "
                            "meant millimetres, write particle.diameter = 0.002"),
            std::string::npos)
      << metres.err;
  const Result grams = run_settle(base + " --set particle.density=2.65");
  EXPECT_EQ(grams.status, 0) << grams.err;
  EXPECT_NE(grams.err.find("particle.density: 2.65 kg/m^3 is lighter than the fluid (998.2 kg/m^3): the particle will "
                           "rise. Densities are in kg/m^3; if you meant 2.65 g/cm^3, write particle.density = 2650"),
            std::string::npos)
      << grams.err;
  const Result plain = run_settle(base);
  EXPECT_EQ(plain.status, 0) << plain.err;
  EXPECT_EQ(plain.err.find("if you meant"), std::string::npos) << plain.err;
  EXPECT_NE(plain.err.find("fluid: rho_f = 998.2 kg/m^3, mu = 0.001 Pa s"), std::string::npos) << plain.err;
  EXPECT_NE(plain.err.find("rho_p = 1100 kg/m^3 (rho_p/rho_f = 1.102), free"), std::string::npos) << plain.err;
}

TEST(RunCli, ACaseWithoutTheParticlesDensityIsRefused) {
  const fs::path case_path = settle::test::write_scratch_case(
      "no_density", "[particle]\nshape = \"sphere\"\ndiameter = 1.0e-3\n[domain]\nsize = [8e-3, 8e-3, 8e-3]\n");
  const Result r = run_settle(case_path.string() + " --dry-run -o " + scratch("no_density_run").string());
  EXPECT_EQ(r.status, 2) << r.err;
  EXPECT_NE(r.err.find("particle.density: required (kg/m^3;"), std::string::npos) << r.err;
}

// A rerun into a folder that holds another run's results is refused (status 2, nothing changed):
// the two runs' files would mix (the earlier run's vtk/ and plots/ beside the new series). With
// --overwrite the earlier run's files go, settle's only: a file of the user's stays.
TEST(RunCli, ARerunIntoAnotherRunsFolderIsRefusedUnlessOverwrite) {
  const fs::path dir = scratch("rerun");
  const std::string run = "-o " + dir.string() + " --set run.end_time=0.0025 --threads 1";
  ASSERT_EQ(run_settle(run + " --set run.vtk_interval=0.0025").status, 0);
  ASSERT_TRUE(fs::exists(dir / "vtk" / "fluid.pvd"));
  fs::create_directories(dir / "plots");
  std::ofstream(dir / "plots" / "velocity.png") << "\x89PNG\r\n\x1a\n(a figure)";
  std::ofstream(dir / "notes.txt") << "the user's";
  const std::string summary_before = read_text(dir / "summary.json");

  const Result refused = run_settle(run);
  EXPECT_EQ(refused.status, 2) << refused.err;
  EXPECT_NE(refused.err.find("holds the results of another run (summary.json, timeseries.csv, case.resolved.toml, "),
            std::string::npos)
      << refused.err;
  EXPECT_NE(refused.err.find("give --overwrite to replace them"), std::string::npos) << refused.err;
  EXPECT_EQ(read_text(dir / "summary.json"), summary_before);
  EXPECT_TRUE(fs::exists(dir / "vtk" / "fluid.pvd"));

  const Result replaced = run_settle(run + " --overwrite");
  ASSERT_EQ(replaced.status, 0) << replaced.err;
  EXPECT_FALSE(fs::exists(dir / "vtk"));
  EXPECT_FALSE(fs::exists(dir / "plots"));
  EXPECT_EQ(read_text(dir / "notes.txt"), "the user's");
  // The log is the new run's alone.
  const std::string log = read_text(dir / "run.log");
  EXPECT_EQ(log.find("fluid: rho_f"), log.rfind("fluid: rho_f")) << log;
  fs::remove_all(dir);
}

// Every run folder holds run.log, the console's lines at the default verbosity whatever the
// console shows (here --quiet: warnings only on stderr), among them the result line.
TEST(RunCli, EveryRunFolderHoldsItsLog) {
  const fs::path dir = scratch("log");
  const Result r = run_settle("-o " + dir.string() + " --set run.end_time=0.0025 --threads 1 --quiet");
  ASSERT_EQ(r.status, 0) << r.err;
  EXPECT_EQ(r.err.find("fluid: rho_f"), std::string::npos) << r.err;
  const std::string log = read_text(dir / "run.log");
  EXPECT_EQ(log.rfind("settle run: ", 0), 0u) << log;
  EXPECT_NE(log.find("fluid: rho_f = 998.2 kg/m^3"), std::string::npos) << log;
  EXPECT_NE(log.find("preflight passed"), std::string::npos) << log;
  EXPECT_NE(log.find("not terminal: mean velocity along g"), std::string::npos) << log;
  fs::remove_all(dir);
}

// A finished run ends with a checkpoint, so that it extends from its end: run to 2.5 ms, then
// --restart --set run.end_time=5 ms, gives the time series of a run to 5 ms byte for byte (one
// thread: every sum in a fixed order; the restart cuts the end's extra row off again).
TEST(RunCli, AFinishedRunExtendsFromItsEndAsIfItHadRunOn) {
  const fs::path whole = scratch("extend_whole"), split = scratch("extend_split");
  ASSERT_EQ(run_settle("-o " + whole.string() + " --set run.end_time=0.005 --threads 1").status, 0);
  const Result first = run_settle("-o " + split.string() + " --set run.end_time=0.0025 --threads 1");
  ASSERT_EQ(first.status, 0) << first.err;
  EXPECT_NE(first.err.find("checkpoint at the end, t = "), std::string::npos) << first.err;
  ASSERT_TRUE(fs::exists(split / "checkpoint.bin"));
  const Result extended = run_settle("--restart " + split.string() + " --set run.end_time=0.005 --threads 1");
  ASSERT_EQ(extended.status, 0) << extended.err;
  EXPECT_NE(extended.err.find("continuing from " + (split / "checkpoint.bin").string() + " at t = 0.0025"),
            std::string::npos)
      << extended.err;
  EXPECT_EQ(read_text(split / "timeseries.csv"), read_text(whole / "timeseries.csv"));
  // The log holds both segments.
  const std::string log = read_text(split / "run.log");
  EXPECT_NE(log.find("checkpoint at the end"), std::string::npos) << log;
  EXPECT_NE(log.find("continuing from"), std::string::npos) << log;
  fs::remove_all(whole);
  fs::remove_all(split);
}

// run.stop_at_terminal feeds the analysis' own detector with every sample: the run ends at the
// first sample where the criterion holds, and the analysis of the written series (the same
// detector on the same numbers, read back at round-trip precision) finds it at exactly that time.
// The summary carries the analysis and the correlations' predictions for the same particle.
TEST(RunCli, StopsAtTheTerminalStateTheAnalysisFinds) {
  const fs::path dir = scratch("terminal");
  const Result r = run_settle("-o " + dir.string() +
                              " --set numerics.cells_per_diameter=6 --set run.stop_at_terminal=true"
                              " --set run.end_time=5 --threads 1");
  ASSERT_EQ(r.status, 0) << r.err;
  const auto summary = nlohmann::json::parse(read_text(dir / "summary.json"));
  EXPECT_EQ(summary["stop_reason"], "terminal_state");
  ASSERT_TRUE(summary["terminal_state"]["reached"].get<bool>());
  EXPECT_EQ(summary["terminal_state"]["detected_at"].get<double>(), summary["simulated_time"].get<double>());
  EXPECT_LT(summary["simulated_time"].get<double>(), 5.0);
  EXPECT_EQ(summary["averaging"]["basis"], "terminal_window");
  // Detected, so called terminal: the terminal velocity is the mean over the terminal window.
  EXPECT_EQ(summary["terminal_vertical_velocity"].get<double>(), summary["late_mean_vertical_velocity"].get<double>());
  EXPECT_NE(r.err.find("terminal velocity along g"), std::string::npos) << r.err;
  EXPECT_EQ(r.err.find("not terminal"), std::string::npos) << r.err;
  // Every law of settle predict, with its ratio to the simulated terminal speed.
  ASSERT_EQ(summary["correlations"].size(), 7u);
  for (const auto& law : summary["correlations"]) {
    EXPECT_TRUE(law["law"].is_string());
    EXPECT_TRUE(law["ratio_to_run"].is_number()) << law["law"];
  }
  fs::remove_all(dir);
}

// --quiet leaves warnings and errors only; the default prints the start-up lines and the end of
// the run, with the timing of every sub-step.
TEST(RunCli, QuietPrintsNothingButWarnings) {
  const fs::path dir = scratch("quiet");
  const Result quiet = run_settle("-o " + dir.string() + " --set run.end_time=0.0025 --threads 1 --quiet");
  ASSERT_EQ(quiet.status, 0) << quiet.err;
  // Warnings only (this short run is warned that it cannot reach its terminal state).
  std::istringstream lines(quiet.err);
  for (std::string line; std::getline(lines, line);) EXPECT_EQ(line.rfind("settle run: warning: ", 0), 0u) << line;
  const Result normal = run_settle("-o " + dir.string() + " --set run.end_time=0.0025 --threads 1 --overwrite");
  ASSERT_EQ(normal.status, 0) << normal.err;
  for (const char* step : {"body_predictor", "body_mapping", "refill", "fluid", "hydrodynamic_force", "body_corrector"})
    EXPECT_NE(normal.err.find(step), std::string::npos) << step;
  EXPECT_EQ(run_settle("-o " + dir.string() + " --quiet --verbose").status, 2);
  fs::remove_all(dir);
}

std::string lower_case(std::string text) {
  std::transform(text.begin(), text.end(), text.begin(), [](unsigned char c) { return std::tolower(c); });
  return text;
}

// The momentum exchange (the default coupling) has no markers, and its run says none: neither its
// console (--verbose: every line) nor its summary.json names them, but for the keys kept for one
// release beside their new names (docs/user-guide.md, "summary.json"), which must carry the new
// keys' numbers: `markers` (surface_elements, the wall links) and the timing of `markers` and
// `forcing` (body_mapping and refill). The immersed boundary keeps its words.
TEST(RunCli, AMomentumExchangeRunNamesNoMarkersButItsDeprecatedKeys) {
  const fs::path dir = scratch("vocabulary");
  const Result r = run_settle("-o " + dir.string() + " --set run.end_time=0.0025 --threads 1 --verbose");
  ASSERT_EQ(r.status, 0) << r.err;
  EXPECT_EQ(lower_case(r.err).find("marker"), std::string::npos) << r.err;
  EXPECT_NE(r.err.find(" wall links, "), std::string::npos) << r.err;
  EXPECT_NE(r.err.find(" boundary cells; "), std::string::npos) << r.err;
  auto summary = nlohmann::json::parse(read_text(dir / "summary.json"));
  EXPECT_EQ(summary["coupling"], "momentum_exchange");
  EXPECT_GT(summary["surface_elements"].get<long>(), 0);
  EXPECT_EQ(summary["markers"], summary["surface_elements"]);
  EXPECT_EQ(summary["timing"]["markers"], summary["timing"]["body_mapping"]);
  EXPECT_EQ(summary["timing"]["forcing"], summary["timing"]["refill"]);
  summary.erase("markers");
  summary["timing"].erase("markers");
  summary["timing"].erase("forcing");
  EXPECT_EQ(lower_case(summary.dump()).find("marker"), std::string::npos) << summary.dump(2);

  const Result immersed =
      run_settle("-o " + dir.string() +
                 " --set run.end_time=0.0025 --threads 1 --overwrite --set 'numerics.coupling=\"immersed_boundary\"'");
  ASSERT_EQ(immersed.status, 0) << immersed.err;
  EXPECT_NE(immersed.err.find(" markers, "), std::string::npos) << immersed.err;
  const auto ib = nlohmann::json::parse(read_text(dir / "summary.json"));
  EXPECT_EQ(ib["markers"], ib["surface_elements"]);
  for (const char* step : {"markers", "forcing"}) EXPECT_TRUE(ib["timing"].contains(step)) << step;
  for (const char* step : {"body_mapping", "refill"}) EXPECT_FALSE(ib["timing"].contains(step)) << step;
  fs::remove_all(dir);
}

TEST(RunCli, CommandLineParseErrorsExitTwo) {
  // An unknown flag and a malformed number are usage errors (exit 2, like a bad case key); --help succeeds.
  EXPECT_EQ(run_settle("--no-such-flag").status, 2);
  EXPECT_EQ(run_settle("--threads many").status, 2);
  EXPECT_EQ(run_settle("--help").status, 0);
}

TEST(RunCli, ReferenceKeyIsCopiedIntoTheSummary) {
  const fs::path dir = scratch("reference");
  const Result r = run_settle("-o " + dir.string() + " --set run.end_time=0.0025 --threads 1 " +
                              "--set 'run.reference=\"tenCate2002_E1\"'");
  ASSERT_EQ(r.status, 0) << r.err;
  const auto summary = nlohmann::json::parse(read_text(dir / "summary.json"));
  EXPECT_EQ(summary.value("reference", std::string()), "tenCate2002_E1");
  fs::remove_all(dir);
}

// The default spheroid (polar half-length 1 mm, d_eq = 1.26 mm, dx = d_eq / 8 = 0.1575 mm) upright
// with its lowest point 3 cells above the floor, in a fixed window so that contact is on. The
// momentum exchange's links need half a cell, so only the contact start rule can refuse it: the
// spring reaches 5 cells, and 2 W / k is about 1e-9 m (k = m pi^2 / (10 dt)^2), far below a cell.
const char* kNearFloor =
    "--set domain.follow_particle=false --set particle.euler=[0,0,0] "
    "--set particle.position=[3.78e-3,3.78e-3,1.4725e-3] --set run.end_time=0.0025 --threads 1";

TEST(RunCli, ParticleInsideTheContactDistanceIsRefused) {
  const Result r =
      run_settle("-o " + scratch("near_floor").string() + " " + kNearFloor + " --set contact.distance_cells=5");
  EXPECT_EQ(r.status, 2);
  EXPECT_NE(r.err.find("particle.position"), std::string::npos) << r.err;
  EXPECT_NE(r.err.find("contact.distance_cells"), std::string::npos) << r.err;
  EXPECT_FALSE(fs::exists(scratch("near_floor")));
  // The same start is accepted with a shorter reach, and with contact off.
  const fs::path dir = scratch("near_floor_ok");
  EXPECT_EQ(run_settle("-o " + dir.string() + " " + kNearFloor + " --set contact.distance_cells=2.5").status, 0);
  EXPECT_EQ(run_settle("-o " + dir.string() + " " + kNearFloor +
                       " --set contact.distance_cells=5 --set contact.enabled=false --overwrite")
                .status,
            0);
  fs::remove_all(dir);
}

TEST(RunCli, ContactKeysOutOfRangeExitTwo) {
  EXPECT_EQ(run_settle("-o " + scratch("e").string() + " --set contact.restitution=0").status, 2);
  EXPECT_EQ(run_settle("-o " + scratch("e").string() + " --set contact.collision_steps=0.5").status, 2);
  const Result wet = run_settle("-o " + scratch("e").string() + " --set contact.wet_stokes_scale=-1");
  EXPECT_EQ(wet.status, 2);
  EXPECT_NE(wet.err.find("wet_stokes_scale"), std::string::npos) << wet.err;
  // 1.2 cells is inside the schema's range [0.5, 1000] but below the immersed boundary's bound
  // with peskin4, 2 - 0.5 = 1.5 (the momentum exchange's is 1 - 0.5, whatever the kernel).
  const Result r =
      run_settle("-o " + scratch("e").string() + " " + kNearFloor +
                 " --set 'numerics.coupling=\"immersed_boundary\"' --set 'numerics.delta_kernel=\"peskin4\"'"
                 " --set contact.distance_cells=1.2");
  EXPECT_EQ(r.status, 2);
  EXPECT_NE(r.err.find("contact.distance_cells"), std::string::npos) << r.err;
}

// The contact columns follow the existing ones (never renamed). In the near-floor start (3 cells
// above the floor, the momentum exchange's default contact distance 1 cell) the body is out of
// the spring's reach in 10 steps (it sinks about 2e-6 m: 1/2 a t^2 with a ~ 0.6 m/s^2, t = 2.5
// ms): zero contact force, and a finite gap close to the start's 3 cells.
// The rows of a timeseries.csv by column name (new columns are appended: tests name them, never
// count from the end).
std::vector<std::map<std::string, double>> rows_by_name(const fs::path& csv_path) {
  std::ifstream csv(csv_path);
  std::string header;
  std::getline(csv, header);
  std::vector<std::string> names;
  std::stringstream header_fields(header);
  for (std::string name; std::getline(header_fields, name, ',');) names.push_back(name);
  std::vector<std::map<std::string, double>> rows;
  for (std::string line; std::getline(csv, line);) {
    std::stringstream fields(line);
    std::map<std::string, double>& row = rows.emplace_back();
    std::size_t c = 0;
    for (std::string field; std::getline(fields, field, ',') && c < names.size(); ++c) row[names[c]] = std::stod(field);
  }
  return rows;
}

TEST(RunCli, TimeseriesCarriesContactForceAndWallGap) {
  const fs::path dir = scratch("contact_columns");
  ASSERT_EQ(run_settle("-o " + dir.string() + " " + kNearFloor).status, 0);
  std::ifstream csv(dir / "timeseries.csv");
  std::string header;
  std::getline(csv, header);
  EXPECT_NE(header.find(",slip_rms,Fcx,Fcy,Fcz,wall_gap"), std::string::npos) << header;
  const auto rows = rows_by_name(dir / "timeseries.csv");
  ASSERT_FALSE(rows.empty());
  const auto& last = rows.back();
  for (const char* column : {"Fcx", "Fcy", "Fcz"}) EXPECT_EQ(last.at(column), 0.0) << column;
  // 3 cells of 0.1575 mm = 4.725e-4 m; 2 % allows the 10 steps' sinking (~2e-6 m, 0.4 %; measured
  // 4.7058e-4 m) and the slight tilt the flow may give, while a wrong unit (cells) or a wrong wall
  // would miss by far.
  EXPECT_NEAR(last.at("wall_gap"), 4.725e-4, 0.02 * 4.725e-4);
  fs::remove_all(dir);
  // The default case's window follows the body: no contact walls, the documented -1.
  ASSERT_EQ(run_settle("-o " + dir.string() + " --set run.end_time=0.0025 --threads 1").status, 0);
  EXPECT_EQ(rows_by_name(dir / "timeseries.csv").back().at("wall_gap"), -1.0);
  fs::remove_all(dir);
}

// The quaternion columns (appended after wall_gap) and the sidecar timeseries.json. At t = 0 the
// attitude is the case's particle.euler exactly, so q_w .. q_z must be the quaternion of
// Rz(psi) Ry(theta) Rx(gamma) (docs/attitude.md, "Conventions"), built here from Eigen's
// angle-axis rotations, independently of settle's Euler code: both are a few products of sines
// and cosines of the same angles, so 1e-15 (a few ulps of a number below 1) separates round-off
// from a wrong order or sign. Every row's quaternion is unit to 1e-14 (it is composed, not
// integrated: round-off of a dozen products).
TEST(RunCli, TimeseriesCarriesTheQuaternionAndItsSidecarNamesEveryColumn) {
  const fs::path dir = scratch("quaternion_columns");
  const double psi = 0.3, theta = 0.4, gamma = 0.5;
  ASSERT_EQ(run_settle("-o " + dir.string() + " --set 'particle.euler=[0.3,0.4,0.5]' --set run.end_time=0.0025" +
                       " --set run.output_interval=0 --threads 1")
                .status,
            0);
  const auto rows = rows_by_name(dir / "timeseries.csv");
  ASSERT_GE(rows.size(), 2u);
  const Eigen::Quaterniond expected = Eigen::AngleAxisd(psi, Eigen::Vector3d::UnitZ()) *
                                      Eigen::AngleAxisd(theta, Eigen::Vector3d::UnitY()) *
                                      Eigen::AngleAxisd(gamma, Eigen::Vector3d::UnitX());
  const auto& first = rows.front();
  ASSERT_EQ(first.at("t"), 0.0);
  EXPECT_NEAR(first.at("q_w"), expected.w(), 1e-15);
  EXPECT_NEAR(first.at("q_x"), expected.x(), 1e-15);
  EXPECT_NEAR(first.at("q_y"), expected.y(), 1e-15);
  EXPECT_NEAR(first.at("q_z"), expected.z(), 1e-15);
  for (const auto& row : rows) {
    const double norm = Eigen::Vector4d(row.at("q_w"), row.at("q_x"), row.at("q_y"), row.at("q_z")).norm();
    EXPECT_NEAR(norm, 1.0, 1e-14) << "t = " << row.at("t");
    EXPECT_GE(row.at("q_w"), 0.0) << "t = " << row.at("t");
  }

  std::ifstream csv(dir / "timeseries.csv");
  std::string header;
  std::getline(csv, header);
  EXPECT_TRUE(header.ends_with(",wall_gap,q_w,q_x,q_y,q_z")) << header;
  const auto sidecar = nlohmann::json::parse(read_text(dir / "timeseries.json"));
  EXPECT_EQ(sidecar["file"], "timeseries.csv");
  std::string names;
  for (const auto& column : sidecar["columns"]) {
    names += (names.empty() ? "" : ",") + column["name"].get<std::string>();
    EXPECT_FALSE(column["unit"].get<std::string>().empty()) << column;
    EXPECT_TRUE(column.contains("frame") && column.contains("meaning")) << column;
  }
  EXPECT_EQ(names, header);
  EXPECT_EQ(sidecar["columns"][6]["unit"], "m/s");  // uz
  fs::remove_all(dir);
}

// run.vtk_interval = 2 dt on a 10-step run (dt = 2.5e-4 s): files at steps 0, 2, ..., 10, i.e. six
// of each kind, and both collections list six times. Counted exactly: the schedule is a closed rule.
TEST(RunCli, VtkOutputOnItsOwnSchedule) {
  const fs::path dir = scratch("vtk");
  const Result r = run_settle("-o " + dir.string() +
                              " --set run.end_time=0.0025 --set run.vtk_interval=0.0005 "
                              "--threads 1");
  ASSERT_EQ(r.status, 0) << r.err;
  int fluid = 0, surface = 0;
  for (const auto& entry : fs::directory_iterator(dir / "vtk")) {
    const std::string name = entry.path().filename().string();
    fluid += name.rfind("fluid_", 0) == 0 && entry.path().extension() == ".vti";
    surface += name.rfind("surface_", 0) == 0 && entry.path().extension() == ".vtp";
  }
  EXPECT_EQ(fluid, 6);
  EXPECT_EQ(surface, 6);
  EXPECT_TRUE(fs::exists(dir / "vtk" / "fluid_000005.vti"));
  const std::string fluid_pvd = read_text(dir / "vtk" / "fluid.pvd");
  const std::string surface_pvd = read_text(dir / "vtk" / "surface.pvd");
  std::size_t datasets = 0;
  for (auto at = fluid_pvd.find("<DataSet"); at != std::string::npos; at = fluid_pvd.find("<DataSet", at + 1))
    ++datasets;
  EXPECT_EQ(datasets, 6u);
  EXPECT_NE(surface_pvd.find("surface_000005.vtp"), std::string::npos);
  EXPECT_NE(read_text(dir / "vtk" / "fluid_000000.vti").find("solid_fraction"), std::string::npos);
  EXPECT_EQ(r.err.find("VTK output is not implemented"), std::string::npos) << r.err;
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

// The number after `label` on the plan's line that starts with `line_key`, e.g. ("units", "dt =").
double plan_number(const std::string& plan, const std::string& line_key, const std::string& label) {
  const std::size_t line = plan.find("  " + line_key + " ");
  if (line == std::string::npos) return std::nan("");
  const std::size_t at = plan.find(label, line);
  if (at == std::string::npos || at > plan.find('\n', line)) return std::nan("");
  return std::atof(plan.c_str() + at + label.size());
}

// `settle run --dry-run` prints the plan the run itself is built on (coupling/case_plan.hpp) and
// writes nothing: its dt, tau and step count must be the ones a real run of the same case
// reports in summary.json (printed with 4 significant digits, hence the relative 1e-3).
TEST(RunCli, DryRunPrintsThePlanTheRunUsesAndWritesNothing) {
  const fs::path planned = scratch("dry_run"), ran = scratch("dry_run_real");
  const std::string args = case_file("periodic_sphere_array.toml") +
                           " --set numerics.cells_per_diameter=8 --set run.end_time=0.05 --threads 1 -q";
  const Result plan = run_settle(args + " --dry-run -o " + planned.string());
  ASSERT_EQ(plan.status, 0) << plan.err;
  EXPECT_FALSE(fs::exists(planned));
  EXPECT_NE(plan.out.find("wall time about"), std::string::npos) << plan.out;

  const Result run = run_settle(args + " -o " + ran.string());
  ASSERT_EQ(run.status, 0) << run.err;
  const auto summary = nlohmann::json::parse(read_text(ran / "summary.json"));
  const double dt = summary["dt"].get<double>(), tau = summary["tau"].get<double>();
  EXPECT_NEAR(plan_number(plan.out, "units", "dt = "), dt, 1e-3 * dt) << plan.out;
  EXPECT_NEAR(plan_number(plan.out, "units", "tau = "), tau, 1e-4) << plan.out;
  EXPECT_EQ(plan_number(plan.out, "run", "s = "), summary["steps"].get<double>()) << plan.out;
  fs::remove_all(ran);
}

// A long run without checkpoints cannot be continued once it has ended: the shipped fixed-sphere
// case (4.2e6 cells, 28 800 steps: 1.2e11 cell updates, above the 1e11 of kLongRunCellUpdates)
// without its wall-clock checkpoints is warned about before it starts, and not with them.
TEST(RunCli, ALongRunWithoutCheckpointsIsWarnedAbout) {
  const std::string args =
      case_file("fixed_sphere_stream.toml") + " --dry-run --threads 1 -q -o " + scratch("long_run_advice").string();
  const Result bare = run_settle(args + " --set run.checkpoint_wall_interval=0");
  ASSERT_EQ(bare.status, 0) << bare.err;
  EXPECT_NE(bare.err.find("keeps no checkpoint"), std::string::npos) << bare.err;
  EXPECT_NE(bare.err.find("run.checkpoint_wall_interval"), std::string::npos) << bare.err;

  const Result kept = run_settle(args);
  ASSERT_EQ(kept.status, 0) << kept.err;
  EXPECT_EQ(kept.err.find("keeps no checkpoint"), std::string::npos) << kept.err;
}

TEST(RunCli, DryRunRefusesARestart) {
  const Result r = run_settle("--dry-run --restart " + scratch("dry_run_restart").string());
  EXPECT_EQ(r.status, 2);
  EXPECT_NE(r.err.find("--dry-run"), std::string::npos) << r.err;
}

}  // namespace test_run_cli

namespace test_run_cli {

// Two runs writing one directory would interleave their time series and overwrite each other's
// checkpoints: the second is refused while the first lives (app/run_directory_lock.hpp), and the
// directory is free again once the first has ended, however it ended.
TEST(RunCli, ASecondRunIntoALiveRunsDirectoryIsRefused) {
  const fs::path dir = settle::test::scratch("run_lock");
  fs::remove_all(dir);
  const std::string towed = std::string(SETTLE_SOURCE_DIR) + "/cases/towed_sphere.toml";
  const pid_t first = fork();
  ASSERT_GE(first, 0);
  if (first == 0) {
    ::execl(std::getenv("SETTLE_BINARY"), "settle", "run", towed.c_str(), "-o", dir.c_str(), "-q", "--set",
            "numerics.cells_per_diameter=5", "--set", "run.end_time=100", static_cast<char*>(nullptr));
    ::_exit(127);
  }
  // The lock file appears once the first run has passed its checks and taken the directory.
  for (int i = 0; i < 3000 && !fs::exists(dir / "case.resolved.toml"); ++i) ::usleep(10000);
  ASSERT_TRUE(fs::exists(dir / "case.resolved.toml"));
  const auto second = settle::test::run_settle("run", towed + " -o " + dir.string() + " --set run.end_time=0.01");
  EXPECT_EQ(second.status, 2);
  EXPECT_NE(second.err.find("another settle run is writing this directory"), std::string::npos) << second.err;
  ::kill(first, SIGKILL);  // no checkpoint, no clean exit: the kernel still releases the lock
  int status = 0;
  ASSERT_EQ(::waitpid(first, &status, 0), first);
  const auto third = settle::test::run_settle(
      "run",
      towed + " -o " + dir.string() + " -q --set numerics.cells_per_diameter=5 --set run.end_time=0.01 --overwrite");
  EXPECT_EQ(third.status, 0) << third.err;
}

// A 1 mm glass sphere started 0.4 mm above the floor lands within 0.01 s and rests there (702
// steps, under a second): over the averaged second half it is held by the wall, so its mean
// velocity (a few 1e-5 m/s of jitter) is no terminal velocity, and the force balance's drag
// coefficient came out 1.7e6, or negative, with no warning. The summary must give none, and say why.
TEST(RunCli, ASphereRestingOnTheFloorGetsNoDragCoefficient) {
  const fs::path dir = scratch("resting");
  const fs::path case_path = settle::test::write_scratch_case(
      "resting",
      "[fluid]\ndensity = 998.2\ndynamic_viscosity = 1.0e-3\n"
      "[particle]\nshape = \"sphere\"\ndiameter = 1.0e-3\ndensity = 2500.0\nposition = [2.0e-3, 2.0e-3, 0.9e-3]\n"
      "[domain]\nsize = [4.0e-3, 4.0e-3, 4.0e-3]\n[numerics]\ncells_per_diameter = 6\n"
      "[run]\nend_time = 0.04\noutput_interval = 1.0e-3\n");
  const Result r = run_settle(case_path.string() + " -o " + dir.string() + " --threads 1");
  ASSERT_EQ(r.status, 0) << r.err;
  const auto summary = nlohmann::json::parse(read_text(dir / "summary.json"));
  EXPECT_TRUE(summary["drag_coefficient"].is_null()) << summary["drag_coefficient"];
  EXPECT_TRUE(summary["drag_coefficient_from_force"].is_null());
  EXPECT_EQ(summary.value("wall_contact_samples", 0), summary["averaging"]["samples"].get<int>());
  const std::string warnings = summary["analysis_warnings"].dump();
  EXPECT_NE(warnings.find("touches a wall"), std::string::npos) << warnings;
  EXPECT_NE(r.err.find("C_D = none"), std::string::npos) << r.err;
  fs::remove_all(dir);
  fs::remove(case_path);
}

}  // namespace test_run_cli
