// Attitude reconstruction from a sampled body-rate series (the standalone use of the
// dual-Euler solver, Cheng et al. 2023, doi:10.1063/5.0165555, supplementary material).
#include <unistd.h>
#include <algorithm>
#include <cmath>
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <string>
#include <vector>

#include <gtest/gtest.h>
#include <Eigen/Geometry>

#include "attitude/attitude.hpp"
#include "attitude/body_rate_series.hpp"
#include "attitude/integrators.hpp"
#include "common/error.hpp"

namespace settle::attitude {
namespace test_body_rate_series {

std::string write_temp_csv(const std::string& name, const std::string& text) {
  const auto path =
      std::filesystem::temp_directory_path() / ("settle_attitude_" + std::to_string(::getpid()) + "_" + name + ".csv");
  std::ofstream(path) << text;
  return path.string();
}

TEST(BodyRateSeries, InterpolatesLinearly) {
  const BodyRateSeries series({0.0, 1.0, 3.0}, {Eigen::Vector3d(0.0, 1.0, 2.0), Eigen::Vector3d(1.0, 1.0, 0.0),
                                                Eigen::Vector3d(3.0, -1.0, 0.0)});
  // Linear interpolation of exactly representable values: exact to rounding (1 ulp).
  EXPECT_LT((series.at(0.0) - Eigen::Vector3d(0.0, 1.0, 2.0)).norm(), 1e-15);
  EXPECT_LT((series.at(0.25) - Eigen::Vector3d(0.25, 1.0, 1.5)).norm(), 1e-15);
  EXPECT_LT((series.at(1.0) - Eigen::Vector3d(1.0, 1.0, 0.0)).norm(), 1e-15);
  EXPECT_LT((series.at(2.0) - Eigen::Vector3d(2.0, 0.0, 0.0)).norm(), 1e-15);
  EXPECT_LT((series.at(3.0) - Eigen::Vector3d(3.0, -1.0, 0.0)).norm(), 1e-15);
  EXPECT_THROW((void)series.at(-1e-9), std::out_of_range);
  EXPECT_THROW((void)series.at(3.0 + 1e-9), std::out_of_range);
}

TEST(BodyRateSeries, RejectsBadSamples) {
  EXPECT_THROW(BodyRateSeries({0.0}, {Eigen::Vector3d::Zero()}), std::invalid_argument);
  EXPECT_THROW(BodyRateSeries({0.0, 0.0}, {Eigen::Vector3d::Zero(), Eigen::Vector3d::Zero()}), std::invalid_argument);
  EXPECT_THROW(BodyRateSeries({0.0, 1.0}, {Eigen::Vector3d::Zero()}), std::invalid_argument);
}

TEST(BodyRateSeries, ReadsCsv) {
  const std::string path = write_temp_csv("good", "t, wx, wy, wz\r\n0,1,2,3\n\n0.5 , 1e-1,-2,3.5\n1,0,0,0\n");
  const BodyRateSeries series = BodyRateSeries::read_csv(path);
  EXPECT_EQ(series.size(), 3U);
  EXPECT_DOUBLE_EQ(series.end_time(), 1.0);
  EXPECT_LT((series.at(0.5) - Eigen::Vector3d(0.1, -2.0, 3.5)).norm(), 1e-15);  // a sample itself
  std::filesystem::remove(path);
}

void expect_input_error(const std::string& name, const std::string& text, const std::string& fragment) {
  const std::string path = write_temp_csv(name, text);
  try {
    (void)BodyRateSeries::read_csv(path);
    ADD_FAILURE() << name << ": no error";
  } catch (const InputError& e) {
    EXPECT_NE(std::string(e.what()).find(fragment), std::string::npos) << e.what();
    EXPECT_NE(std::string(e.what()).find(path), std::string::npos) << e.what();
  }
  std::filesystem::remove(path);
}

TEST(BodyRateSeries, ReportsMalformedCsv) {
  expect_input_error("header", "time,wx,wy,wz\n0,0,0,0\n1,0,0,0\n", "header");
  expect_input_error("fields", "t,wx,wy,wz\n0,0,0,0\n1,0,0\n", "line 3");
  expect_input_error("number", "t,wx,wy,wz\n0,0,0,0\n1,0,abc,0\n", "'abc'");
  expect_input_error("trailing", "t,wx,wy,wz\n0,0,0,0\n1,0,2x,0\n", "'2x'");
  expect_input_error("order", "t,wx,wy,wz\n0,0,0,0\n1,0,0,0\n1,0,0,0\n", "increase");
  expect_input_error("short", "t,wx,wy,wz\n0,0,0,0\n", "two samples");
  expect_input_error("empty", "", "empty");
  try {
    (void)BodyRateSeries::read_csv("/nonexistent/settle/rates.csv");
    ADD_FAILURE() << "missing file: no error";
  } catch (const InputError& e) {
    EXPECT_NE(std::string(e.what()).find("cannot open"), std::string::npos);
  }
}

// Reconstruction of a known motion (rotation about a fixed body axis with a precessing rate
// vector: the symmetric top's body rates) from samples spaced like the integration step.
// Linear interpolation turns RK4's Simpson weights on the rates into the trapezoidal rule,
// so the reconstruction is second order in the sample spacing.
double reconstruction_error(double spacing) {
  const double spin = 0.9;  // rate at which omega_b precesses about body z
  const Eigen::Vector3d omega0(0.6, -0.4, 1.3);
  const auto omega_b = [&](double t) -> Eigen::Vector3d {
    return Eigen::AngleAxisd(spin * t, Eigen::Vector3d::UnitZ()).toRotationMatrix() * omega0;
  };
  const double t_end = 4.0;
  const auto samples = static_cast<int>(std::lround(t_end / spacing));
  std::vector<double> times;
  std::vector<Eigen::Vector3d> rates;
  for (int i = 0; i <= samples; ++i) {
    times.push_back(i * spacing);
    rates.push_back(omega_b(i * spacing));
  }
  const BodyRateSeries series(times, rates);
  const BodyRateFunction sampled = [&](double t) { return series.at(std::min(t, series.end_time())); };
  Attitude reconstructed = Attitude::from_set1(0.2, 0.3, -0.1);
  Eigen::Quaterniond reference = reconstructed.quaternion();
  const double fine = spacing / 50.0;  // reference: exact rates, RK4 error ~1e-17 per step
  for (int i = 0; i < samples; ++i) dual_euler_step(reconstructed, i * spacing, spacing, sampled);
  for (int i = 0; i < samples * 50; ++i) reference = quaternion_step(reference, i * fine, fine, omega_b);
  return (reconstructed.body_to_inertial() - reference.toRotationMatrix()).cwiseAbs().maxCoeff();
}

TEST(BodyRateSeries, ReconstructionIsSecondOrderInSampleSpacing) {
  const double coarse = reconstruction_error(0.02);
  const double fine = reconstruction_error(0.01);
  const double order = std::log2(coarse / fine);
  std::printf("[measured] reconstruction from samples: errors %.3g %.3g, order %.3f\n", coarse, fine, order);
  // Trapezoidal quadrature of the rates: second order (errors 1e-5 .. 1e-6, far above the
  // reference's own error).
  EXPECT_GT(order, 1.8);
  EXPECT_LT(order, 2.2);
}

}  // namespace test_body_rate_series
}  // namespace settle::attitude
