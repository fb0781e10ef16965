#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <functional>
#include <numbers>
#include <random>
#include <string>
#include <vector>

#include "attitude/euler.hpp"
#include "common/error.hpp"
#include "coupling/units.hpp"
#include "io/case.hpp"
#include "study/derived_inputs.hpp"

namespace test_derived_inputs {

using namespace settle;

constexpr const char* kTowedSpheroid = R"(
[fluid]
density = 1000.0
dynamic_viscosity = 1.0e-3
[particle]
shape = "spheroid"
diameter = 1.0e-3
aspect_ratio = 2.5
density = 1050.0
motion = "towed"
towing_velocity = [0.0, 0.0, -0.01]
[domain]
size = [6.0e-3, 6.0e-3, 12.0e-3]
)";

constexpr const char* kFreeSphere = R"(
[fluid]
density = 1000.0
dynamic_viscosity = 1.0e-3
[particle]
shape = "sphere"
diameter = 2.0e-3
density = 1500.0
[domain]
size = [6.0e-3, 6.0e-3, 12.0e-3]
)";

Eigen::Vector3d vec(const io::CaseValues& v, const char* key) {
  const auto& r = v.reals(key);
  return {r[0], r[1], r[2]};
}

TEST(DerivedInputs, ReynoldsSetsTheTowingSpeedFromTheEquivalentDiameter) {
  io::CaseValues v = io::load_case_text(kTowedSpheroid, "test");
  study::set_derived_input(v, "reynolds", 50.0, ".");
  // d_eq of a spheroid of equatorial diameter d and aspect ratio 2.5: d 2.5^(1/3).
  const double d_eq = 1.0e-3 * std::cbrt(2.5);
  const Eigen::Vector3d u = vec(v, "particle.towing_velocity");
  EXPECT_NEAR(u.norm(), 50.0 * 1.0e-6 / d_eq, 1e-15);
  EXPECT_NEAR(u.normalized().z(), -1.0, 1e-15);  // the base case's direction kept
}

TEST(DerivedInputs, TravelSetsTheEndTimeFromTheSpeedAndTheEquivalentDiameter) {
  io::CaseValues v = io::load_case_text(kTowedSpheroid, "test");
  study::set_derived_input(v, "travel_diameters", 20.0, ".");
  EXPECT_NEAR(v.real("run.end_time"), 20.0 * 1.0e-3 * std::cbrt(2.5) / 0.01, 1e-14);
  io::CaseValues free_body = io::load_case_text(kFreeSphere, "test");
  EXPECT_THROW(study::set_derived_input(free_body, "travel_diameters", 20.0, "."), InputError);
}

TEST(DerivedInputs, GalileoSetsTheViscosityThatGivesItBack) {
  io::CaseValues v = io::load_case_text(kFreeSphere, "test");
  study::set_derived_input(v, "galileo", 178.46, ".");
  const double nu = v.real("fluid.dynamic_viscosity") / v.real("fluid.density");
  EXPECT_NEAR(coupling::galileo_number(2.0e-3, 1500.0, 1000.0, nu, 9.81), 178.46, 1e-10);
}

TEST(DerivedInputs, IncidenceIsTheAngleBetweenTheAxisAndTheFlow) {
  io::CaseValues v = io::load_case_text(kTowedSpheroid, "test");
  study::set_derived_input(v, "incidence_deg", 30.0, ".");
  const Eigen::Matrix3d r = attitude::set1_body_to_inertial(vec(v, "particle.euler"));
  // The spheroid's axis is body z; the flow is along inertial z.
  EXPECT_NEAR(std::acos(std::abs(r.col(2).z())) * 180.0 / std::numbers::pi, 30.0, 1e-10);
}

TEST(DerivedInputs, RefusesWhatTheBodyCannotTake) {
  io::CaseValues free_body = io::load_case_text(kFreeSphere, "test");
  io::CaseValues towed = io::load_case_text(kTowedSpheroid, "test");
  const auto message = [](auto&& f) {
    try {
      f();
    } catch (const InputError& e) {
      return std::string(e.what());
    }
    return std::string("no error");
  };
  EXPECT_NE(message([&] { study::set_derived_input(free_body, "reynolds", 10.0, "."); }).find("reynolds:"),
            std::string::npos);
  EXPECT_NE(message([&] { study::set_derived_input(towed, "galileo", 10.0, "."); }).find("galileo:"),
            std::string::npos);
  EXPECT_NE(message([&] { study::set_derived_input(towed, "reynolds", -1.0, "."); }).find("not > 0"),
            std::string::npos);
}

// The towed spheroid travels along -z from the window's centre (3, 3, 6) mm; d_eq = d 2.5^(1/3).
// Each window input must move one pair of faces and keep the rest: the other end's distance and
// the body's offset from the axis (a seed of 0.1 mm here).
TEST(DerivedInputs, WindowInputsPlaceTheFacesInEquivalentDiameters) {
  io::CaseValues v = io::load_case_text(kTowedSpheroid, "test");
  v.set("particle.position", io::Value(std::vector<double>{3.1e-3, 3.0e-3, 6.0e-3}), "test");
  const double d_eq = 1.0e-3 * std::cbrt(2.5);
  study::set_derived_input(v, "domain_width_diameters", 8.0, ".");
  EXPECT_NEAR(vec(v, "domain.size").x(), 8.0 * d_eq, 1e-15);
  EXPECT_NEAR(vec(v, "domain.size").y(), 8.0 * d_eq, 1e-15);
  EXPECT_NEAR(vec(v, "particle.position").x(), 4.0 * d_eq + 0.1e-3, 1e-15);
  EXPECT_NEAR(vec(v, "particle.position").y(), 4.0 * d_eq, 1e-15);
  EXPECT_NEAR(vec(v, "domain.size").z(), 12.0e-3, 1e-15);

  study::set_derived_input(v, "domain_ahead_diameters", 3.0, ".");  // ahead = below: the bottom moves
  EXPECT_NEAR(vec(v, "particle.position").z(), 3.0 * d_eq, 1e-15);
  EXPECT_NEAR(vec(v, "domain.size").z() - vec(v, "particle.position").z(), 6.0e-3, 1e-15);
  study::set_derived_input(v, "domain_behind_diameters", 10.0, ".");  // behind = above: the top moves
  EXPECT_NEAR(vec(v, "particle.position").z(), 3.0 * d_eq, 1e-15);
  EXPECT_NEAR(vec(v, "domain.size").z(), 13.0 * d_eq, 1e-15);
}

// Travelling up, ahead is above: a fixed body in an inflow from below (the flow comes from z-, so
// the body's front faces down) and a free body lighter than the fluid (it rises).
TEST(DerivedInputs, WindowEndsFollowTheDirectionOfTravel) {
  io::CaseValues fixed = io::load_case_text(kTowedSpheroid, "test");
  fixed.set("particle.motion", io::Value(std::string("fixed")), "test");
  fixed.set("domain.inflow_velocity", io::Value(std::vector<double>{0.0, 0.0, 0.02}), "test");
  const double d_eq = 1.0e-3 * std::cbrt(2.5);
  study::set_derived_input(fixed, "domain_ahead_diameters", 4.0, ".");
  EXPECT_NEAR(vec(fixed, "particle.position").z(), 4.0 * d_eq, 1e-15);

  io::CaseValues rising = io::load_case_text(kFreeSphere, "test");
  rising.set("particle.density", io::Value(800.0), "test");
  study::set_derived_input(rising, "domain_ahead_diameters", 2.0, ".");  // d_eq = d = 2 mm
  EXPECT_NEAR(vec(rising, "particle.position").z(), 6.0e-3, 1e-15);
  EXPECT_NEAR(vec(rising, "domain.size").z(), 10.0e-3, 1e-15);
}

TEST(DerivedInputs, WindowInputsNeedTravelAlongZ) {
  io::CaseValues sideways = io::load_case_text(kTowedSpheroid, "test");
  sideways.set("particle.towing_velocity", io::Value(std::vector<double>{0.01, 0.0, 0.0}), "test");
  try {
    study::set_derived_input(sideways, "domain_width_diameters", 6.0, ".");
    FAIL() << "a body towed along x was given a window width";
  } catch (const InputError& e) {
    EXPECT_NE(std::string(e.what()).find("domain_width_diameters: the body travels along"), std::string::npos);
  }
  io::CaseValues towed = io::load_case_text(kTowedSpheroid, "test");
  EXPECT_THROW(study::set_derived_input(towed, "domain_behind_diameters", 0.0, "."), InputError);
}

// Kolmogorov-Smirnov statistic of samples against a continuous CDF.
double ks_statistic(std::vector<double> x, const std::function<double(double)>& cdf) {
  std::sort(x.begin(), x.end());
  double d = 0.0;
  const double n = static_cast<double>(x.size());
  for (std::size_t i = 0; i < x.size(); ++i)
    d = std::max(
        {d, std::abs(cdf(x[i]) - static_cast<double>(i) / n), std::abs(cdf(x[i]) - static_cast<double>(i + 1) / n)});
  return d;
}

// Uniform on SO(3): the image of a fixed axis is uniform on the sphere (its z component uniform on
// [-1, 1]), and the rotation angle w has the CDF (w - sin w) / pi. With 4000 samples the
// Kolmogorov-Smirnov statistic of a correct sampler exceeds 1.63 / sqrt(N) with probability 1%
// (the asymptotic critical value at that level); the seed is fixed, so the test is deterministic.
// Euler angles drawn uniformly, the classic mistake, fail the same test (checked below), so the
// test can fail.
constexpr int kSamples = 4000;
const double kCritical = 1.63 / std::sqrt(static_cast<double>(kSamples));

double axis_z_cdf(double z) { return (z + 1.0) / 2.0; }
double angle_cdf(double w) { return (w - std::sin(w)) / std::numbers::pi; }

void statistics(const std::vector<Eigen::Quaterniond>& q, double& axis_d, double& angle_d) {
  std::vector<double> z, w;
  for (const auto& r : q) {
    z.push_back((r * Eigen::Vector3d::UnitZ()).z());
    w.push_back(2.0 * std::acos(std::min(1.0, std::abs(r.w()))));
  }
  axis_d = ks_statistic(z, axis_z_cdf);
  angle_d = ks_statistic(w, angle_cdf);
}

TEST(UniformRotations, PassTheKolmogorovSmirnovTestsOfTheHaarMeasure) {
  const auto q = study::uniform_rotations(kSamples, 20261126);
  ASSERT_EQ(q.size(), static_cast<std::size_t>(kSamples));
  for (const auto& r : q) ASSERT_NEAR(r.norm(), 1.0, 1e-14);
  double axis_d = 0, angle_d = 0;
  statistics(q, axis_d, angle_d);
  EXPECT_LT(axis_d, kCritical);
  EXPECT_LT(angle_d, kCritical);

  std::vector<Eigen::Quaterniond> euler;  // psi, theta, gamma uniform: not uniform rotations
  std::mt19937_64 engine(7);
  const auto uniform = [&engine] { return static_cast<double>(engine() >> 11) * 0x1.0p-53; };
  for (int i = 0; i < kSamples; ++i) {
    const double psi = std::numbers::pi * (2 * uniform() - 1), theta = std::numbers::pi * (uniform() - 0.5);
    euler.emplace_back(attitude::set1_body_to_inertial({psi, theta, std::numbers::pi * (2 * uniform() - 1)}));
  }
  statistics(euler, axis_d, angle_d);
  EXPECT_GT(std::max(axis_d, angle_d), kCritical);
}

TEST(UniformRotations, TheSameSeedGivesTheSameRotations) {
  const auto a = study::uniform_rotations(5, 42), b = study::uniform_rotations(5, 42),
             c = study::uniform_rotations(5, 43);
  for (int i = 0; i < 5; ++i) {
    EXPECT_EQ(a[i].coeffs(), b[i].coeffs());
    EXPECT_NE(a[i].coeffs(), c[i].coeffs());
  }
}

}  // namespace test_derived_inputs
