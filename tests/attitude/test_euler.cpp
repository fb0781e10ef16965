// Checks of Eqs. (S1)-(S12) of Cheng et al. (2023), doi:10.1063/5.0165555 (supplementary
// material): the written-out matrices and rate maps against their definitions, and the
// conversion between the two Euler sets through the matrix.
#include <algorithm>
#include <array>
#include <cmath>
#include <cstdio>
#include <limits>
#include <numbers>
#include <random>
#include <vector>

#include <gtest/gtest.h>
#include <Eigen/Geometry>

#include "attitude/attitude.hpp"
#include "attitude/euler.hpp"

namespace settle::attitude {
namespace test_euler {

constexpr double pi = std::numbers::pi;

double max_abs_difference(const Eigen::Matrix3d& a, const Eigen::Matrix3d& b) { return (a - b).cwiseAbs().maxCoeff(); }

/// Angles uniform in [-pi, pi] for all three (every quadrant of every angle).
std::vector<Eigen::Vector3d> random_angles(int count, unsigned seed) {
  std::mt19937_64 generator(seed);
  std::uniform_real_distribution<double> angle(-pi, pi);
  std::vector<Eigen::Vector3d> result;
  for (int i = 0; i < count; ++i) result.emplace_back(angle(generator), angle(generator), angle(generator));
  return result;
}

TEST(EulerMatrices, Set1WrittenOutEqualsElementaryProduct) {
  for (const Eigen::Vector3d& a : random_angles(1000, 1)) {
    const Eigen::Matrix3d product =
        (elementary_gamma(a[2]) * elementary_theta(a[1]) * elementary_psi(a[0])).transpose();
    // Both sides are sums of at most three products of unit-size sines and cosines: a few
    // ulps (~1e-15) of difference at most; 1e-13 leaves a hundredfold margin.
    EXPECT_LT(max_abs_difference(set1_body_to_inertial(a), product), 1e-13);
  }
}

TEST(EulerMatrices, Set2WrittenOutEqualsElementaryProduct) {
  for (const Eigen::Vector3d& a : random_angles(1000, 2)) {
    // Set 2 angles are (psi_r, theta_r, gamma_r); the sequence psi_r -> gamma_r -> theta_r.
    const Eigen::Matrix3d product =
        (elementary_theta(a[1]) * elementary_gamma(a[2]) * elementary_psi(a[0])).transpose();
    // Same rounding argument as for set 1.
    EXPECT_LT(max_abs_difference(set2_body_to_inertial(a), product), 1e-13);
  }
}

TEST(EulerMatrices, ElementaryRotationsArePassiveAxisRotations) {
  // C_psi is the frame rotation about z: its transpose is Eigen's active rotation.
  const double angle = 0.7;
  // Two independent evaluations of the same cosines and sines: agreement to a few ulps.
  EXPECT_LT(max_abs_difference(elementary_psi(angle).transpose(),
                               Eigen::AngleAxisd(angle, Eigen::Vector3d::UnitZ()).toRotationMatrix()),
            1e-15);
  EXPECT_LT(max_abs_difference(elementary_theta(angle).transpose(),
                               Eigen::AngleAxisd(angle, Eigen::Vector3d::UnitY()).toRotationMatrix()),
            1e-15);
  EXPECT_LT(max_abs_difference(elementary_gamma(angle).transpose(),
                               Eigen::AngleAxisd(angle, Eigen::Vector3d::UnitX()).toRotationMatrix()),
            1e-15);
}

// The forward maps (S6 and its set-2 counterpart) checked against the kinematics itself:
// [omega_b]x = (C_b^n)^T d(C_b^n)/dt, with the time derivative by central differences.
template <typename MatrixOf, typename ForwardMap>
void check_forward_map_against_matrix_derivative(MatrixOf matrix_of, ForwardMap forward, unsigned seed) {
  std::mt19937_64 generator(seed);
  std::uniform_real_distribution<double> rate(-2.0, 2.0);
  const double h = 1e-5;
  for (const Eigen::Vector3d& a : random_angles(200, seed)) {
    const Eigen::Vector3d angle_rates(rate(generator), rate(generator), rate(generator));
    const Eigen::Matrix3d derivative =
        (matrix_of(Eigen::Vector3d(a + h * angle_rates)) - matrix_of(Eigen::Vector3d(a - h * angle_rates))) / (2.0 * h);
    const Eigen::Matrix3d skew = matrix_of(a).transpose() * derivative;
    const Eigen::Vector3d omega(skew(2, 1), skew(0, 2), skew(1, 0));
    // Central-difference truncation h^2/6 |R'''| <= 1e-10/6 * 6^3 ~ 4e-9 for rates up to
    // 2 rad/s per angle, plus rounding eps/h ~ 1e-11: 1e-8 separates that from any wrong term
    // (a wrong sign or factor would be O(1)).
    EXPECT_LT((forward(a, angle_rates) - omega).cwiseAbs().maxCoeff(), 1e-8);
    EXPECT_LT(std::abs(skew(0, 1) + skew(1, 0)), 1e-8);  // skew-symmetric, same bound
  }
}

TEST(EulerRates, Set1ForwardMapMatchesMatrixKinematics) {
  check_forward_map_against_matrix_derivative(
      [](const Eigen::Vector3d& a) { return set1_body_to_inertial(a); },
      [](const Eigen::Vector3d& a, const Eigen::Vector3d& r) { return set1_body_rates(a, r); }, 3);
}

TEST(EulerRates, Set2ForwardMapMatchesMatrixKinematics) {
  check_forward_map_against_matrix_derivative(
      [](const Eigen::Vector3d& a) { return set2_body_to_inertial(a); },
      [](const Eigen::Vector3d& a, const Eigen::Vector3d& r) { return set2_body_rates(a, r); }, 4);
}

template <typename Inverse, typename Forward>
void check_inverse_rate_map(Inverse inverse, Forward forward, int singular_index, unsigned seed) {
  std::mt19937_64 generator(seed);
  std::uniform_real_distribution<double> value(-3.0, 3.0);
  int checked = 0;
  for (const Eigen::Vector3d& a : random_angles(2000, seed)) {
    // Stay where the maps are usable: |cos| >= 0.1 for the angle they are singular in.
    if (std::abs(std::cos(a[singular_index])) < 0.1) continue;
    const Eigen::Vector3d rates(value(generator), value(generator), value(generator));
    const Eigen::Vector3d omega(value(generator), value(generator), value(generator));
    // Rounding of O(10) unit-size terms divided by |cos| >= 0.1: ~1e-14 for values up to 3;
    // 1e-12 leaves a hundredfold margin.
    EXPECT_LT((inverse(a, forward(a, rates)) - rates).cwiseAbs().maxCoeff(), 1e-12);
    EXPECT_LT((forward(a, inverse(a, omega)) - omega).cwiseAbs().maxCoeff(), 1e-12);
    ++checked;
  }
  EXPECT_GT(checked, 1500);
}

TEST(EulerRates, S7InvertsSet1ForwardMap) {
  check_inverse_rate_map([](const Eigen::Vector3d& a, const Eigen::Vector3d& w) { return set1_angle_rates(a, w); },
                         [](const Eigen::Vector3d& a, const Eigen::Vector3d& r) { return set1_body_rates(a, r); }, 1,
                         5);
}

TEST(EulerRates, S9InvertsSet2ForwardMap) {
  check_inverse_rate_map([](const Eigen::Vector3d& a, const Eigen::Vector3d& w) { return set2_angle_rates(a, w); },
                         [](const Eigen::Vector3d& a, const Eigen::Vector3d& r) { return set2_body_rates(a, r); }, 2,
                         6);
}

// The seed's conversion formulas (S11/S12) with two-argument arctangents and clamped arcsines
// (docs/architecture.md, "Frames and attitude"; docs/attitude.md), used only to print how much the
// robust forms gain.
Eigen::Vector3d seed_set1_angles(const Eigen::Matrix3d& z) {
  return {std::atan2(z(1, 0), z(0, 0)), -std::asin(std::clamp(z(2, 0), -1.0, 1.0)), std::atan2(z(2, 1), z(2, 2))};
}
Eigen::Vector3d seed_set2_angles(const Eigen::Matrix3d& z) {
  return {std::atan2(-z(0, 1), z(1, 1)), std::atan2(-z(2, 0), z(2, 2)), std::asin(std::clamp(z(2, 1), -1.0, 1.0))};
}

/// Largest matrix error of set 1 -> matrix -> set 2 -> matrix -> set 1 -> matrix.
template <typename ToSet1, typename ToSet2>
double round_trip_error(const Eigen::Vector3d& set1, ToSet1 to_set1, ToSet2 to_set2) {
  const Eigen::Matrix3d original = set1_body_to_inertial(set1);
  const Eigen::Matrix3d via_set2 = set2_body_to_inertial(to_set2(original));
  const Eigen::Matrix3d via_set1 = set1_body_to_inertial(to_set1(via_set2));
  const double error = std::max(max_abs_difference(via_set2, original), max_abs_difference(via_set1, original));
  return std::isnan(error) ? std::numeric_limits<double>::infinity() : error;
}

double round_trip_error(const Eigen::Vector3d& set1) {
  return round_trip_error(
      set1, [](const Eigen::Matrix3d& z) { return set1_angles_from_matrix(z); },
      [](const Eigen::Matrix3d& z) { return set2_angles_from_matrix(z); });
}

double seed_round_trip_error(const Eigen::Vector3d& set1) {
  return round_trip_error(set1, seed_set1_angles, seed_set2_angles);
}

/// Set 1 -> matrix -> set 2 -> matrix -> set 1 -> matrix; every matrix must be the first.
void expect_round_trip(const Eigen::Vector3d& set1, double tolerance) {
  EXPECT_LT(round_trip_error(set1), tolerance) << set1.transpose();
}

TEST(EulerConversion, RoundTripAllQuadrants) {
  double worst = 0.0, seed_worst = 0.0;
  for (const Eigen::Vector3d& a : random_angles(100000, 7)) {
    worst = std::max(worst, round_trip_error(a));  // round_trip_error maps NaN to infinity
    seed_worst = std::max(seed_worst, seed_round_trip_error(a));
  }
  std::printf("[measured] round trip, 1e5 random angle triples: %.3g (seed formulas: %.3g)\n", worst, seed_worst);
  // Three conversions, each a few atan2/sin/cos (1-ulp functions) on unit-size values:
  // ~1e-15 expected; 1e-14 leaves a factor of ten.
  EXPECT_LT(worst, 1e-14);
}

TEST(EulerConversion, RoundTripAtSingularPoints) {
  const std::array<double, 9> others{-pi, -2.5, -pi / 2, -0.3, 0.0, 0.4, pi / 2, 2.9, pi};
  for (double psi : others) {
    for (double gamma : others) {
      // Set-1 singularity (theta = +-pi/2): only psi -+ gamma is defined; the matrix must
      // still be reproduced. Same bound as the regular round trip.
      expect_round_trip({psi, pi / 2, gamma}, 1e-14);
      expect_round_trip({psi, -pi / 2, gamma}, 1e-14);
      // Set-2 singularity gamma_r = +-pi/2, i.e. set 1 with theta = 0 or pi, gamma = +-pi/2.
      expect_round_trip({psi, 0.0, pi / 2}, 1e-14);
      expect_round_trip({psi, 0.0, -pi / 2}, 1e-14);
      expect_round_trip({psi, pi, gamma > 0 ? pi / 2 : -pi / 2}, 1e-14);
    }
  }
}

TEST(EulerConversion, RoundTripFromSet2AtItsSingularPoint) {
  const std::array<double, 7> others{-pi, -2.0, -0.5, 0.0, 1.0, 2.5, pi};
  for (double psi_r : others) {
    for (double theta_r : others) {
      for (double gamma_r : {pi / 2, -pi / 2}) {
        const Eigen::Matrix3d original = set2_body_to_inertial({psi_r, theta_r, gamma_r});
        const Eigen::Vector3d set1 = set1_angles_from_matrix(original);
        const Eigen::Vector3d set2 = set2_angles_from_matrix(set1_body_to_inertial(set1));
        // Two conversions of unit-size values: bound as in the round trips above.
        EXPECT_LT(max_abs_difference(set2_body_to_inertial(set2), original), 1e-14);
        // z31 and z33 are rounding noise (~1e-16) here, so gamma_r sits within ~1e-16 of pi/2.
        EXPECT_NEAR(std::abs(set2[2]), pi / 2, 1e-14);
      }
    }
  }
}

TEST(EulerConversion, NearSingularPointKeepsFullPrecision) {
  // Within 1e-9 rad of the singular angle the seed's arcsine returns the singular angle
  // itself (sin rounds to exactly +-1), an error of ~1e-9 in the matrix (printed below for
  // the seed formulas); the two-argument form used here keeps the round trip at
  // rounding level.
  for (double offset : {1e-6, 1e-9, 1e-12}) {
    double worst = 0.0, seed_worst = 0.0;
    for (double sign : {1.0, -1.0}) {
      for (const Eigen::Vector3d& a : {Eigen::Vector3d(0.8, sign * (pi / 2 - offset), -1.9),  // set-1 near-singular
                                       Eigen::Vector3d(-2.2, 0.0, sign * (pi / 2 - offset)),  // set-2 near-singular
                                       Eigen::Vector3d(0.3, offset, sign * (pi / 2 - offset))}) {
        worst = std::max(worst, round_trip_error(a));
        seed_worst = std::max(seed_worst, seed_round_trip_error(a));
      }
    }
    std::printf("[measured] round trip %.0e rad from the singular angle: %.3g (seed formulas: %.3g)\n", offset, worst,
                seed_worst);
    // Rounding level, as for the regular round trip.
    EXPECT_LT(worst, 1e-14);
  }
}

TEST(EulerConversion, SingularMatricesBuiltElsewhereAreReproduced) {
  // Gimbal-locked matrices computed another way (Eigen's axis-angle products, as the
  // quaternion integrator produces them) carry rounding noise in every entry the seed's
  // outer-angle formulas read; two separate arctangents of that noise rebuild a matrix that
  // is wrong by O(1) (printed below: 2). The remainder-based outer angle must reproduce it.
  using Eigen::AngleAxisd;
  double seed_worst = 0.0;
  for (double outer = -3.0; outer < 3.0; outer += 0.37) {
    for (double inner = -3.0; inner < 3.0; inner += 0.41) {
      for (double sign : {1.0, -1.0}) {
        const Eigen::Matrix3d set1_locked =
            (AngleAxisd(outer, Eigen::Vector3d::UnitZ()) * AngleAxisd(sign * pi / 2, Eigen::Vector3d::UnitY()) *
             AngleAxisd(inner, Eigen::Vector3d::UnitX()))
                .toRotationMatrix();
        const Eigen::Matrix3d set2_locked =
            (AngleAxisd(outer, Eigen::Vector3d::UnitZ()) * AngleAxisd(sign * pi / 2, Eigen::Vector3d::UnitX()) *
             AngleAxisd(inner, Eigen::Vector3d::UnitY()))
                .toRotationMatrix();
        // Rounding level of unit-size entries (measured 9e-16).
        EXPECT_LT(max_abs_difference(set1_body_to_inertial(set1_angles_from_matrix(set1_locked)), set1_locked), 1e-14);
        EXPECT_LT(max_abs_difference(set2_body_to_inertial(set2_angles_from_matrix(set2_locked)), set2_locked), 1e-14);
        seed_worst =
            std::max({seed_worst, max_abs_difference(set1_body_to_inertial(seed_set1_angles(set1_locked)), set1_locked),
                      max_abs_difference(set2_body_to_inertial(seed_set2_angles(set2_locked)), set2_locked)});
      }
    }
  }
  std::printf("[measured] gimbal-locked matrices: seed formulas rebuild them with error %.3g\n", seed_worst);
}

TEST(EulerConversion, RegularAnglesAreRecovered) {
  // Away from the singular points the conversions return the canonical angles themselves.
  std::mt19937_64 generator(9);
  std::uniform_real_distribution<double> outer(-3.1, 3.1), middle(-1.5, 1.5);
  for (int i = 0; i < 1000; ++i) {
    const Eigen::Vector3d set1(outer(generator), middle(generator), outer(generator));
    // Conditioning 1/cos(middle) <= 1/cos(1.5) ~ 14 times a few ulps: < 1e-13.
    EXPECT_LT((set1_angles_from_matrix(set1_body_to_inertial(set1)) - set1).cwiseAbs().maxCoeff(), 1e-13);
    const Eigen::Vector3d set2(outer(generator), outer(generator), middle(generator));
    EXPECT_LT((set2_angles_from_matrix(set2_body_to_inertial(set2)) - set2).cwiseAbs().maxCoeff(), 1e-13);
  }
}

TEST(EulerConversion, MatchesSeedClosedFormsAwayFromSingularities) {
  // S11 and S12 in terms of the other set's angles (the seed's right-hand forms), evaluated
  // with the quadrant-correct atan2. Valid for |theta| < pi/2, |gamma| < pi/2 (set 1) and
  // |theta_r| < pi/2, |gamma_r| < pi/2 (set 2), where cos > 0 lets atan2 of the ratios' terms agree.
  std::mt19937_64 generator(10);
  std::uniform_real_distribution<double> psi(-3.1, 3.1), small(-1.4, 1.4);
  for (int i = 0; i < 500; ++i) {
    const double ps = psi(generator), th = small(generator), ga = small(generator);
    const Eigen::Vector3d set2 = set2_angles_from_matrix(set1_body_to_inertial({ps, th, ga}));
    const double theta_r = std::atan2(std::tan(th), std::cos(ga));
    const double gamma_r = std::asin(std::cos(th) * std::sin(ga));
    const double psi_r = std::atan2(std::sin(ps) * std::cos(ga) - std::cos(ps) * std::sin(th) * std::sin(ga),
                                    std::cos(ps) * std::cos(ga) + std::sin(ps) * std::sin(th) * std::sin(ga));
    // Different but equivalent formulas with conditioning <= 1/cos(1.4) ~ 6: < 1e-13.
    EXPECT_NEAR(set2[1], theta_r, 1e-13);
    EXPECT_NEAR(set2[2], gamma_r, 1e-13);
    EXPECT_NEAR(set2[0], psi_r, 1e-13);

    const Eigen::Vector3d set1 = set1_angles_from_matrix(set2_body_to_inertial({ps, th, ga}));
    const double gamma = std::atan2(std::tan(ga), std::cos(th));
    const double theta = std::asin(std::sin(th) * std::cos(ga));
    const double psi_1 = std::atan2(std::cos(th) * std::sin(ps) + std::sin(th) * std::sin(ga) * std::cos(ps),
                                    std::cos(th) * std::cos(ps) - std::sin(th) * std::sin(ga) * std::sin(ps));
    EXPECT_NEAR(set1[2], gamma, 1e-13);
    EXPECT_NEAR(set1[1], theta, 1e-13);
    EXPECT_NEAR(set1[0], psi_1, 1e-13);
  }
}

TEST(EulerAngles, WrapAngle) {
  EXPECT_DOUBLE_EQ(wrap_angle(0.5), 0.5);
  EXPECT_DOUBLE_EQ(wrap_angle(pi), pi);
  EXPECT_DOUBLE_EQ(wrap_angle(-pi), pi);  // (-pi, pi]: -pi maps to pi
  // 2 pi is not exact in binary: wrapping a multiple costs one rounding of 2 pi (~1e-15).
  EXPECT_NEAR(wrap_angle(0.5 + 6.0 * pi), 0.5, 1e-14);
  EXPECT_NEAR(wrap_angle(-0.5 - 4.0 * pi), -0.5, 1e-14);
}

// Curated edge cases (identity, tiny angles, near pi, exactly +-pi/2 pitch) through the
// Attitude type: matrix, quaternion and both charts must describe one rotation.
struct EdgeCase {
  const char* name;
  Eigen::Vector3d set1;
};

std::vector<EdgeCase> edge_cases() {
  return {{"identity", {0.0, 0.0, 0.0}},
          {"tiny", {1e-8, -1e-8, 1e-8}},
          {"near pi", {pi - 1e-9, 1e-9 - pi, pi - 2e-9}},
          {"half turn", {pi, 0.0, 0.0}},
          {"pitch +pi/2", {0.3, pi / 2, -0.8}},
          {"pitch -pi/2", {-2.0, -pi / 2, 2.7}},
          {"roll pi/2 (set-2 singular)", {1.1, 0.0, pi / 2}}};
}

TEST(AttitudeEdgeCases, MatrixQuaternionAndChartsAgree) {
  for (const EdgeCase& c : edge_cases()) {
    SCOPED_TRACE(c.name);
    const Attitude a = Attitude::from_set1(c.set1[0], c.set1[1], c.set1[2]);
    const Eigen::Matrix3d r = a.body_to_inertial();
    // Orthonormal with det +1: products of exact-to-1-ulp sines and cosines, ~1e-16.
    EXPECT_LT(max_abs_difference(r.transpose() * r, Eigen::Matrix3d::Identity()), 1e-15);
    EXPECT_NEAR(r.determinant(), 1.0, 1e-15);
    // Quaternion composed from axis rotations versus the written-out matrix: a few ulps.
    EXPECT_LT(max_abs_difference(a.quaternion().toRotationMatrix(), r), 1e-15);
    EXPECT_NEAR(a.quaternion().norm(), 1.0, 1e-15);
    // The other chart and back (rounding bound of the round trips above).
    const Attitude other = a.in_set(EulerSet::set2);
    EXPECT_EQ(other.set(), EulerSet::set2);
    EXPECT_LT(max_abs_difference(other.body_to_inertial(), r), 1e-14);
    EXPECT_LT(max_abs_difference(other.in_set(EulerSet::set1).body_to_inertial(), r), 1e-14);
    // From the quaternion back to a chart.
    EXPECT_LT(max_abs_difference(Attitude::from_quaternion(a.quaternion()).body_to_inertial(), r), 1e-14);
  }
}

TEST(AttitudeEdgeCases, TinyAnglesAreRecoveredToRelativePrecision) {
  const Attitude a = Attitude::from_set1(1e-8, -2e-8, 3e-8);
  const Eigen::Vector3d back = set1_angles_from_matrix(a.body_to_inertial());
  // Matrix entries of size 1e-8 carry the angles to ~1e-16 relative; the conversion
  // combines a few of them: 1e-22 absolute is 1e-14 relative for these angles.
  EXPECT_NEAR(back[0], 1e-8, 1e-22);
  EXPECT_NEAR(back[1], -2e-8, 1e-22);
  EXPECT_NEAR(back[2], 3e-8, 1e-22);
}

TEST(AttitudeEdgeCases, RotationByNearlyPiAboutGenericAxis) {
  const Eigen::Vector3d axis = Eigen::Vector3d(1.0, -2.0, 0.5).normalized();
  for (double angle : {pi, pi - 1e-9, pi - 1e-5}) {
    const Eigen::Matrix3d r = Eigen::AngleAxisd(angle, axis).toRotationMatrix();
    const Attitude a = Attitude::from_matrix(r);
    // Conversion of a unit-size orthonormal matrix and back: rounding level.
    EXPECT_LT(max_abs_difference(a.body_to_inertial(), r), 1e-14);
    EXPECT_LT(max_abs_difference(a.quaternion().toRotationMatrix(), r), 1e-14);
    EXPECT_GE(a.quaternion().w(), 0.0);
  }
}

TEST(AttitudeSwitchingRule, BoundariesFollowTheSeed) {
  // Set 1 while |theta| <= pi/4 or |theta| > 3pi/4 (theta wrapped into (-pi, pi]).
  EXPECT_EQ(preferred_set_for_pitch(0.0), EulerSet::set1);
  EXPECT_EQ(preferred_set_for_pitch(pi / 4), EulerSet::set1);
  EXPECT_EQ(preferred_set_for_pitch(-pi / 4), EulerSet::set1);
  EXPECT_EQ(preferred_set_for_pitch(std::nextafter(pi / 4, 1.0)), EulerSet::set2);
  EXPECT_EQ(preferred_set_for_pitch(pi / 2), EulerSet::set2);
  EXPECT_EQ(preferred_set_for_pitch(-pi / 2), EulerSet::set2);
  EXPECT_EQ(preferred_set_for_pitch(3 * pi / 4), EulerSet::set2);
  EXPECT_EQ(preferred_set_for_pitch(std::nextafter(3 * pi / 4, 4.0)), EulerSet::set1);
  EXPECT_EQ(preferred_set_for_pitch(pi), EulerSet::set1);
  EXPECT_EQ(preferred_set_for_pitch(2 * pi + 0.1), EulerSet::set1);
  EXPECT_EQ(preferred_set_for_pitch(4.0), EulerSet::set2);  // 4 - 2pi = -2.28: |.| in (pi/4, 3pi/4]
}

TEST(AttitudeSwitchingRule, PreferredChartIsFarFromItsSingularity) {
  for (const Eigen::Vector3d& a : random_angles(2000, 11)) {
    const Attitude chart = Attitude::from_matrix(set1_body_to_inertial(a));
    const double middle = chart.set() == EulerSet::set1 ? chart.angles()[1] : chart.angles()[2];
    // The seed's guarantee: the active set's singular angle is at least pi/4 away
    // (allowing rounding of the boundary value itself).
    EXPECT_LE(std::abs(middle), pi / 4 + 1e-15);
  }
}

}  // namespace test_euler
}  // namespace settle::attitude
