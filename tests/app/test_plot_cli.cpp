// Case tests of `settle plot`: the real binary (SETTLE_BINARY) on the output of a short real run
// and on run directories written here with known content, so that what the figures are drawn
// from can be checked against closed forms: the tilt of a given initial attitude, and the
// reference overlay of a run that reproduces the reference exactly. Without a python3 that can
// import matplotlib and numpy the figure tests are skipped (docs/plots.md).
#include <algorithm>
#include <array>
#include <cmath>
#include <cstdint>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <numbers>
#include <regex>
#include <sstream>
#include <string>
#include <vector>

#include <fmt/core.h>
#include <gtest/gtest.h>
#include <nlohmann/json.hpp>

#include "cli_support.hpp"

namespace test_plot_cli {

namespace fs = std::filesystem;
using nlohmann::json;
using settle::test::read_text;
using settle::test::scratch;
using Result = settle::test::CliResult;

const std::array<const char*, 5> kFigures = {"velocity.png", "trajectory.png", "trajectory_3d.png", "orientation.png",
                                             "forces.png"};

Result run_plot(const std::string& arguments) { return settle::test::run_settle("plot", arguments); }

/// Whether a python the command would use imports matplotlib and numpy (the same order as
/// cmd_plot.cpp: $SETTLE_PYTHON alone when set, else python3 from PATH, then /usr/bin/python3).
bool matplotlib_available() {
  const char* chosen = std::getenv("SETTLE_PYTHON");
  std::vector<std::string> candidates;
  if (chosen != nullptr && *chosen != '\0')
    candidates = {chosen};
  else
    candidates = {"python3", "/usr/bin/python3"};
  return std::any_of(candidates.begin(), candidates.end(), [](const std::string& python) {
    return std::system((python + " -c 'import matplotlib, numpy' > /dev/null 2>&1").c_str()) == 0;
  });
}

#define SKIP_WITHOUT_MATPLOTLIB() \
  if (!matplotlib_available())    \
  GTEST_SKIP() << "no python3 importing matplotlib and numpy (Debian: apt-get install python3-matplotlib)"

struct PngHeader {
  bool signature_ok = false;
  std::uint32_t width = 0, height = 0;
  std::uintmax_t bytes = 0;
};

std::uint32_t big_endian(const unsigned char* p) {
  return (std::uint32_t{p[0]} << 24) | (std::uint32_t{p[1]} << 16) | (std::uint32_t{p[2]} << 8) | p[3];
}

/// The PNG signature and the image size from the IHDR chunk, which the format puts first.
PngHeader read_png_header(const fs::path& path) {
  PngHeader header;
  std::ifstream file(path, std::ios::binary);
  std::array<unsigned char, 24> bytes{};
  if (!file.read(reinterpret_cast<char*>(bytes.data()), bytes.size())) return header;
  const std::array<unsigned char, 8> signature = {0x89, 'P', 'N', 'G', '\r', '\n', 0x1a, '\n'};
  header.signature_ok = std::equal(signature.begin(), signature.end(), bytes.begin()) &&
                        std::string(reinterpret_cast<const char*>(&bytes[12]), 4) == "IHDR";
  header.width = big_endian(&bytes[16]);
  header.height = big_endian(&bytes[20]);
  header.bytes = fs::file_size(path);
  return header;
}

void expect_figure(const fs::path& path, const std::string& listed) {
  ASSERT_TRUE(fs::exists(path)) << path;
  const PngHeader png = read_png_header(path);
  EXPECT_TRUE(png.signature_ok) << path;
  // Every figure is at least 7 x 5.5 inches at 150 dpi (settle_plot.py): a smaller image means a
  // figure that lost its content or its layout.
  EXPECT_GE(png.width, 1000u) << path;
  EXPECT_GE(png.height, 800u) << path;
  // Measured with this matplotlib: a blank 8.5 x 8 inch canvas at 150 dpi is 9 kB and three
  // empty labelled axes 35 kB; the figures with curves, legends and titles are 90-250 kB.
  EXPECT_GT(png.bytes, 50'000u) << path;
  // The command lists each file it wrote on its own line of stdout.
  EXPECT_NE(listed.find(path.string() + "\n"), std::string::npos) << path << " not in:\n" << listed;
}

/// The number captured by the first group of `pattern` in `text` (the command's notes on stderr).
double printed_number(const std::string& text, const std::string& pattern) {
  std::smatch match;
  if (!std::regex_search(text, match, std::regex(pattern))) {
    ADD_FAILURE() << "no match for '" << pattern << "' in:\n" << text;
    return std::nan("");
  }
  return std::stod(match[1].str());
}

TEST(PlotCli, DrawsEveryFigureOfAShortRealRun) {
  SKIP_WITHOUT_MATPLOTLIB();
  const fs::path run = scratch("plot_run");
  // The built-in case for 40 steps, started from set-1 angles (psi, theta, gamma) = (0.3, 0.4, 0.5).
  const Result simulated = settle::test::run_settle(
      "run", "-o " + run.string() +
                 " --set run.end_time=0.01 --set run.output_interval=0.001 --set 'particle.euler=[0.3,0.4,0.5]' "
                 "--threads 1");
  ASSERT_EQ(simulated.status, 0) << simulated.err;

  const Result r = run_plot(run.string());
  ASSERT_EQ(r.status, 0) << r.err;
  for (const char* figure : kFigures) expect_figure(run / "plots" / figure, r.out);
  // The run names no reference data, so none is drawn.
  EXPECT_FALSE(fs::exists(run / "plots" / "reference.png"));

  // Tilt of body z at t = 0, from the CSV's set-1 angles through C_b^n = Rz(psi) Ry(theta) Rx(gamma)
  // (docs/architecture.md, "Frames and attitude"): cos(tilt) = C_b^n(3,3) = cos(theta) cos(gamma), independent of psi.
  const double expected_deg = std::acos(std::cos(0.4) * std::cos(0.5)) * 180.0 / std::numbers::pi;
  const double printed_deg = printed_number(r.err, R"(tilt of body z from vertical: ([-0-9.e+]+) deg at t = 0 s)");
  // Printed with 6 decimals; the angles in the CSV are the case's exactly (17 digits).
  EXPECT_NEAR(printed_deg, expected_deg, 2e-6);
  // The set-1 and set-2 angles of each row are written from one matrix: no disagreement warning.
  EXPECT_EQ(r.err.find("disagree"), std::string::npos) << r.err;
  fs::remove_all(run);
}

// A run directory whose sphere follows the ten Cate et al. (2002) E1 curves exactly: u_z and the
// gap are the reference series, linearly interpolated onto the union of their sample times (so
// at each reference time the run holds the reference value to 17 digits), with the fluid and
// particle of that experiment.
struct ReferenceSeries {
  std::vector<std::array<double, 2>> velocity;    // t (s), u_z (m/s)
  std::vector<std::array<double, 2>> trajectory;  // t (s), bottom gap / d
};

ReferenceSeries tencate_e1() {
  const json data = json::parse(read_text(fs::path(SETTLE_SOURCE_DIR) / "validation/reference-data.json"));
  const json& fields = data.at("tenCate2002_E1").at("fields");
  return {fields.at("digitized_velocity_t_s__uz_m_per_s").get<std::vector<std::array<double, 2>>>(),
          fields.at("digitized_trajectory_t_s__gap_over_d").get<std::vector<std::array<double, 2>>>()};
}

/// Piecewise-linear interpolation of (t, value) samples sorted by t, held constant outside.
double interpolate(const std::vector<std::array<double, 2>>& samples, double t) {
  if (t <= samples.front()[0]) return samples.front()[1];
  if (t >= samples.back()[0]) return samples.back()[1];
  const auto upper = std::upper_bound(samples.begin(), samples.end(), t,
                                      [](double value, const std::array<double, 2>& s) { return value < s[0]; });
  const auto lower = upper - 1;
  if (t == (*lower)[0]) return (*lower)[1];
  const double w = (t - (*lower)[0]) / ((*upper)[0] - (*lower)[0]);
  return (1.0 - w) * (*lower)[1] + w * (*upper)[1];
}

constexpr double kTenCateDiameter = 0.015;  // m (reference-data.json, tenCate2002_setup)

fs::path write_reference_run(const std::string& name, const ReferenceSeries& reference) {
  const fs::path dir = scratch(name);
  fs::create_directories(dir);
  std::vector<double> times;
  for (const auto& s : reference.velocity) times.push_back(s[0]);
  for (const auto& s : reference.trajectory) times.push_back(s[0]);
  std::sort(times.begin(), times.end());
  times.erase(std::unique(times.begin(), times.end()), times.end());

  std::ofstream csv(dir / "timeseries.csv");
  csv << "t,x,y,z,ux,uy,uz,wx,wy,wz,wbx,wby,wbz,psi,theta,gamma,psi_r,theta_r,gamma_r,euler_set,"
         "Fx,Fy,Fz,Tx,Ty,Tz,Re,slip_max,slip_rms\n";
  for (const double t : times) {
    const double z = (interpolate(reference.trajectory, t) + 0.5) * kTenCateDiameter;
    const double uz = interpolate(reference.velocity, t);
    csv << fmt::format("{:.17g},0.05,0.05,{:.17g},0,0,{:.17g},0,0,0,0,0,0,0,0,0,0,0,0,1,0,0,1e-3,0,0,0,1.5,0,0\n", t, z,
                       uz);
  }
  std::ofstream(dir / "summary.json") << R"({"case": "synthetic", "motion": "free", "equivalent_diameter": 0.015,
  "terminal_vertical_velocity": 0.036, "reference": "tenCate2002_E1"})";
  std::ofstream(dir / "case.resolved.toml") << "[fluid]\ndensity = 970.0\ndynamic_viscosity = 0.373\n"
                                               "gravity = [0.0, 0.0, -9.81]\n\n"
                                               "[particle]\nshape = \"sphere\"\ndiameter = 0.015\ndensity = 1120.0\n"
                                               "motion = \"free\"\n\n"
                                               "[domain]\nsize = [0.1, 0.1, 0.16]\nfollow_particle = false\n";
  return dir;
}

TEST(PlotCli, ReferenceNamedByTheRunIsDrawnAndAgreesWithItself) {
  SKIP_WITHOUT_MATPLOTLIB();
  const ReferenceSeries reference = tencate_e1();
  const fs::path run = write_reference_run("plot_reference", reference);
  const Result r = run_plot(run.string());  // no --reference: summary.json names tenCate2002_E1
  ASSERT_EQ(r.status, 0) << r.err;
  for (const char* figure : kFigures) expect_figure(run / "plots" / figure, r.out);
  expect_figure(run / "plots" / "reference.png", r.out);

  // The run holds each reference value exactly at its time, so the measured differences vanish:
  // u_z is compared as is, the gap as (z - d/2) / d, which undoes z = (gap + 1/2) d to round-off
  // (1e-15 of a gap of 8).
  EXPECT_NEAR(printed_number(r.err, R"(u_z: rms difference ([-0-9.e+]+) m/s)"), 0.0, 1e-12);
  EXPECT_NEAR(printed_number(r.err, R"(gap/d: rms difference ([-0-9.e+]+),)"), 0.0, 1e-12);
  // Every reference point lies inside the run's time span and is compared.
  EXPECT_EQ(printed_number(r.err, R"(u_z: .*\((\d+) reference points?\))"),
            static_cast<double>(reference.velocity.size()));
  EXPECT_EQ(printed_number(r.err, R"(gap/d: .*\((\d+) reference points?\))"),
            static_cast<double>(reference.trajectory.size()));
  // Fluid, particle and size are those of E1: no mismatch is reported.
  EXPECT_EQ(r.err.find("differs"), std::string::npos) << r.err;
  fs::remove_all(run);
}

// A run stopped by a full disk leaves timeseries.csv with its last row cut mid-number: numpy
// refused the table ("the number of columns changed from 29 to 16"). The cut row is left out with
// a note, and the figures of the whole rows are drawn.
TEST(PlotCli, ACutLastRowIsLeftOutWithANote) {
  SKIP_WITHOUT_MATPLOTLIB();
  const fs::path run = write_reference_run("plot_cut_row", tencate_e1());
  std::ofstream(run / "timeseries.csv", std::ios::app) << "1.5,0.05,0.05,0.0123,0,0,-0.03";
  const Result r = run_plot(run.string());
  ASSERT_EQ(r.status, 0) << r.err;
  EXPECT_NE(r.err.find("its last row is incomplete"), std::string::npos) << r.err;
  for (const char* figure : kFigures) expect_figure(run / "plots" / figure, r.out);
  fs::remove_all(run);
}

TEST(PlotCli, ExplicitReferenceWinsAndAMismatchedCaseIsReported) {
  SKIP_WITHOUT_MATPLOTLIB();
  const fs::path run = write_reference_run("plot_reference_e2", tencate_e1());
  const fs::path out = scratch("plot_reference_e2_figures");
  const Result r = run_plot(run.string() + " --reference tenCate2002_E2 -o " + out.string());
  ASSERT_EQ(r.status, 0) << r.err;
  expect_figure(out / "reference.png", r.out);
  EXPECT_FALSE(fs::exists(run / "plots"));  // -o moves every figure
  // E2 is a different silicone oil (0.212 Pa s, 965 kg/m^3) from the run's E1 fluid.
  EXPECT_NE(r.err.find("the case differs from tenCate2002_E2"), std::string::npos) << r.err;
  EXPECT_NE(r.err.find("dynamic viscosity 0.373 vs 0.212 Pa s"), std::string::npos) << r.err;
  fs::remove_all(run);
  fs::remove_all(out);
}

TEST(PlotCli, UnknownReferenceKeyExitsTwoNamingIt) {
  SKIP_WITHOUT_MATPLOTLIB();
  const fs::path run = write_reference_run("plot_reference_unknown", tencate_e1());
  const Result r = run_plot(run.string() + " --reference tenCate2002_E9");
  EXPECT_EQ(r.status, 2);
  EXPECT_NE(r.err.find("--reference: 'tenCate2002_E9'"), std::string::npos) << r.err;
  EXPECT_NE(r.err.find("tenCate2002_E1"), std::string::npos) << r.err;  // the keys that do work
  EXPECT_FALSE(fs::exists(run / "plots"));                              // refused before drawing
  fs::remove_all(run);
}

TEST(PlotCli, MissingRunDirExitsTwoNamingIt) {
  const fs::path missing = scratch("plot_no_such_run");
  const Result r = run_plot(missing.string());
  EXPECT_EQ(r.status, 2);
  EXPECT_NE(r.err.find("RUN_DIR"), std::string::npos) << r.err;
  EXPECT_NE(r.err.find(missing.string()), std::string::npos) << r.err;
}

TEST(PlotCli, DirectoryWithoutTimeseriesExitsTwoNamingIt) {
  const fs::path empty = scratch("plot_empty_run");
  fs::create_directories(empty);
  const Result r = run_plot(empty.string());
  EXPECT_EQ(r.status, 2);
  EXPECT_NE(r.err.find(empty.string()), std::string::npos) << r.err;
  EXPECT_NE(r.err.find("timeseries.csv"), std::string::npos) << r.err;
  fs::remove_all(empty);
}

}  // namespace test_plot_cli
