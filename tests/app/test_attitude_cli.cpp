// Case tests of `settle attitude`: the real binary (SETTLE_BINARY) on small runs, checked
// against closed forms, the CSV contract (docs/architecture.md, "Contracts"), and its handling of bad input.
#include <sys/wait.h>
#include <unistd.h>

#include <cmath>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <map>
#include <sstream>
#include <string>
#include <vector>

#include <gtest/gtest.h>
#include <Eigen/Geometry>

#include "cli_support.hpp"

namespace test_attitude_cli {

namespace fs = std::filesystem;

const std::vector<std::string> expected_columns{
    "t",   "wx",  "wy",  "wz",  "psi", "theta", "gamma", "psi_r", "theta_r", "gamma_r", "euler_set",
    "R11", "R12", "R13", "R21", "R22", "R23",   "R31",   "R32",   "R33",     "energy",  "angular_momentum"};

using settle::test::read_text;
using settle::test::scratch;
using Result = settle::test::CliResult;

Result run_settle(const std::string& arguments) { return settle::test::run_settle("attitude", arguments); }

struct Table {
  std::vector<std::string> header;
  std::vector<std::map<std::string, double>> rows;
};

Table parse_csv(const std::string& text) {
  Table table;
  std::istringstream lines(text);
  std::string line;
  std::getline(lines, line);
  std::istringstream names(line);
  for (std::string name; std::getline(names, name, ',');) table.header.push_back(name);
  while (std::getline(lines, line)) {
    std::istringstream fields(line);
    std::map<std::string, double> row;
    std::size_t column = 0;
    for (std::string field; std::getline(fields, field, ',') && column < table.header.size(); ++column) {
      row[table.header[column]] = std::stod(field);
    }
    table.rows.push_back(row);
  }
  return table;
}

Eigen::Matrix3d matrix_of(const std::map<std::string, double>& row) {
  // Names spelt out: building them with operator+ trips GCC 12's false -Wrestrict (PR 105651).
  static const char* const names[3][3] = {{"R11", "R12", "R13"}, {"R21", "R22", "R23"}, {"R31", "R32", "R33"}};
  Eigen::Matrix3d r;
  for (int i = 0; i < 3; ++i) {
    for (int j = 0; j < 3; ++j) r(i, j) = row.at(names[i][j]);
  }
  return r;
}

Eigen::Matrix3d set1_matrix(double psi, double theta, double gamma) {
  return (Eigen::AngleAxisd(psi, Eigen::Vector3d::UnitZ()) * Eigen::AngleAxisd(theta, Eigen::Vector3d::UnitY()) *
          Eigen::AngleAxisd(gamma, Eigen::Vector3d::UnitX()))
      .toRotationMatrix();
}

TEST(AttitudeCli, SphericalTopFollowsClosedForm) {
  // Isotropic inertia: omega_b is constant and C_b^n(t) = C_b^n(0) Rot(omega, |omega| t).
  const Result r = run_settle(
      "--inertia 2,2,2 --omega 0.1,-0.2,0.5 --euler 0.2,0.3,0.4 --dt 0.01 --t-end 10 "
      "--output-every 100");
  ASSERT_EQ(r.status, 0) << r.err;
  const Table table = parse_csv(r.out);
  EXPECT_EQ(table.header, expected_columns);
  ASSERT_EQ(table.rows.size(), 11U);  // t = 0, 1, ..., 10
  const Eigen::Vector3d omega(0.1, -0.2, 0.5);
  const Eigen::Matrix3d start = set1_matrix(0.2, 0.3, 0.4);
  for (const auto& row : table.rows) {
    const double t = row.at("t");
    const Eigen::Matrix3d exact = start * Eigen::AngleAxisd(omega.norm() * t, omega.normalized()).toRotationMatrix();
    // RK4 on the angles at |omega| dt = 5.5e-3: error ~ t |omega|^5 dt^4 ~ 5e-10 at most
    // (measured far smaller); the CSV's 17 digits add nothing visible.
    EXPECT_LT((matrix_of(row) - exact).cwiseAbs().maxCoeff(), 1e-10) << "t = " << t;
    // The set-1 and set-2 columns describe the same matrix (conversion at rounding level;
    // 1e-13 allows for the CSV's decimal round trip).
    EXPECT_LT((set1_matrix(row.at("psi"), row.at("theta"), row.at("gamma")) - matrix_of(row)).cwiseAbs().maxCoeff(),
              1e-13);
    const Eigen::Matrix3d set2 = (Eigen::AngleAxisd(row.at("psi_r"), Eigen::Vector3d::UnitZ()) *
                                  Eigen::AngleAxisd(row.at("gamma_r"), Eigen::Vector3d::UnitX()) *
                                  Eigen::AngleAxisd(row.at("theta_r"), Eigen::Vector3d::UnitY()))
                                     .toRotationMatrix();
    EXPECT_LT((set2 - matrix_of(row)).cwiseAbs().maxCoeff(), 1e-13);
    // Energy 0.5 I |omega|^2 and |L| = I |omega|, constant: rounding level.
    EXPECT_NEAR(row.at("energy"), 0.5 * 2.0 * omega.squaredNorm(), 1e-14);
    EXPECT_NEAR(row.at("angular_momentum"), 2.0 * omega.norm(), 1e-14);
    EXPECT_TRUE(row.at("euler_set") == 1.0 || row.at("euler_set") == 2.0);
  }
  EXPECT_NE(r.err.find("set switches"), std::string::npos);
}

TEST(AttitudeCli, MethodsAgreeThroughIntermediateAxisFlips) {
  const std::string args = "--inertia 1,2,3 --omega 0.01,1,0.01 --dt 1e-3 --t-end 40 --output-every 4000";
  const Result dual = run_settle(args);
  const Result quaternion = run_settle(args + " --method quaternion");
  ASSERT_EQ(dual.status, 0) << dual.err;
  ASSERT_EQ(quaternion.status, 0) << quaternion.err;
  const Table a = parse_csv(dual.out), b = parse_csv(quaternion.out);
  ASSERT_EQ(a.rows.size(), 11U);
  ASSERT_EQ(b.rows.size(), a.rows.size());
  for (std::size_t i = 0; i < a.rows.size(); ++i) {
    // The library test measures 5e-14 between the two methods on this case; 1e-10 is the
    // bound beyond which one of them is wrong, not merely rounded.
    EXPECT_LT((matrix_of(a.rows[i]) - matrix_of(b.rows[i])).cwiseAbs().maxCoeff(), 1e-10);
    // The quaternion run reports the set the rule would pick: the same as the solver's.
    EXPECT_EQ(a.rows[i].at("euler_set"), b.rows[i].at("euler_set"));
  }
  // 24 switches in 40 time units (library test); the summary reports them.
  EXPECT_NE(dual.err.find("24 set switches"), std::string::npos) << dual.err;
}

TEST(AttitudeCli, RateSeriesReconstructsConstantRotation) {
  const fs::path csv = scratch("rates.csv");
  std::ofstream(csv) << "t,wx,wy,wz\n0,0,0.8,0\n2.5,0,0.8,0\n5,0,0.8,0\n";
  const Result r = run_settle("--inertia 1,1,1 --omega-file " + csv.string() + " --dt 0.003 --t-end 5 -o " +
                              scratch("out.csv").string());
  ASSERT_EQ(r.status, 0) << r.err;
  const Table table = parse_csv(read_text(scratch("out.csv")));
  fs::remove(csv);
  fs::remove(scratch("out.csv"));
  ASSERT_EQ(table.rows.size(), 1668U);  // ceil(5 / 0.003) = 1667 steps, the last shortened
  const auto& last = table.rows.back();
  EXPECT_DOUBLE_EQ(last.at("t"), 5.0);
  // From the identity about body y: theta = 0.8 t through +-pi/2, RK4 exact up to rounding.
  const Eigen::Matrix3d exact = Eigen::AngleAxisd(4.0, Eigen::Vector3d::UnitY()).toRotationMatrix();
  EXPECT_LT((matrix_of(last) - exact).cwiseAbs().maxCoeff(), 1e-12);
}

void expect_rejected(const std::string& arguments, const std::string& flag) {
  const Result r = run_settle(arguments);
  EXPECT_EQ(r.status, 2) << arguments << "\n" << r.err;
  EXPECT_NE(r.err.find(flag), std::string::npos) << arguments << "\n" << r.err;
}

// Body rates of 1e300 rad/s: the energy overflows, and every row after the first was NaN with exit
// status 0. Refused (status 2, the flag named) before anything is written.
TEST(AttitudeCli, RatesWhoseEnergyOverflowsAreRefused) {
  const Result r = run_settle("--inertia 1,2,3 --omega 1e300,1e300,0 --dt 0.01 --t-end 1");
  EXPECT_EQ(r.status, 2) << r.err;
  EXPECT_NE(r.err.find("--omega"), std::string::npos) << r.err;
  EXPECT_EQ(r.out.find("nan"), std::string::npos);
}

// 1e100 rad/s (energy 1.5e200, finite) with dt = 0.01 s: RK4's second stage squares 1e198 and the
// state is NaN after one step. The run stops with status 3 and a message, and every row written is
// finite (the first one, t = 0).
TEST(AttitudeCli, AStateThatIsNoLongerFiniteStopsTheRun) {
  for (const char* method : {"dual-euler", "quaternion"}) {
    const Result r =
        run_settle(std::string("--inertia 1,2,3 --omega 1e100,1e100,0 --dt 0.01 --t-end 0.05 --method ") + method);
    EXPECT_EQ(r.status, 3) << method << ": " << r.err;
    EXPECT_NE(r.err.find("no longer finite"), std::string::npos) << r.err;
    EXPECT_NE(r.err.find("--dt"), std::string::npos) << r.err;
    EXPECT_EQ(r.out.find("nan"), std::string::npos) << r.out;
    EXPECT_EQ(r.out.find("inf"), std::string::npos) << r.out;
  }
}

TEST(AttitudeCli, BadInputExitsWithStatus2NamingTheFlag) {
  const std::string run = " --dt 0.1 --t-end 1";
  expect_rejected("--inertia 1,2 --omega 0,0,1" + run, "--inertia");
  expect_rejected("--inertia 0,1,1 --omega 0,0,1" + run, "--inertia");
  expect_rejected("--inertia 1,2,4 --omega 0,0,1" + run, "--inertia");  // triangle inequality
  expect_rejected("--omega 0,0,1" + run, "--inertia");                  // missing
  expect_rejected("--inertia 1,1,1 --omega 0,0" + run, "--omega");
  expect_rejected("--inertia 1,1,1" + run, "--omega");
  expect_rejected("--inertia 1,1,1 --omega 0,0,1 --euler 0,x,0" + run, "--euler");
  expect_rejected("--inertia 1,1,1 --omega 0,0,1 --dt 0 --t-end 1", "--dt");
  expect_rejected("--inertia 1,1,1 --omega 0,0,1 --dt -1 --t-end 1", "--dt");
  expect_rejected("--inertia 1,1,1 --omega 0,0,1 --dt 0.1 --t-end -2", "--t-end");
  expect_rejected("--inertia 1,1,1 --omega 0,0,1 --method euler" + run, "--method");
  expect_rejected("--inertia 1,1,1 --omega 0,0,1 --output-every 0" + run, "--output-every");
  expect_rejected("--inertia 1,1,1 --omega-file /nonexistent/settle.csv" + run, "--omega-file");

  const fs::path csv = scratch("bad.csv");
  std::ofstream(csv) << "t,wx,wy,wz\n0,0,0,1\n0.5,0,0,1\n0.4,0,0,1\n";
  expect_rejected("--inertia 1,1,1 --omega-file " + csv.string() + run, "--omega-file");  // not monotonic
  std::ofstream(csv) << "t,wx,wy,wz\n0,0,0,1\n0.5,0,0\n";
  expect_rejected("--inertia 1,1,1 --omega-file " + csv.string() + run, "--omega-file");  // malformed row
  std::ofstream(csv) << "t,wx,wy,wz\n0,0,0,1\n0.5,0,0,1\n";
  expect_rejected("--inertia 1,1,1 --omega-file " + csv.string() + run, "--omega-file");  // ends before t_end
  fs::remove(csv);
}

}  // namespace test_attitude_cli
