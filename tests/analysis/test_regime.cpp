// Regime classification (analysis/regime.hpp): each regime built analytically as a synthetic
// motion and recognised by the whole analysis, and the rules' thresholds checked on either side.
#include <cmath>
#include <string>

#include <gtest/gtest.h>

#include "analysis/observables.hpp"
#include "analysis/regime.hpp"
#include "synthetic_motion.hpp"

namespace test_regime {

using namespace settle::analysis;
using settle::test::kDegree;
using settle::test::kPi;
using settle::test::Motion;
using settle::test::rotation;
using settle::test::sample_motion;

constexpr double kSpeed = 0.1;  // m/s, mean settling speed of every motion below

Analysis analyse_motion(const Motion& motion, const ParticleProperties& properties, double t_end = 6.0,
                        double dt = 0.002) {
  return analyse(sample_motion(motion, dt, t_end), properties);
}

// A planar swing of the disk's axis by amplitude A about y, with the lateral velocity B cos(w t)
// along x and the vertical velocity oscillating at 2w (the zigzag of Ern et al. 2012, Fig. 1).
Motion planar_swing(double amplitude, double lateral, double frequency) {
  const double w = 2.0 * kPi * frequency;
  Motion m;
  m.velocity = [=](double t) {
    return Eigen::Vector3d(lateral * std::cos(w * t), 0.0, -kSpeed * (1.0 + 0.05 * std::sin(2.0 * w * t)));
  };
  m.attitude = [=](double t) { return rotation(amplitude * std::sin(w * t), Eigen::Vector3d::UnitY()); };
  m.omega_n = [=](double t) { return Eigen::Vector3d(0.0, amplitude * w * std::cos(w * t), 0.0); };
  return m;
}

TEST(Regimes, SteadyVerticalSphere) {
  Motion m;
  m.velocity = [](double) { return Eigen::Vector3d(0.0, 0.0, -kSpeed); };
  const Analysis a = analyse_motion(m, settle::test::sphere_in_water(1e-3));
  EXPECT_EQ(a.regime.regime, Regime::steady_vertical) << a.regime.reason;
}

TEST(Regimes, SteadyObliqueSphere) {
  // Constant lateral velocity 9% of the vertical one: a path 5.1 degrees from vertical.
  Motion m;
  m.velocity = [](double) { return Eigen::Vector3d(0.006, 0.0067, -kSpeed); };
  const Analysis a = analyse_motion(m, settle::test::sphere_in_water(1e-3));
  EXPECT_EQ(a.regime.regime, Regime::steady_oblique) << a.regime.reason;
}

TEST(Regimes, ObliqueOscillatingSphere) {
  // Drift of 10% of the speed along x with a 3% oscillation along it: the lateral velocity never
  // reverses (Jenny et al. 2004's oscillating oblique regime).
  Motion m;
  m.velocity = [](double t) { return Eigen::Vector3d(0.01 + 0.003 * std::sin(2.0 * kPi * 4.0 * t), 0.0, -kSpeed); };
  const Analysis a = analyse_motion(m, settle::test::sphere_in_water(1e-3));
  EXPECT_EQ(a.regime.regime, Regime::oblique_oscillating) << a.regime.reason;
}

// An oblique path has no preferred azimuth, so its plane may turn slowly (Uhlmann and Dusek's
// case C at 32 cells turns from one azimuth to another, fastest half-way). The lateral fluctuation
// is measured in axes that follow the drift's azimuth smoothed by a cubic in time, so a steady
// drift of 10% of the speed whose plane turns by 90 degrees along a cubic (slowly, then faster,
// then slowly) has no fluctuation to round-off; in fixed axes its chord would read as a lateral
// oscillation of several percent of the speed. 1e-6 of the drift is far above round-off and far
// below the 1% steadiness threshold.
TEST(Regimes, SteadyObliqueSphereWhosePlaneTurns) {
  const double drift = 0.01, turn = 0.5 * kPi, end = 6.0;
  Motion m;
  m.velocity = [=](double t) {
    const double s = t / end, azimuth = turn * s * s * (3.0 - 2.0 * s);
    return Eigen::Vector3d(drift * std::cos(azimuth), drift * std::sin(azimuth), -kSpeed);
  };
  const Analysis a = analyse_motion(m, settle::test::sphere_in_water(1e-3), end);
  EXPECT_EQ(a.regime.regime, Regime::steady_oblique) << a.regime.reason;
  EXPECT_LT(a.lateral_amplitude_si, 1e-6 * drift);
}

// An oscillation that reverses the lateral velocity about a slightly oblique mean path (drift 3%,
// swing 20% of the speed) has no drift direction to follow: it is judged in fixed axes, a zigzag
// of amplitude 0.02 m/s. The window holds c = 12 or more periods, not whole, so sqrt(2) x rms is
// within 1/(4 pi c) + 1/(pi c)^2 of the amplitude (ZigzagDiskSwingsLittle), under 3%.
TEST(Regimes, ZigzagAboutAnObliquePathIsJudgedInFixedAxes) {
  const double swing = 0.02;
  Motion m;
  m.velocity = [=](double t) { return Eigen::Vector3d(0.003 + swing * std::sin(2.0 * kPi * 3.0 * t), 0.0, -kSpeed); };
  const Analysis a = analyse_motion(m, settle::test::sphere_in_water(1e-3));
  EXPECT_GE(a.path_angle_deg, 1.0);  // oblique by the regime's measure
  EXPECT_EQ(a.regime.regime, Regime::zigzag) << a.regime.reason;
  EXPECT_NEAR(a.lateral_amplitude_si, swing, 0.03 * swing);
}

// A drift of 10% of the speed turning uniformly at 25 deg/s with a 3% oscillation at 4 Hz along
// it: oblique_oscillating at 4 Hz. The oscillation changes the drift's size, not its azimuth, so
// the cubic that the drift axes follow is the azimuth itself and the oscillation is a pure tone
// along one axis; amplitude and frequency are then off only by the window's partial periods, well
// under the 1% tolerance.
TEST(Regimes, ObliqueOscillatingSphereWhosePlaneTurns) {
  const double rate = 25.0 * kDegree, frequency_hz = 4.0, oscillation = 0.003;
  Motion m;
  m.velocity = [=](double t) {
    const double size = 0.01 + oscillation * std::sin(2.0 * kPi * frequency_hz * t);
    return Eigen::Vector3d(size * std::cos(rate * t), size * std::sin(rate * t), -kSpeed);
  };
  const Analysis a = analyse_motion(m, settle::test::sphere_in_water(1e-3));
  EXPECT_EQ(a.regime.regime, Regime::oblique_oscillating) << a.regime.reason;
  EXPECT_NEAR(a.lateral_amplitude_si, oscillation, 0.01 * oscillation);
  ASSERT_TRUE(a.lateral_frequency_hz.has_value());
  EXPECT_NEAR(*a.lateral_frequency_hz, frequency_hz, 0.01 * frequency_hz);
}

TEST(Regimes, ZigzagSphereHasNoAxis) {
  Motion m;
  m.velocity = [](double t) { return Eigen::Vector3d(0.0, 0.02 * std::sin(2.0 * kPi * 3.0 * t), -kSpeed); };
  const Analysis a = analyse_motion(m, settle::test::sphere_in_water(1e-3));
  EXPECT_EQ(a.regime.regime, Regime::zigzag) << a.regime.reason;
}

TEST(Regimes, ZigzagDiskSwingsLittle) {
  const Analysis a = analyse_motion(planar_swing(8.0 * kDegree, 0.02, 3.0), settle::test::disk_in_water());
  EXPECT_EQ(a.regime.regime, Regime::zigzag) << a.regime.reason;
  // sqrt(2) x rms of A sin over c periods, c not whole: the mean of sin^2 is off 1/2 by up to
  // 1/(4 pi c) and the removed mean is up to 1/(pi c), so A is found to 1/(4 pi c) + 1/(pi c)^2.
  const double periods = 3.0 * (a.window_end_si - a.window_start_si);
  ASSERT_TRUE(a.tilt_amplitude_deg.has_value());
  EXPECT_NEAR(*a.tilt_amplitude_deg, 8.0, 8.0 * (1.0 / (4.0 * kPi * periods) + 1.0 / std::pow(kPi * periods, 2)));
}

TEST(Regimes, FlutteringDiskSwingsWide) {
  const Analysis a = analyse_motion(planar_swing(45.0 * kDegree, 0.06, 2.0), settle::test::disk_in_water());
  EXPECT_EQ(a.regime.regime, Regime::fluttering) << a.regime.reason;
}

TEST(Regimes, SpiralDiskPrecessesRoundTheVertical) {
  // The lateral velocity turns round the vertical at constant magnitude and the tilted axis
  // precesses with it: attitude Rz(w t) Ry(beta), inertial angular velocity w z.
  const double w = 2.0 * kPi * 2.5, beta = 15.0 * kDegree, lateral = 0.02;
  Motion m;
  m.velocity = [=](double t) { return Eigen::Vector3d(lateral * std::cos(w * t), lateral * std::sin(w * t), -kSpeed); };
  m.attitude = [=](double t) {
    return Eigen::Matrix3d(rotation(w * t, Eigen::Vector3d::UnitZ()) * rotation(beta, Eigen::Vector3d::UnitY()));
  };
  m.omega_n = [=](double) { return Eigen::Vector3d(0.0, 0.0, w); };
  const Analysis a = analyse_motion(m, settle::test::disk_in_water());
  EXPECT_EQ(a.regime.regime, Regime::spiral) << a.regime.reason;
  // A circle traversed one way has circularity 1 and an axis always beta from vertical. The
  // window holds a non-whole number c of turns, so its mean velocity and mean axis are off
  // centre by up to 1/(pi c) of the radius; that lowers the circularity by about
  // 1/(2 pi^2 c^2) and tilts the mean axis by up to tan(beta)/(pi c): the bounds below carry a
  // factor 2 and 1 respectively.
  const double turns = 2.5 * (a.window_end_si - a.window_start_si);
  EXPECT_GT(a.lateral_circularity, 1.0 - 1.0 / (kPi * kPi * turns * turns));
  EXPECT_LE(a.lateral_circularity, 1.0 + 1e-12);
  EXPECT_NEAR(a.tilt_mean_deg, 15.0, 1e-9);
  ASSERT_TRUE(a.mean_axis_tilt_deg.has_value());
  EXPECT_LT(*a.mean_axis_tilt_deg, std::tan(beta) / (kPi * turns) / kDegree);
}

TEST(Regimes, TumblingDiskTurnsOverAndOver) {
  const double omega = 10.0;
  Motion m;
  m.velocity = [=](double t) { return Eigen::Vector3d(0.05 + 0.02 * std::cos(2.0 * omega * t), 0.0, -kSpeed); };
  m.attitude = [=](double t) { return rotation(omega * t, Eigen::Vector3d::UnitY()); };
  m.omega_n = [=](double) { return Eigen::Vector3d(0.0, omega, 0.0); };
  const Analysis a = analyse_motion(m, settle::test::disk_in_water());
  EXPECT_EQ(a.regime.regime, Regime::tumbling) << a.regime.reason;
}

TEST(Regimes, BroadbandLateralMotionIsChaotic) {
  // Forty tones of incommensurate frequencies between 0.5 and 10 Hz in each horizontal
  // component, each 0.3% of the speed: no spectral peak stands out.
  const std::vector<double> phase = settle::test::phases(80, 2024);
  Motion m;
  m.velocity = [=](double t) {
    Eigen::Vector3d u(0.0, 0.0, -kSpeed);
    for (int k = 0; k < 40; ++k) {
      const double f = 0.5 + 0.2437 * k;
      u.x() += 3e-4 * std::sin(2.0 * kPi * f * t + phase[k]);
      u.y() += 3e-4 * std::sin(2.0 * kPi * 1.013 * f * t + phase[40 + k]);
    }
    return u;
  };
  const Analysis a = analyse_motion(m, settle::test::sphere_in_water(1e-3), 20.0, 0.005);
  EXPECT_EQ(a.regime.regime, Regime::chaotic) << a.regime.reason;
  EXPECT_LT(a.lateral_peak.concentration, 0.2);
}

TEST(Regimes, DiskStillTurningBroadsideIsNotClassified) {
  // Steady velocity, but the axis still turns slowly and steadily (1 degree per second): the
  // tilt's unsteadiness is a linear drift, not a regime.
  Motion m;
  m.velocity = [](double) { return Eigen::Vector3d(0.0, 0.0, -kSpeed); };
  m.attitude = [](double t) { return rotation((60.0 + 1.0 * t) * kDegree, Eigen::Vector3d::UnitY()); };
  m.omega_n = [](double) { return Eigen::Vector3d(0.0, kDegree, 0.0); };
  const Analysis a = analyse_motion(m, settle::test::disk_in_water());
  EXPECT_EQ(a.regime.regime, Regime::not_classified) << a.regime.reason;
  EXPECT_NE(a.regime.reason.find("still drifting"), std::string::npos) << a.regime.reason;
  EXPECT_NEAR(a.tilt_trend_fraction, 1.0, 1e-9);  // a straight line, fitted exactly
}

// A swing of the disk's axis about y whose amplitude decays as exp(-t / tau) from A0, at a
// steady velocity: a body coming to rest at its final attitude after its velocity has settled.
Motion decaying_swing(double initial_amplitude, double time_constant, double frequency) {
  const double w = 2.0 * kPi * frequency;
  const auto angle = [=](double t) { return initial_amplitude * std::exp(-t / time_constant) * std::sin(w * t); };
  Motion m;
  m.velocity = [](double) { return Eigen::Vector3d(0.0, 0.0, -kSpeed); };
  m.attitude = [=](double t) { return rotation(angle(t), Eigen::Vector3d::UnitY()); };
  m.omega_n = [=](double t) {
    const double rate =
        initial_amplitude * std::exp(-t / time_constant) * (w * std::cos(w * t) - std::sin(w * t) / time_constant);
    return Eigen::Vector3d(0.0, rate, 0.0);
  };
  return m;
}

TEST(Regimes, SwingDyingAwayIsJudgedAfterIt) {
  // 20 degrees decaying with tau = 0.5 s at 2.2 Hz: over the whole window (from about 0.1 s to
  // 6 s) the tilt amplitude is about 3 degrees, a "zigzag" if the decay were ignored; its later
  // half is at rest to within 20 exp(-6) = 0.05 degrees.
  const Analysis a = analyse_motion(decaying_swing(20.0 * kDegree, 0.5, 2.2), settle::test::disk_in_water());
  EXPECT_EQ(a.regime.regime, Regime::steady_vertical) << a.regime.reason;
  EXPECT_GT(a.regime_window_start_si, a.window_start_si + 0.25 * (a.window_end_si - a.window_start_si));
  ASSERT_TRUE(a.tilt_amplitude_deg.has_value());
  EXPECT_LT(*a.tilt_amplitude_deg, 0.1);
}

TEST(Regimes, SlowlyDecayingSwingKeepsItsRegimeAndItsDecayRatio) {
  // tau = 10 s over a window of about 5.9 s: the later half's amplitude is exp(-T / (2 tau)),
  // about 0.75 of the earlier half's, above the 0.5 that makes an oscillation a transient. With
  // 6.5 periods in each half the sin^2 means of the halves are off 1/2 by up to 1/(4 pi 6.5),
  // 1.2% each; 3% covers both halves.
  const Analysis a = analyse_motion(decaying_swing(8.0 * kDegree, 10.0, 2.2), settle::test::disk_in_water());
  EXPECT_EQ(a.regime.regime, Regime::zigzag) << a.regime.reason;
  EXPECT_EQ(a.regime_window_start_si, a.window_start_si);
  const double span = a.window_end_si - a.window_start_si;
  EXPECT_NEAR(a.tilt_decay_ratio, std::exp(-span / (2.0 * 10.0)), 0.03 * std::exp(-span / 20.0));
}

// ------------------------------------------------------------------ the rules, on their thresholds
RegimeEvidence steady_sphere() {
  RegimeEvidence e;
  e.classifiable = true;
  return e;
}

RegimeEvidence periodic_disk(double tilt_amplitude_deg, double circularity) {
  RegimeEvidence e;
  e.classifiable = true;
  e.has_axis = true;
  e.lateral_amplitude_ratio = 0.2;
  e.lateral_concentration = 0.9;
  e.lateral_cycles = 10.0;
  e.lateral_circularity = circularity;
  e.tilt_amplitude_deg = tilt_amplitude_deg;
  return e;
}

TEST(RegimeRules, ThresholdsSeparateTheRegimes) {
  const RegimeThresholds th;
  RegimeEvidence e = steady_sphere();
  e.lateral_amplitude_ratio = 0.99 * th.steady_lateral_amplitude;
  EXPECT_EQ(classify_regime(e).regime, Regime::steady_vertical);
  e.path_angle_deg = 1.01 * th.oblique_path_angle_deg;
  EXPECT_EQ(classify_regime(e).regime, Regime::steady_oblique);
  e.lateral_amplitude_ratio = 1.01 * th.steady_lateral_amplitude;  // now unsteady, no spectrum
  EXPECT_EQ(classify_regime(e).regime, Regime::chaotic);

  EXPECT_EQ(classify_regime(periodic_disk(19.9, 0.0)).regime, Regime::zigzag);
  EXPECT_EQ(classify_regime(periodic_disk(20.1, 0.0)).regime, Regime::fluttering);
  EXPECT_EQ(classify_regime(periodic_disk(5.0, 0.79)).regime, Regime::zigzag);
  EXPECT_EQ(classify_regime(periodic_disk(5.0, 0.81)).regime, Regime::spiral);

  RegimeEvidence few_periods = periodic_disk(5.0, 0.0);
  few_periods.lateral_cycles = 1.9;
  EXPECT_EQ(classify_regime(few_periods).regime, Regime::not_classified);
  RegimeEvidence drifting = periodic_disk(5.0, 0.0);
  drifting.lateral_trend_fraction = 0.91;
  EXPECT_EQ(classify_regime(drifting).regime, Regime::not_classified);
  drifting.lateral_trend_fraction = 0.89;
  EXPECT_EQ(classify_regime(drifting).regime, Regime::zigzag);
  RegimeEvidence broadband = periodic_disk(5.0, 0.0);
  broadband.lateral_concentration = 0.49;
  EXPECT_EQ(classify_regime(broadband).regime, Regime::chaotic);

  // Only the tilt oscillates: its spectrum decides.
  RegimeEvidence rocking = periodic_disk(5.0, 0.0);
  rocking.lateral_amplitude_ratio = 0.0;
  rocking.lateral_concentration = 0.0;
  rocking.tilt_concentration = 0.9;
  rocking.tilt_cycles = 10.0;
  EXPECT_EQ(classify_regime(rocking).regime, Regime::zigzag);
  EXPECT_FALSE(is_decaying(rocking));

  // ... and whether it dies away: a transient is not a regime (analyse() then judges the window's
  // later part; here, with no later part, it stays not classified).
  rocking.tilt_decay_ratio = 0.98 * th.decaying_max_amplitude_ratio;
  EXPECT_TRUE(is_decaying(rocking));
  EXPECT_EQ(classify_regime(rocking).regime, Regime::not_classified);
  rocking.tilt_decay_ratio = 1.02 * th.decaying_max_amplitude_ratio;
  EXPECT_FALSE(is_decaying(rocking));
  EXPECT_EQ(classify_regime(rocking).regime, Regime::zigzag);
  // A steady window never decays: the rule applies to unsteady signals only.
  RegimeEvidence quiet = steady_sphere();
  quiet.tilt_decay_ratio = 0.1;
  quiet.lateral_decay_ratio = 0.1;
  EXPECT_FALSE(is_decaying(quiet));
  EXPECT_EQ(classify_regime(quiet).regime, Regime::steady_vertical);
}

TEST(RegimeRules, TumblingNeedsHalfATurnOneWayAboutANearHorizontalAxis) {
  RegimeEvidence e = periodic_disk(60.0, 0.0);
  e.axis_net_rotation = -1.01 * kPi;
  e.axis_rotation_monotonicity = 0.81;
  e.axis_rotation_elevation_deg = 29.0;
  EXPECT_EQ(classify_regime(e).regime, Regime::tumbling);
  RegimeEvidence short_turn = e;
  short_turn.axis_net_rotation = 0.99 * kPi;
  EXPECT_EQ(classify_regime(short_turn).regime, Regime::fluttering);
  RegimeEvidence back_and_forth = e;
  back_and_forth.axis_rotation_monotonicity = 0.79;
  EXPECT_EQ(classify_regime(back_and_forth).regime, Regime::fluttering);
  RegimeEvidence steep_axis = e;
  steep_axis.axis_rotation_elevation_deg = 31.0;
  EXPECT_EQ(classify_regime(steep_axis).regime, Regime::fluttering);
  RegimeEvidence no_axis = e;
  no_axis.has_axis = false;
  EXPECT_EQ(classify_regime(no_axis).regime, Regime::zigzag);
}

TEST(RegimeRules, ObliqueOscillationNeedsADriftLargerThanTheOscillation) {
  RegimeEvidence e = periodic_disk(5.0, 0.0);
  e.path_angle_deg = 5.0;
  e.lateral_drift_ratio = 0.21;  // > lateral amplitude 0.2
  EXPECT_EQ(classify_regime(e).regime, Regime::oblique_oscillating);
  e.lateral_drift_ratio = 0.19;
  EXPECT_EQ(classify_regime(e).regime, Regime::zigzag);
}

TEST(RegimeRules, UnclassifiableWindowKeepsItsReason) {
  RegimeEvidence e;
  e.not_classifiable_reason = "too short";
  const RegimeResult r = classify_regime(e);
  EXPECT_EQ(r.regime, Regime::not_classified);
  EXPECT_EQ(r.reason, "too short");
  EXPECT_EQ(regime_name(Regime::not_classified), "not classified");
  EXPECT_EQ(regime_name(Regime::oblique_oscillating), "oblique_oscillating");
}

}  // namespace test_regime
