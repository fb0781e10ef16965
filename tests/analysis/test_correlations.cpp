// Empirical drag laws and the terminal-velocity solver (src/analysis/correlations.hpp) against
// worked values (validation/reference-data.json, key check_values_D, and the fluids library's
// documented example), the laws' own sphere forms, the Stokes closed form, closed-form shape
// descriptors and the force balance itself.
#include <cmath>
#include <fstream>
#include <limits>
#include <map>
#include <numbers>
#include <string>

#include <gtest/gtest.h>
#include <nlohmann/json.hpp>

#include "analysis/correlations.hpp"
#include "attitude/attitude.hpp"
#include "body/cuboid.hpp"
#include "body/cylinder.hpp"
#include "body/ellipsoid.hpp"
#include "body/shape_factors.hpp"
#include "common/error.hpp"
#include "coupling/simulation.hpp"
#include "support/default_setup.hpp"

namespace settle::analysis {
namespace test_correlations {

using nlohmann::json;
using std::numbers::pi;

const json& reference() {
  static const json data = [] {
    std::ifstream file(SETTLE_SOURCE_DIR "/validation/reference-data.json");
    return json::parse(file);
  }();
  return data;
}

const json& check_values(const char* table) { return reference()["check_values_D"]["fields"][table]; }

// The worked values are stored rounded to a fixed number of decimals; a correct implementation
// agrees to half a unit in the last stored place (plus round-off, far smaller).
constexpr double kFiveDecimals = 0.5e-5 * 1.0001;
constexpr double kFourDecimals = 0.5e-4 * 1.0001;

// The fall direction is read by Orientation::initial only.
const Eigen::Vector3d kUnusedFall = Eigen::Vector3d::UnitZ();

std::map<std::string, double> by_law(const std::vector<LawPrediction>& predictions) {
  std::map<std::string, double> speeds;
  for (const auto& p : predictions) speeds[p.law] = p.state.terminal_velocity_si;
  return speeds;
}

const LawPrediction& find(const std::vector<LawPrediction>& predictions, const std::string& law) {
  for (const auto& p : predictions) {
    if (p.law == law) return p;
  }
  throw std::runtime_error("no law " + law);
}

// ------------------------------------------------------------------ worked values

TEST(DragLaws, SphereLawsMatchTheWorkedValues) {
  for (const json& row : check_values("sphere_Cd")) {
    const double re = row["Re"].get<double>();
    EXPECT_NEAR(schiller_naumann_drag(re), row["SchillerNaumann"].get<double>(), kFiveDecimals) << "Re " << re;
    EXPECT_NEAR(clift_grace_weber_drag(re), row["Clift_curve"].get<double>(), kFiveDecimals) << "Re " << re;
    EXPECT_NEAR(haider_levenspiel_drag(re, 1.0), row["HL_general_phi1"].get<double>(), kFiveDecimals) << "Re " << re;
  }
}

TEST(DragLaws, CliftCurveMatchesTheFluidsLibraryExample) {
  // fluids.drag.Clift docstring (CalebBell/fluids): Clift(200) = 0.7756342422322543. Same
  // formula, evaluated by another pow(): agreement to a few ulp.
  EXPECT_NEAR(clift_grace_weber_drag(200.0), 0.7756342422322543, 1e-14);
}

TEST(DragLaws, IsometricCubeMatchesTheWorkedValues) {
  // The worked values use the exact sphericity of a cube, pi^(1/3) 6^(2/3) / 6 = 0.805996 (the
  // table's "phi" is rounded to 3 decimals; with 0.806 itself Ganser's value at Re = 10 rounds
  // differently). Here it comes from settle's cuboid. Ganser's isometric form is d_n = d_v.
  const double phi =
      body::compute_shape_factors(body::Cuboid(Eigen::Vector3d::Ones()), Eigen::Vector3d::UnitZ()).sphericity;
  for (const json& row : check_values("cube_phi_0.806")) {
    const double re = row["Re"].get<double>();
    EXPECT_NEAR(phi, row["phi"].get<double>(), 0.5e-3);
    EXPECT_NEAR(haider_levenspiel_drag(re, phi), row["HL"].get<double>(), kFourDecimals) << "Re " << re;
    EXPECT_NEAR(ganser_drag(re, phi, 1.0), row["Ganser_isometric"].get<double>(), kFourDecimals) << "Re " << re;
  }
}

TEST(DragLaws, HolzerSommerfeldOnAProlateSpheroidMatchesTheWorkedValues) {
  // The worked values use the crosswise sphericity in the Stokes term too (the MFiX/Basilisk
  // variant), so pass it as the lengthwise one. Descriptors from settle's own geometry of a
  // prolate spheroid of aspect ratio 2.5; end-on = fall along the axis.
  const body::Ellipsoid spheroid = body::Ellipsoid::spheroid(1.0, 2.5);
  const body::ShapeFactors end_on = body::compute_shape_factors(spheroid, Eigen::Vector3d::UnitZ());
  const body::ShapeFactors broadside = body::compute_shape_factors(spheroid, Eigen::Vector3d::UnitX());
  for (const json& row : check_values("HS_prolate_2.5")) {
    const double re = row["Re"].get<double>();
    EXPECT_NEAR(end_on.sphericity, row["phi"].get<double>(), kFiveDecimals);
    const double phi = end_on.sphericity;
    const double end = holzer_sommerfeld_drag(re, phi, end_on.crosswise_sphericity, end_on.crosswise_sphericity);
    const double side = holzer_sommerfeld_drag(re, phi, broadside.crosswise_sphericity, broadside.crosswise_sphericity);
    EXPECT_NEAR(end, row["end_on_log10"].get<double>(), kFourDecimals) << "Re " << re;
    EXPECT_NEAR(side, row["broadside_log10"].get<double>(), kFourDecimals) << "Re " << re;
    // The natural-log reading differs by 0.042 (10^(0.4 x^0.2) at two x) / phi_perp = 0.037:
    // far outside the rounding, so this test tells the two log bases apart.
    EXPECT_GT(std::abs(end - row["end_on_ln"].get<double>()), 0.03) << "Re " << re;
  }
}

TEST(DragLaws, BagheriBonadonnaMatchesTheWorkedValues) {
  // Ellipsoids with axes L, I, S (volume ratio d_v^3 / (L I S) = 1), rho_p / rho_f = 2.5.
  for (const json& row : check_values("BagheriBonadonna_rho2.5")) {
    const double l = row["L_I_S"][0].get<double>(), i = row["L_I_S"][1].get<double>(),
                 s = row["L_I_S"][2].get<double>();
    const BagheriBonadonnaFactors k = bagheri_bonadonna_factors(s / i, i / l, 1.0, 2.5);
    EXPECT_NEAR(k.stokes_correction, row["kS"].get<double>(), kFourDecimals);
    EXPECT_NEAR(k.newton_correction, row["kN"].get<double>(), kFourDecimals);
    EXPECT_NEAR(bagheri_bonadonna_drag(row["Re"].get<double>(), k), row["Cd"].get<double>(), kFourDecimals);
  }
}

TEST(DragLaws, DietrichMatchesTheWorkedValues) {
  // Quartz in water as in the worked values: rho_s = 2650, rho = 1000, nu = 1.004e-6, g = 9.81.
  for (const json& row : check_values("Dietrich_quartz")) {
    const SettlingConditions c{1000.0, 1.004e-3, 9.81, 2650.0, row["D_m"].get<double>()};
    const double dstar = archimedes_number(c);
    // D* stored with 3 decimals.
    EXPECT_NEAR(dstar, row["Dstar"].get<double>(), 0.5e-3 * 1.0001);
    const double wstar = dietrich_dimensionless_velocity(dstar, row["CSF"].get<double>(), row["P"].get<double>());
    EXPECT_NEAR(wstar, row["Wstar"].get<double>(), kFiveDecimals);
    const double speed = std::cbrt(wstar * 1650.0 * 9.81 * 1.004e-6 / 1000.0);
    EXPECT_NEAR(speed, row["ws_m_per_s"].get<double>(), 0.5e-6 * 1.0001);  // 6 decimals
  }
}

TEST(Predictions, DietrichThroughTheFullPathMatchesTheWorkedSpeed) {
  // The same grain (D = 1 mm, CSF 0.7, P 3.5) through predict_terminal_velocities: 0.12371 m/s.
  ParticleDescriptors grain;
  grain.equivalent_diameter_si = 1e-3;
  grain.density_si = 2650.0;
  grain.corey_shape_factor = 0.7;
  grain.powers_roundness = 3.5;
  const LawPrediction p = find(predict_terminal_velocities(grain, 1000.0, 1.004e-3, 9.81), "dietrich");
  ASSERT_TRUE(p.state.solved);
  EXPECT_NEAR(p.state.terminal_velocity_si, 0.12371, 0.5e-5 * 1.0001);  // stored with 5 decimals
  EXPECT_TRUE(p.in_range) << p.reason;
}

// At a viscosity of 1e-300 Pa s the Archimedes number D* is infinite and Dietrich's fit has no
// velocity; the reason given was "Corey shape factor 1 <= 0.15" for a sphere (Corey factor 1).
// It must name what failed: D* and W*, and not the shape factor.
TEST(Predictions, DietrichsReasonAtAnExtremeViscosityNamesDStarNotTheShape) {
  const body::Ellipsoid sphere = body::Ellipsoid::sphere(0.002);
  const ParticleDescriptors particle =
      describe_particle(sphere, 2500.0, Orientation::broadside, Eigen::Vector3d::UnitZ());
  for (const double mu : {1e-300, 1e300}) {
    const LawPrediction p = find(predict_terminal_velocities(particle, 998.0, mu, 9.81), "dietrich");
    EXPECT_FALSE(p.state.solved) << mu;
    EXPECT_EQ(p.reason.find("Corey"), std::string::npos) << p.reason;
    EXPECT_NE(p.reason.find("D* = "), std::string::npos) << p.reason;
  }
}

// ------------------------------------------------------------------ sphere limits

TEST(SphereLimits, EachShapeLawReducesToItsOwnSphereForm) {
  // At sphericity 1 (phi = phi_perp = phi_par = 1, d_n = d_v, F_S = F_N = 1, Corey 1, P 6) each
  // paper's correlation becomes its sphere form exactly; only round-off separates them.
  const BagheriBonadonnaFactors round = bagheri_bonadonna_factors(1.0, 1.0, 1.0, 2.65);
  EXPECT_EQ(round.stokes_correction, 1.0);
  EXPECT_EQ(round.newton_correction, 1.0);
  for (double re : {1e-3, 0.1, 1.0, 10.0, 100.0, 1e3, 1e4, 1e5}) {
    const double ganser_sphere = 24.0 / re * (1.0 + 0.1118 * std::pow(re, 0.6567)) + 0.4305 / (1.0 + 3305.0 / re);
    const double hs_sphere = 24.0 / re + 3.0 / std::sqrt(re) + 0.42;
    const double bb_sphere = 24.0 / re * (1.0 + 0.125 * std::pow(re, 2.0 / 3.0)) + 0.46 / (1.0 + 5330.0 / re);
    EXPECT_NEAR(ganser_drag(re, 1.0, 1.0), ganser_sphere, 1e-14 * ganser_sphere) << re;
    EXPECT_NEAR(holzer_sommerfeld_drag(re, 1.0, 1.0, 1.0), hs_sphere, 1e-14 * hs_sphere) << re;
    EXPECT_NEAR(bagheri_bonadonna_drag(re, round), bb_sphere, 1e-14 * bb_sphere) << re;
  }
  // Dietrich: R2 = 0 and R3 = 1 for CSF = 1, P = 6, leaving his sphere curve 10^R1.
  for (double dstar : {0.05, 1.0, 1e3, 1e6, 1e9}) {
    const double x = std::log10(dstar);
    const double r1 = -3.76715 + 1.92944 * x - 0.09815 * x * x - 0.00575 * x * x * x + 0.00056 * x * x * x * x;
    EXPECT_NEAR(dietrich_dimensionless_velocity(dstar, 1.0, 6.0), std::pow(10.0, r1), 1e-14 * std::pow(10.0, r1));
  }
}

TEST(SphereLimits, SphereFormsStayNearTheStandardCurve) {
  // Each law at sphericity 1 against Clift, Grace and Weber's standard curve for 0.01 <= Re <=
  // 1e5. The fits were made to different sphere data and differ among themselves; measured on
  // this grid the largest gaps are Ganser -26% (Re 100), Hoelzer-Sommerfeld +21% (Re 3162),
  // Bagheri-Bonadonna -18% (Re 100), Dietrich +14% (Re 4.3), Haider-Levenspiel +9% (Re 316),
  // Schiller-Naumann +5% (Re 316, up to its limit 800); see docs/correlations.md. The 30% bound
  // accepts that known spread but fails on a wrong coefficient or exponent, which moves a curve
  // by a factor.
  const BagheriBonadonnaFactors round = bagheri_bonadonna_factors(1.0, 1.0, 1.0, 2.65);
  for (double re = 0.01; re <= 1.0001e5; re *= std::sqrt(10.0)) {
    const double standard = clift_grace_weber_drag(re);
    EXPECT_NEAR(haider_levenspiel_drag(re, 1.0) / standard, 1.0, 0.30) << re;
    EXPECT_NEAR(ganser_drag(re, 1.0, 1.0) / standard, 1.0, 0.30) << re;
    EXPECT_NEAR(holzer_sommerfeld_drag(re, 1.0, 1.0, 1.0) / standard, 1.0, 0.30) << re;
    EXPECT_NEAR(bagheri_bonadonna_drag(re, round) / standard, 1.0, 0.30) << re;
    if (re <= 800.0) {
      EXPECT_NEAR(schiller_naumann_drag(re) / standard, 1.0, 0.30) << re;
    }
  }
  // Dietrich is explicit in D*: Re = (W* D*)^(1/3), C_D = (4/3) D* / Re^2.
  for (double dstar = 0.05; dstar <= 5e9; dstar *= std::sqrt(10.0)) {
    const double re = std::cbrt(dietrich_dimensionless_velocity(dstar, 1.0, 6.0) * dstar);
    if (re < 0.01 || re > 1e5) continue;
    EXPECT_NEAR(4.0 / 3.0 * dstar / (re * re) / clift_grace_weber_drag(re), 1.0, 0.30) << "D* " << dstar;
  }
}

// ------------------------------------------------------------------ Stokes limit and force balance

TEST(ForceBalance, SmallSphereSettlesAtTheStokesVelocity) {
  // d = 1 um quartz in water: U_s = (rho_p - rho_f) g d^2 / (18 mu) = 9.0e-7 m/s, Re = 9e-7.
  // Every C_D law is 24/Re (1 + delta(Re)) with delta -> 0; U/U_s = 1/(1 + delta) differs from
  // 1 by at most delta(Re_s). The largest delta is Hoelzer-Sommerfeld's 3 sqrt(Re)/24 = 1.2e-4,
  // so 2e-4 bounds all of them (Schiller-Naumann's is 1.1e-5).
  const double d = 1e-6, rho_p = 2650.0, rho_f = 1000.0, mu = 1e-3, g = 9.81;
  const double stokes = (rho_p - rho_f) * g * d * d / (18.0 * mu);
  const body::Ellipsoid sphere = body::Ellipsoid::sphere(d);
  const ParticleDescriptors particle =
      describe_particle(sphere, rho_p, Orientation::broadside, Eigen::Vector3d::UnitZ());
  for (const LawPrediction& p : predict_terminal_velocities(particle, rho_f, mu, g)) {
    ASSERT_TRUE(p.state.solved) << p.law;
    if (p.law == "dietrich") {
      // Dietrich's fit starts at D* = 0.05; here D* = 1.6e-5 and the law is flagged.
      EXPECT_FALSE(p.in_range);
      continue;
    }
    EXPECT_NEAR(p.state.terminal_velocity_si / stokes, 1.0, 2e-4) << p.law;
  }
}

TEST(ForceBalance, ResidualOfTheSolvedStateIsRoundOff) {
  // The bisection stops when the bracket is 4 ulp wide in Re; the drag force C_D Re^2 has a
  // log-slope between 1 and 2, and evaluating weight and drag rounds at ~10 ulp: |residual|
  // <= 1e-13 leaves a margin of ~100.
  for (double diameter_scale : {1e-3, 1.0, 30.0}) {
    const body::Ellipsoid shape = body::Ellipsoid::spheroid(2e-3 * diameter_scale, 0.4);
    const ParticleDescriptors particle =
        describe_particle(shape, 1200.0, Orientation::broadside, Eigen::Vector3d::UnitZ());
    const SettlingConditions c{998.2, 1e-3, 9.81, 1200.0, particle.equivalent_diameter_si};
    for (const LawPrediction& p :
         predict_terminal_velocities(particle, c.fluid_density_si, c.dynamic_viscosity_si, c.gravity_si)) {
      ASSERT_TRUE(p.state.solved) << p.law << " scale " << diameter_scale;
      EXPECT_LT(std::abs(force_balance_residual(p.state, c)), 1e-13) << p.law << " scale " << diameter_scale;
    }
  }
}

TEST(ForceBalance, LightParticleRisesAtTheSameSpeedAsItsMirror) {
  // Only |rho_p - rho_f| enters the balance of the density-independent laws.
  ParticleDescriptors heavy;
  heavy.equivalent_diameter_si = 2e-3;
  heavy.density_si = 1100.0;
  ParticleDescriptors light = heavy;
  light.density_si = 900.0;
  const auto down = by_law(predict_terminal_velocities(heavy, 1000.0, 1e-3, 9.81));
  const auto up = by_law(predict_terminal_velocities(light, 1000.0, 1e-3, 9.81));
  for (const char* law :
       {"schiller_naumann", "clift_grace_weber", "haider_levenspiel", "ganser", "holzer_sommerfeld", "dietrich"}) {
    EXPECT_EQ(down.at(law), up.at(law)) << law;
  }
}

TEST(ForceBalance, UnbracketedOrUndefinedLawIsReportedUnsolved) {
  const SettlingConditions c{1000.0, 1e-3, 9.81, 2000.0, 1e-3};
  EXPECT_FALSE(solve_force_balance([](double) { return 1e-40; }, c).solved);  // drag never reaches the weight
  EXPECT_FALSE(solve_force_balance([](double) { return std::numeric_limits<double>::quiet_NaN(); }, c).solved);
}

TEST(ForceBalance, EqualDensitiesAreRefused) {
  ParticleDescriptors neutral;
  neutral.equivalent_diameter_si = 1e-3;
  neutral.density_si = 1000.0;
  EXPECT_THROW(predict_terminal_velocities(neutral, 1000.0, 1e-3, 9.81), InputError);
}

// ------------------------------------------------------------------ descriptors and ranges

TEST(Descriptors, ProlateSpheroidInEachOrientation) {
  // Semi-axes a = 0.5 (equatorial), c = 1.25 (polar, body z); d_v^3 = 2.5.
  const body::Ellipsoid shape = body::Ellipsoid::spheroid(1.0, 2.5);
  const double a = 0.5, c = 1.25, section = pi / 4 * std::pow(2.5, 2.0 / 3.0);
  constexpr double kClosedForm = 1e-12;  // closed-form shadows, evaluated to round-off

  const ParticleDescriptors side = describe_particle(shape, 2000.0, Orientation::broadside, kUnusedFall);
  EXPECT_NEAR(side.fall_direction_body.z(), 0.0, kClosedForm);  // across the long axis
  EXPECT_NEAR(side.crosswise_sphericity, section / (pi * a * c), kClosedForm);

  const ParticleDescriptors end = describe_particle(shape, 2000.0, Orientation::initial, Eigen::Vector3d(0, 0, -3));
  EXPECT_NEAR(end.crosswise_sphericity, section / (pi * a * a), kClosedForm);

  const ParticleDescriptors tumbling = describe_particle(shape, 2000.0, Orientation::mean, kUnusedFall);
  EXPECT_EQ(tumbling.crosswise_sphericity, tumbling.sphericity);
  EXPECT_EQ(tumbling.lengthwise_sphericity, tumbling.sphericity);

  // Ellipsoid: L I S = (2a)(2a)(2c) = d_v^3; f = 1, e = 0.4, Corey = 1/sqrt(2.5).
  EXPECT_NEAR(side.volume_ratio, 1.0, kClosedForm);
  EXPECT_NEAR(side.flatness, 1.0, kClosedForm);
  EXPECT_NEAR(side.elongation, 0.4, kClosedForm);
  EXPECT_NEAR(side.corey_shape_factor, 1.0 / std::sqrt(2.5), kClosedForm);
}

TEST(Descriptors, CaseSetUpUsesTheInitialAttitude) {
  // Tilted by theta = 0.5 about y: gravity meets the symmetry axis at 0.5 rad, so the shadow is
  // pi a sqrt(a^2 cos^2 0.5 + c^2 sin^2 0.5) and Ganser's d_n/d_v follows from it.
  coupling::SimulationSetup setup = settle::test::default_setup();
  setup.shape = std::make_shared<body::Ellipsoid>(body::Ellipsoid::spheroid(1e-3, 2.5));
  setup.particle_density_si = 1500.0;
  setup.initial.attitude = attitude::Attitude::from_set1(0.0, 0.5, 0.0);
  const double a = 0.5e-3, c = 1.25e-3;
  const double shadow =
      pi * a * std::sqrt(a * a * std::cos(0.5) * std::cos(0.5) + c * c * std::sin(0.5) * std::sin(0.5));
  const double section = pi / 4 * std::pow(2.5e-9, 2.0 / 3.0);
  const LawPrediction g = find(predict_terminal_velocities(setup, Orientation::initial), "ganser");
  double dn_over_dv = 0.0;
  for (const auto& [name, value] : g.descriptors) {
    if (name == "projected_to_volume_diameter") dn_over_dv = value;
  }
  EXPECT_NEAR(dn_over_dv, std::sqrt(shadow / section), 1e-12);
}

TEST(Ranges, SphereLawsFlagNonSpheresAndLargeReynolds) {
  // A 5 mm steel-like sphere in water: Re ~ 4e3, beyond Schiller-Naumann's 800.
  const ParticleDescriptors ball =
      describe_particle(body::Ellipsoid::sphere(5e-3), 7800.0, Orientation::broadside, kUnusedFall);
  const auto fast = predict_terminal_velocities(ball, 998.2, 1e-3, 9.81);
  EXPECT_FALSE(find(fast, "schiller_naumann").in_range);
  EXPECT_NE(find(fast, "schiller_naumann").reason.find("> 800"), std::string::npos);
  EXPECT_TRUE(find(fast, "clift_grace_weber").in_range) << find(fast, "clift_grace_weber").reason;

  const ParticleDescriptors rod =
      describe_particle(body::Ellipsoid::spheroid(1e-3, 4.0), 1100.0, Orientation::broadside, kUnusedFall);
  const LawPrediction sn = find(predict_terminal_velocities(rod, 998.2, 1e-3, 9.81), "schiller_naumann");
  EXPECT_FALSE(sn.in_range);
  EXPECT_NE(sn.reason.find("sphericity"), std::string::npos);
}

TEST(Ranges, BagheriBonadonnaIsUndefinedForACube) {
  // A cube: f = e = 1 and d_v^3 / (L I S) = 6/pi, so F_N = 1.91 > 1 and k_N has no real value.
  const ParticleDescriptors cube =
      describe_particle(body::Cuboid(Eigen::Vector3d::Constant(1e-3)), 2500.0, Orientation::broadside, kUnusedFall);
  EXPECT_NEAR(cube.volume_ratio, 6.0 / pi, 1e-12);
  const LawPrediction bb = find(predict_terminal_velocities(cube, 998.2, 1e-3, 9.81), "bagheri_bonadonna");
  EXPECT_FALSE(bb.state.solved);
  EXPECT_FALSE(bb.in_range);
  EXPECT_NE(bb.reason.find("F_N"), std::string::npos);
}

TEST(Ranges, ABoundIsInclusiveAndARisingParticleIsFlaggedForBagheriBonadonna) {
  // Disk D = 3 mm, L = 0.6 mm: Corey = 0.6 / 3 = 0.2 (computed as 0.19999999999999998), on
  // Dietrich's bound, which is inclusive.
  const ParticleDescriptors disk =
      describe_particle(body::Cylinder(3e-3, 0.6e-3), 2500.0, Orientation::broadside, kUnusedFall);
  EXPECT_NEAR(disk.corey_shape_factor, 0.2, 1e-15);
  const LawPrediction dietrich = find(predict_terminal_velocities(disk, 998.2, 1e-3, 9.81), "dietrich");
  EXPECT_TRUE(dietrich.in_range) << dietrich.reason;
  // A light disk rises: Bagheri and Bonadonna fitted falling particles only (rho_p/rho_f > 1).
  ParticleDescriptors light = disk;
  light.density_si = 900.0;
  const LawPrediction bb = find(predict_terminal_velocities(light, 998.2, 1e-3, 9.81), "bagheri_bonadonna");
  EXPECT_TRUE(bb.state.solved);
  EXPECT_FALSE(bb.in_range);
  EXPECT_NE(bb.reason.find("rho_p/rho_f"), std::string::npos);
}

TEST(Ranges, LawsAreReportedInTheDocumentedOrder) {
  ParticleDescriptors grain;
  grain.equivalent_diameter_si = 1e-3;
  grain.density_si = 2650.0;
  const auto predictions = predict_terminal_velocities(grain, 1000.0, 1e-3, 9.81);
  ASSERT_EQ(predictions.size(), law_names().size());
  for (std::size_t i = 0; i < predictions.size(); ++i) EXPECT_EQ(predictions[i].law, law_names()[i]);
  EXPECT_EQ(parse_orientation("mean"), Orientation::mean);
  EXPECT_FALSE(parse_orientation("sideways").has_value());
}

}  // namespace test_correlations
}  // namespace settle::analysis
