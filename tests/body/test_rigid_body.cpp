// Rigid-body dynamics (Newton-Euler with the dual-Euler attitude of Cheng et al. 2023,
// doi:10.1063/5.0165555) against closed forms, invariants and a fine quaternion reference.
#include <algorithm>
#include <cmath>
#include <cstdio>
#include <numbers>
#include <utility>

#include <gtest/gtest.h>
#include <Eigen/Geometry>

#include "support/matrix_checks.hpp"

#include "attitude/integrators.hpp"
#include "attitude/rotational_dynamics.hpp"
#include "body/rigid_body.hpp"

namespace settle::body {
namespace test_rigid_body {

using attitude::Attitude;

using settle::test::max_abs_difference;
using settle::test::raise_to;
using settle::test::rotation_about;

/// A state at the origin, not translating (Eigen vectors written as {} would be uninitialised).
RigidBodyState spinning(const Attitude& attitude, const Eigen::Vector3d& omega_b) {
  return {Eigen::Vector3d::Zero(), Eigen::Vector3d::Zero(), attitude, omega_b};
}

MassProperties mass_properties(double mass, double volume, const Eigen::Matrix3d& inertia) {
  MassProperties p;
  p.mass = mass;
  p.volume = volume;
  p.density = mass / volume;
  p.inertia = inertia;
  return p;
}

// ---------------------------------------------------------------------------------------
// Translation under a constant force: x(t) = x0 + v0 t + a t^2 / 2 with
// a = (F + (m - rho_f V) g) / m.

struct ConstantForceCase {
  MassProperties properties = mass_properties(2.0, 1.5e-3, Eigen::Vector3d(0.1, 0.2, 0.3).asDiagonal());
  Environment environment{998.2, Eigen::Vector3d(0.0, 0.0, -9.81)};
  RigidBodyState initial{Eigen::Vector3d(0.1, -0.2, 0.3), Eigen::Vector3d(0.5, 0.0, -1.0),
                         Attitude::from_set1(0.2, 0.4, -0.3), Eigen::Vector3d::Zero()};
  Wrench external{Eigen::Vector3d(0.3, -0.2, 0.1), Eigen::Vector3d::Zero()};

  [[nodiscard]] Eigen::Vector3d acceleration() const {
    const double buoyant_mass = properties.mass - environment.fluid_density_si * properties.volume;
    return (external.force_si + buoyant_mass * environment.gravity_si) / properties.mass;
  }
  [[nodiscard]] Eigen::Vector3d position(double t) const {
    return initial.position_si + t * initial.velocity_si + 0.5 * t * t * acceleration();
  }
  [[nodiscard]] Eigen::Vector3d velocity(double t) const { return initial.velocity_si + t * acceleration(); }
};

TEST(RigidBodyTranslation, ConstantForceRk4IsExact) {
  const ConstantForceCase c;
  RigidBody body(c.properties, c.environment, c.initial);
  const double dt = 0.01;
  for (int i = 0; i < 100; ++i) body.advance(i * dt, dt, [&](double, const RigidBodyState&) { return c.external; });
  // RK4 integrates a quadratic exactly; 100 steps of rounding on O(1) values: < 1e-13.
  EXPECT_LT((body.state().position_si - c.position(1.0)).cwiseAbs().maxCoeff(), 1e-13);
  EXPECT_LT((body.state().velocity_si - c.velocity(1.0)).cwiseAbs().maxCoeff(), 1e-13);
  // No torque, no rotation: the attitude is untouched to rounding.
  EXPECT_LT(max_abs_difference(body.body_to_inertial(), c.initial.attitude.body_to_inertial()), 1e-15);
}

TEST(RigidBodyTranslation, ConstantForceCorrectorIsExact) {
  const ConstantForceCase c;
  RigidBody body(c.properties, c.environment, c.initial);
  const double dt = 0.01;
  for (int i = 0; i < 100; ++i) {
    const Pose predicted = body.predict_pose(dt);
    // The predictor is the pose at the current velocity.
    ASSERT_LT((predicted.position_si - (body.state().position_si + dt * body.state().velocity_si)).norm(), 1e-15);
    body.correct(dt, c.external);
  }
  // Trapezoidal position update with exact velocity: exact for a constant force.
  EXPECT_LT((body.state().position_si - c.position(1.0)).cwiseAbs().maxCoeff(), 1e-13);
  EXPECT_LT((body.state().velocity_si - c.velocity(1.0)).cwiseAbs().maxCoeff(), 1e-13);
}

TEST(RigidBodyTranslation, NeutrallyBuoyantBodyFeelsNoGravity) {
  // A volume of 2^-20 m^3 (about 1 cm^3): rho V = 1000 * 2^-20 is exact in double, so m = rho V
  // holds exactly and (m - rho V) g must vanish exactly, whether or not the compiler fuses the
  // product and the difference into one multiply-add (-march=native builds do).
  const double volume = std::ldexp(1.0, -20);
  RigidBody body(mass_properties(1000.0 * volume, volume, 1e-12 * Eigen::Matrix3d::Identity()),
                 Environment{1000.0, Eigen::Vector3d(0.0, 0.0, -9.81)}, RigidBodyState{});
  EXPECT_EQ(body.net_weight_si().norm(), 0.0);
}

// ---------------------------------------------------------------------------------------
// Torque-free motion with a full (non-diagonal) inertia tensor. A diagonal tensor I_p
// rotated by a known Q (v_b = Q v_p) gives I_b = Q I_p Q^T; the same physical motion then has
// C_b^n = C_p^n Q^T and omega_b = Q omega_p at all times.

TEST(RigidBodyRotation, FullTensorMatchesRotatedDiagonalCase) {
  const Eigen::Matrix3d diagonal = Eigen::Vector3d(1.0, 2.0, 3.0).asDiagonal();
  const Eigen::Matrix3d q = Attitude::from_set1(0.4, -0.9, 1.3).body_to_inertial();
  const Eigen::Matrix3d full = q * diagonal * q.transpose();
  ASSERT_GT(std::abs(full(0, 1)), 0.1);  // really non-diagonal

  const Attitude start = Attitude::from_set1(-0.7, 0.3, 2.1);
  const Eigen::Vector3d omega_p(0.05, 1.0, 0.05);  // near the intermediate axis: it tumbles
  const Environment vacuum{};
  RigidBody principal(mass_properties(1.0, 1.0, diagonal), vacuum, spinning(start, omega_p));
  RigidBody rotated(mass_properties(1.0, 1.0, full), vacuum,
                    spinning(Attitude::from_matrix(start.body_to_inertial() * q.transpose()), q * omega_p));

  const double energy0 = rotated.kinetic_energy_si();
  const Eigen::Vector3d momentum0 = rotated.angular_momentum_n_si();
  const double dt = 1e-3;
  double attitude_difference = 0.0, omega_difference = 0.0, energy_drift = 0.0, momentum_drift = 0.0;
  for (int i = 0; i < 30000; ++i) {
    principal.advance(i * dt, dt);
    rotated.advance(i * dt, dt);
    raise_to(attitude_difference,
             max_abs_difference(rotated.body_to_inertial(), principal.body_to_inertial() * q.transpose()));
    raise_to(omega_difference,
             (rotated.state().angular_velocity_b_si - q * principal.state().angular_velocity_b_si).norm());
    raise_to(energy_drift, std::abs(rotated.kinetic_energy_si() - energy0) / energy0);
    raise_to(momentum_drift, (rotated.angular_momentum_n_si() - momentum0).norm() / momentum0.norm());
  }
  std::printf(
      "[measured] full tensor vs rotated diagonal, dt=1e-3, t=30: attitude %.3g, omega %.3g, "
      "energy drift %.3g, |L_n| drift %.3g, switches %ld / %ld\n",
      attitude_difference, omega_difference, energy_drift, momentum_drift, rotated.switch_count(),
      principal.switch_count());
  // The tumbling takes both bodies through both charts (each in its own frame's angles).
  EXPECT_GE(principal.switch_count(), 2);
  EXPECT_GE(rotated.switch_count(), 2);
  // Same RK4 in two frames and two charts: they differ by their truncation errors,
  // ~t (|omega| dt)^4 |omega| = 30 * 1e-12 at most.
  EXPECT_LT(attitude_difference, 1e-10);
  EXPECT_LT(omega_difference, 1e-10);
  // Exact invariants of torque-free motion, RK4 drift of the same size.
  EXPECT_LT(energy_drift, 1e-10);
  EXPECT_LT(momentum_drift, 1e-10);
}

// ---------------------------------------------------------------------------------------
// Heavy symmetric top on a fixed pivot at the origin (Lagrange top). The body's reference
// point is the pivot: inertia about the pivot I_o = I_c + m (|d|^2 1 - d d^T) with d the
// centre of mass in body axes, torque about the pivot (C d) x (m g), and no net force (the
// pivot reaction balances gravity, so the pivot stays put). Exact invariants: the energy
// 0.5 omega.I_o omega + m |g| z_c, the angular momentum about the vertical e_z.(C I_o omega)
// and about the symmetry axis (I_o omega)_3.

struct HeavyTop {
  double mass = 1.0;
  double axial = 0.02;                      // kg m^2 about the symmetry axis (body z)
  double transverse_cm = 0.005;             // kg m^2 about a transverse axis through the centre of mass
  Eigen::Vector3d offset_b{0.0, 0.0, 0.1};  // pivot to centre of mass, m
  Eigen::Vector3d gravity_n{0.0, 0.0, -9.81};
  Eigen::Vector3d omega0_b{0.5, -0.3, 15.0};  // a fast top, tilted and nutating
  Attitude initial = Attitude::from_set1(0.3, 0.6, 0.2);

  [[nodiscard]] Eigen::Matrix3d inertia_about_pivot() const {
    const Eigen::Matrix3d about_cm = Eigen::Vector3d(transverse_cm, transverse_cm, axial).asDiagonal();
    return about_cm + mass * (offset_b.squaredNorm() * Eigen::Matrix3d::Identity() - offset_b * offset_b.transpose());
  }
  [[nodiscard]] Eigen::Vector3d torque_n(const Eigen::Matrix3d& body_to_inertial) const {
    return (body_to_inertial * offset_b).cross(mass * gravity_n);
  }
  [[nodiscard]] double energy(const Eigen::Matrix3d& r, const Eigen::Vector3d& omega_b) const {
    return 0.5 * omega_b.dot(inertia_about_pivot() * omega_b) - mass * gravity_n.dot(r * offset_b);
  }
  [[nodiscard]] double vertical_momentum(const Eigen::Matrix3d& r, const Eigen::Vector3d& omega_b) const {
    return (r * (inertia_about_pivot() * omega_b))[2];
  }
  [[nodiscard]] double axial_momentum(const Eigen::Vector3d& omega_b) const {
    return (inertia_about_pivot() * omega_b)[2];
  }
};

struct HeavyTopRun {
  double attitude_error = 0.0;  ///< max over the run against the fine quaternion reference
  double energy_drift = 0.0;    ///< relative to the energy
  double vertical_drift = 0.0;  ///< relative to the axial angular momentum
  double axial_drift = 0.0;     ///< relative to the axial angular momentum
  long switches = 0;
};

HeavyTopRun run_heavy_top(const HeavyTop& top, double dt, double t_end) {
  // Gravity is applied as the pivot torque, so the environment is gravity-free.
  RigidBody body(mass_properties(top.mass, 1.0, top.inertia_about_pivot()), Environment{},
                 spinning(top.initial, top.omega0_b));
  const WrenchFunction pivot_torque = [&](double, const RigidBodyState& s) {
    return Wrench{Eigen::Vector3d::Zero(), top.torque_n(s.attitude.body_to_inertial())};
  };
  // Reference: quaternion RK4 with a ten times smaller step (error 1e4 times smaller).
  const attitude::BodyInertia inertia(top.inertia_about_pivot());
  attitude::QuaternionSpinState reference{top.omega0_b, top.initial.quaternion()};
  const attitude::BodyTorqueFunction reference_torque = [&](double, const Eigen::Vector3d&, const Eigen::Matrix3d& r) {
    return Eigen::Vector3d(r.transpose() * top.torque_n(r));
  };
  const double fine = dt / 10.0;
  const double energy0 = top.energy(body.body_to_inertial(), top.omega0_b);
  const double vertical0 = top.vertical_momentum(body.body_to_inertial(), top.omega0_b);
  const double axial0 = top.axial_momentum(top.omega0_b);
  HeavyTopRun run;
  const auto steps = static_cast<int>(std::lround(t_end / dt));
  for (int i = 0; i < steps; ++i) {
    body.advance(i * dt, dt, pivot_torque);
    for (int k = 0; k < 10; ++k)
      attitude::quaternion_spin_step(reference, inertia, i * dt + k * fine, fine, reference_torque);
    const Eigen::Matrix3d r = body.body_to_inertial();
    const Eigen::Vector3d& omega = body.state().angular_velocity_b_si;
    raise_to(run.attitude_error, max_abs_difference(r, reference.orientation.toRotationMatrix()));
    raise_to(run.energy_drift, std::abs(top.energy(r, omega) - energy0) / std::abs(energy0));
    raise_to(run.vertical_drift, std::abs(top.vertical_momentum(r, omega) - vertical0) / std::abs(axial0));
    raise_to(run.axial_drift, std::abs(top.axial_momentum(omega) - axial0) / std::abs(axial0));
  }
  run.switches = body.switch_count();
  return run;
}

TEST(RigidBodyRotation, HeavySymmetricTopMatchesFineQuaternionReference) {
  const HeavyTop top;
  const HeavyTopRun run = run_heavy_top(top, 5e-4, 5.0);
  const HeavyTopRun coarse = run_heavy_top(top, 1e-3, 5.0);
  const double order = std::log2(coarse.attitude_error / run.attitude_error);
  std::printf(
      "[measured] heavy top, dt=5e-4, t=5: attitude vs reference %.3g (dt=1e-3: %.3g, order %.3f), "
      "energy drift %.3g, vertical L drift %.3g, axial L drift %.3g, switches %ld\n",
      run.attitude_error, coarse.attitude_error, order, run.energy_drift, run.vertical_drift, run.axial_drift,
      run.switches);
  // The top precesses round the vertical with its axis tilted by ~0.6 rad: the pitch leaves
  // the set-1 band, so both charts are used.
  EXPECT_GE(run.switches, 2);
  // The difference to the reference is the dual-Euler run's own RK4 error: it must shrink
  // sixteenfold when dt halves...
  EXPECT_GT(order, 3.8);
  EXPECT_LT(order, 4.2);
  // ...and at |omega| dt = 7.5e-3 over 75 radians of spin it is ~1e-9 (measured 8e-10).
  // 1e-8 would still catch any error of the method's form, which is O(dt) or O(1).
  EXPECT_LT(run.attitude_error, 1e-8);
  // Exact invariants of the Lagrange top. They drift at O(dt^4) too, with a smaller constant
  // than the attitude, whose error is mostly a phase along the precession that changes
  // neither invariant (measured 3e-12 and 5e-12).
  EXPECT_LT(run.energy_drift, 1e-10);
  EXPECT_LT(run.vertical_drift, 1e-10);
  // omega_3 is constant exactly (no axial torque, no axial gyroscopic term for I1 = I2):
  // only rounding, ~1e-16 per step.
  EXPECT_LT(run.axial_drift, 1e-12);
}

// ---------------------------------------------------------------------------------------
// The coupled-step corrector's rotation.

/// Spin-up from rest by a constant inertial torque along a principal axis (body y): the body
/// turns about that axis with omega = T t / I and angle T t^2 / (2 I). Returns the attitude
/// and body-rate errors at t = 3 through correct().
std::pair<double, double> spin_up_errors(const Attitude& start, double dt) {
  const Eigen::Matrix3d inertia = Eigen::Vector3d(0.2, 0.3, 0.5).asDiagonal();
  const Eigen::Vector3d axis_b = Eigen::Vector3d::UnitY();
  const Eigen::Vector3d axis_n = start.body_to_inertial() * axis_b;
  const double torque = 0.15, t_end = 3.0;
  RigidBody body(mass_properties(1.0, 1.0, inertia), Environment{}, spinning(start, Eigen::Vector3d::Zero()));
  const auto steps = static_cast<int>(std::lround(t_end / dt));
  for (int i = 0; i < steps; ++i) body.correct(dt, Wrench{Eigen::Vector3d::Zero(), torque * axis_n});
  const Eigen::Matrix3d exact = start.body_to_inertial() * rotation_about(axis_b, torque * t_end * t_end / (2.0 * 0.3));
  return {max_abs_difference(body.body_to_inertial(), exact),
          (body.state().angular_velocity_b_si - torque * t_end / 0.3 * axis_b).norm()};
}

TEST(RigidBodyCorrector, SpinUpFromIdentityIsExact) {
  // omega is linear in t, so RK4 on omega and the linear interpolation of omega inside each
  // step are exact; from the identity the active angle (theta, then theta_r) is the rotation
  // angle itself, so the chart's RK4 is exact too. Only rounding remains: 300 steps on
  // angles up to 2.25 rad, < 1e-13.
  const auto [attitude_error, omega_error] = spin_up_errors(Attitude(), 0.01);
  EXPECT_LT(attitude_error, 1e-13);
  EXPECT_LT(omega_error, 1e-13);
}

TEST(RigidBodyCorrector, SpinUpFromGenericAttitudeIsFourthOrder) {
  // From a generic attitude the chart's angle equations are nonlinear and RK4 has its
  // O(dt^4) error; the interpolation of omega (linear in t here) adds none. An interpolation
  // that was wrong (e.g. holding omega at its start value) would show order 1 or 2.
  const Attitude start = Attitude::from_set1(0.3, -0.2, 0.5);
  const auto [coarse, omega_coarse] = spin_up_errors(start, 0.04);
  const auto [fine, omega_fine] = spin_up_errors(start, 0.02);
  const double order = std::log2(coarse / fine);
  std::printf("[measured] corrector spin-up: attitude errors %.3g %.3g (order %.3f), omega errors %.3g %.3g\n", coarse,
              fine, order, omega_coarse, omega_fine);
  EXPECT_GT(order, 3.8);
  EXPECT_LT(order, 4.2);
  // The body rate's only error comes from the predicted attitude used to bring the torque
  // into the body frame, which is itself RK4-accurate: below the attitude error's size.
  EXPECT_LT(omega_fine, 1e-8);
}

double corrector_symmetric_top_error(double dt) {
  // Torque-free symmetric top (closed form as in the attitude tests) through correct().
  const double i1 = 1.0, i3 = 1.7;
  const Eigen::Vector3d omega0(0.6, -0.4, 1.3);
  const Attitude start = Attitude::from_set1(0.3, -0.5, 1.2);
  RigidBody body(mass_properties(1.0, 1.0, Eigen::Vector3d(i1, i1, i3).asDiagonal()), Environment{},
                 spinning(start, omega0));
  const Eigen::Vector3d momentum = body.angular_momentum_n_si();
  const double precession = (i3 - i1) / i1 * omega0[2];
  const double t_end = 4.0;
  const auto steps = static_cast<int>(std::lround(t_end / dt));
  for (int i = 0; i < steps; ++i) body.correct(dt, Wrench{});
  const Eigen::Matrix3d exact = rotation_about(momentum, momentum.norm() / i1 * t_end) * start.body_to_inertial() *
                                rotation_about(Eigen::Vector3d::UnitZ(), -precession * t_end);
  return max_abs_difference(body.body_to_inertial(), exact);
}

TEST(RigidBodyCorrector, TorqueFreeAttitudeIsSecondOrder) {
  // Linear interpolation of the body rates inside the step makes the attitude second order
  // (trapezoidal quadrature of omega), the order of the coupled step.
  const double coarse = corrector_symmetric_top_error(0.02);
  const double fine = corrector_symmetric_top_error(0.01);
  const double order = std::log2(coarse / fine);
  std::printf("[measured] corrector torque-free: errors %.3g %.3g, order %.3f\n", coarse, fine, order);
  EXPECT_GT(order, 1.8);
  EXPECT_LT(order, 2.2);
}

// ---------------------------------------------------------------------------------------
// Prescribed motion.

TEST(RigidBodyMotionKinds, TowedMovesAtPrescribedVelocities) {
  const Eigen::Vector3d velocity(0.0, 0.0, -0.05), omega_b(0.0, 0.0, 0.8);
  const Attitude start = Attitude::from_set1(0.1, 0.2, 0.3);
  const Eigen::Vector3d x0(0.02, 0.02, 0.1);
  RigidBody body(mass_properties(1.0, 1.0, Eigen::Matrix3d::Identity()),
                 Environment{1000.0, Eigen::Vector3d(0.0, 0.0, -9.81)}, {x0, velocity, start, omega_b},
                 MotionKind::towed);
  const double dt = 0.01;
  for (int i = 0; i < 100; ++i) {
    if (i % 2 == 0) {
      body.correct(dt, Wrench{Eigen::Vector3d(5.0, 0.0, 0.0), Eigen::Vector3d(0.0, 1.0, 0.0)});  // ignored
    } else {
      body.advance(i * dt, dt);
    }
  }
  // Linear position and constant-rate rotation: exact up to rounding over 100 steps.
  EXPECT_LT((body.state().position_si - (x0 + 1.0 * velocity)).norm(), 1e-14);
  EXPECT_EQ(body.state().velocity_si, velocity);
  EXPECT_EQ(body.state().angular_velocity_b_si, omega_b);
  // The attitude is exactly the dual-Euler kinematics at the constant body rate...
  Attitude kinematics = start;
  for (int i = 0; i < 100; ++i) attitude::dual_euler_step(kinematics, dt, omega_b, omega_b);
  EXPECT_EQ(body.state().attitude.angles(), kinematics.angles());
  // ...which follows the closed form to RK4 accuracy: (|omega| dt)^4 t |omega| ~ 3e-9 times
  // RK4's small constant (measured 8e-12); 1e-10 is the bound used for RK4 rotations.
  EXPECT_LT(max_abs_difference(body.body_to_inertial(), start.body_to_inertial() * rotation_about(omega_b, 0.8)),
            1e-10);
}

TEST(RigidBodyMotionKinds, FixedBodyDoesNotMove) {
  const RigidBodyState initial{Eigen::Vector3d(1.0, 2.0, 3.0), Eigen::Vector3d(1.0, 0.0, 0.0),
                               Attitude::from_set1(0.5, 0.1, 0.0), Eigen::Vector3d(0.0, 1.0, 0.0)};
  RigidBody body(mass_properties(1.0, 1.0, Eigen::Matrix3d::Identity()),
                 Environment{0.0, Eigen::Vector3d(0.0, 0.0, -9.81)}, initial, MotionKind::fixed);
  EXPECT_EQ(body.state().velocity_si, Eigen::Vector3d::Zero());
  EXPECT_EQ(body.state().angular_velocity_b_si, Eigen::Vector3d::Zero());
  body.correct(0.1, Wrench{Eigen::Vector3d(1.0, 1.0, 1.0), Eigen::Vector3d(1.0, 1.0, 1.0)});
  body.advance(0.1, 0.1);
  EXPECT_EQ(body.state().position_si, initial.position_si);
  EXPECT_EQ(body.state().attitude.angles(), initial.attitude.angles());
}

// A free body with its rotation locked translates as Newton's law says and keeps its attitude,
// whatever torque it is given; the same body unlocked would turn (so the check can fail).
TEST(RigidBodyMotionKinds, ALockedFreeBodyTranslatesAndKeepsItsAttitude) {
  ConstantForceCase c;
  c.external.torque_si = Eigen::Vector3d(0.02, -0.05, 0.03);
  const double dt = 0.01;
  RigidBody by_corrector(c.properties, c.environment, c.initial);
  RigidBody by_rk4(c.properties, c.environment, c.initial);
  RigidBody unlocked(c.properties, c.environment, c.initial);
  by_corrector.lock_rotation();
  by_rk4.lock_rotation();
  for (int i = 0; i < 100; ++i) {
    by_corrector.correct(dt, c.external);
    by_rk4.advance(i * dt, dt, [&](double, const RigidBodyState&) { return c.external; });
    unlocked.correct(dt, c.external);
  }
  for (const RigidBody* body : {&by_corrector, &by_rk4}) {
    // The translation is the constant-force case's, exact to rounding (as in its own tests).
    EXPECT_LT((body->state().position_si - c.position(1.0)).cwiseAbs().maxCoeff(), 1e-13);
    EXPECT_LT((body->state().velocity_si - c.velocity(1.0)).cwiseAbs().maxCoeff(), 1e-13);
    EXPECT_EQ(body->state().attitude.angles(), c.initial.attitude.angles());
    EXPECT_EQ(body->state().angular_velocity_b_si, Eigen::Vector3d::Zero());
    EXPECT_TRUE(body->rotation_locked());
  }
  // Unlocked, the torque of |T| ~ 0.06 N m on inertias 0.1-0.3 kg m^2 spins it up to O(0.1) rad/s in 1 s.
  EXPECT_GT(unlocked.state().angular_velocity_b_si.norm(), 0.1);
  EXPECT_GT(max_abs_difference(unlocked.body_to_inertial(), c.initial.attitude.body_to_inertial()), 0.01);
}

TEST(RigidBodyMotionKinds, LockingTheRotationStopsASpinningBody) {
  RigidBody body(mass_properties(1.0, 1.0, Eigen::Matrix3d::Identity()), Environment{},
                 spinning(Attitude::from_set1(0.1, 0.2, 0.3), Eigen::Vector3d(0.0, 2.0, 0.0)));
  body.lock_rotation();
  EXPECT_EQ(body.state().angular_velocity_b_si, Eigen::Vector3d::Zero());
  // A state restored later (a checkpoint) keeps the lock.
  body.set_state(spinning(Attitude::from_set1(0.1, 0.2, 0.3), Eigen::Vector3d(1.0, 0.0, 0.0)));
  EXPECT_EQ(body.state().angular_velocity_b_si, Eigen::Vector3d::Zero());
}

TEST(RigidBodyMotionKinds, RejectsInvalidMassProperties) {
  const Eigen::Matrix3d identity = Eigen::Matrix3d::Identity();
  EXPECT_THROW(RigidBody(mass_properties(0.0, 1.0, identity), Environment{}, RigidBodyState{}), std::invalid_argument);
  EXPECT_THROW(RigidBody(mass_properties(1.0, -1.0, identity), Environment{}, RigidBodyState{}), std::invalid_argument);
  EXPECT_THROW(RigidBody(mass_properties(1.0, 1.0, -identity), Environment{}, RigidBodyState{}), std::invalid_argument);
}

// ---------------------------------------------------------------------------------------
// The corrector's virtual mass and inertia (VirtualInertia; Schwarz, Kempe and Froehlich 2015):
// m_v a_est and I_v alpha_est on the right, m_v and I_v on the left.

struct VirtualInertiaCase {
  MassProperties properties = mass_properties(2.0, 1.5e-3, Eigen::Vector3d(0.1, 0.2, 0.3).asDiagonal());
  Environment environment{998.2, Eigen::Vector3d(0.0, 0.0, -9.81)};
  Attitude start = Attitude::from_set1(0.2, 0.4, -0.3);
  double torque_about_body_z = 0.06;  // N m
  Wrench external() const {
    // The torque about the body's principal z axis, which keeps its direction while the body
    // spins about it: domega_b/dt = (0, 0, T / I_zz) exactly (no gyroscopic term).
    return {Eigen::Vector3d(0.3, -0.2, 0.1), start.body_to_inertial() * Eigen::Vector3d(0.0, 0.0, torque_about_body_z)};
  }
  Eigen::Vector3d acceleration() const {
    const double buoyant_mass = properties.mass - environment.fluid_density_si * properties.volume;
    return (external().force_si + buoyant_mass * environment.gravity_si) / properties.mass;
  }
  Eigen::Vector3d angular_acceleration_b() const {
    return Eigen::Vector3d(0.0, 0.0, torque_about_body_z / properties.inertia(2, 2));
  }
  RigidBody body() const {
    return RigidBody(properties, environment,
                     {Eigen::Vector3d::Zero(), Eigen::Vector3d(0.5, 0.0, -1.0), start, Eigen::Vector3d::Zero()});
  }
  VirtualInertia virtual_inertia(const Eigen::Vector3d& a_est, const Eigen::Vector3d& alpha_est) const {
    return {0.7, 0.4 * properties.inertia, a_est, alpha_est};
  }
};

TEST(RigidBodyVirtualInertia, ZeroVirtualInertiaIsThePlainCorrectorBitForBit) {
  // A non-diagonal inertia and a torque off every axis, so the gyroscopic term is at work.
  Eigen::Matrix3d inertia;
  inertia << 0.3, 0.02, -0.01, 0.02, 0.2, 0.03, -0.01, 0.03, 0.1;
  const RigidBodyState start{Eigen::Vector3d(0.1, 0.2, 0.3), Eigen::Vector3d(0.1, -0.2, 0.3),
                             Attitude::from_set1(0.3, -0.2, 0.5), Eigen::Vector3d(1.0, -2.0, 0.5)};
  const Environment environment{998.2, Eigen::Vector3d(0.0, 0.0, -9.81)};
  RigidBody plain(mass_properties(2.0, 1.5e-3, inertia), environment, start);
  RigidBody with_zero(mass_properties(2.0, 1.5e-3, inertia), environment, start);
  const Wrench wrench{Eigen::Vector3d(0.3, -0.2, 0.1), Eigen::Vector3d(0.01, 0.02, -0.03)};
  for (int i = 0; i < 50; ++i) {
    plain.correct(0.01, wrench);
    with_zero.correct(0.01, wrench, VirtualInertia{});
  }
  EXPECT_EQ(with_zero.state().position_si, plain.state().position_si);
  EXPECT_EQ(with_zero.state().velocity_si, plain.state().velocity_si);
  EXPECT_EQ(with_zero.state().angular_velocity_b_si, plain.state().angular_velocity_b_si);
  EXPECT_EQ(with_zero.state().attitude.angles(), plain.state().attitude.angles());
}

TEST(RigidBodyVirtualInertia, LeavesASteadyAccelerationUnchanged) {
  // When the estimate is the step's own acceleration, m_v a_est = m_v a and I_v alpha_est = I_v alpha
  // cancel the added inertia: the motion is the plain one (the terminal state and any steady
  // acceleration are untouched). 50 steps of 0.01 s; the two differ by round-off only.
  const VirtualInertiaCase c;
  RigidBody plain = c.body();
  RigidBody stabilised = c.body();
  const VirtualInertia steady = c.virtual_inertia(c.acceleration(), c.angular_acceleration_b());
  for (int i = 0; i < 50; ++i) {
    plain.correct(0.01, c.external());
    stabilised.correct(0.01, c.external(), steady);
  }
  // Velocities of order 1 m/s and 1 rad/s after 50 steps of a few round-offs each.
  EXPECT_LT((stabilised.state().velocity_si - plain.state().velocity_si).norm(), 1e-13);
  EXPECT_LT((stabilised.state().position_si - plain.state().position_si).norm(), 1e-13);
  EXPECT_LT((stabilised.state().angular_velocity_b_si - plain.state().angular_velocity_b_si).norm(), 1e-13);
  EXPECT_LT((stabilised.state().attitude.angles() - plain.state().attitude.angles()).norm(), 1e-12);
  // And the plain motion is the closed form: a constant acceleration and a constant body rate change.
  EXPECT_LT((stabilised.state().velocity_si - (Eigen::Vector3d(0.5, 0.0, -1.0) + 0.5 * c.acceleration())).norm(),
            1e-13);
  EXPECT_LT((stabilised.state().angular_velocity_b_si - 0.5 * c.angular_acceleration_b()).norm(), 1e-13);
}

TEST(RigidBodyVirtualInertia, OneStepTakesTheVirtualTermsAsWritten) {
  // Any other estimate: one step gives (m + m_v) dv/dt = F + W + m_v a_est and, about the principal
  // axis from rest, (I + I_v) domega/dt = T + I_v alpha_est, exactly (constant rates).
  const VirtualInertiaCase c;
  const Eigen::Vector3d a_est(1.0, -2.0, 3.0), alpha_est(0.0, 0.0, -5.0);
  const VirtualInertia v = c.virtual_inertia(a_est, alpha_est);
  RigidBody body = c.body();
  const double dt = 0.01;
  body.correct(dt, c.external(), v);
  const double m = c.properties.mass;
  const Eigen::Vector3d a = (m * c.acceleration() + v.mass_si * a_est) / (m + v.mass_si);
  EXPECT_LT((body.state().velocity_si - (Eigen::Vector3d(0.5, 0.0, -1.0) + dt * a)).norm(), 1e-15);
  const double izz = c.properties.inertia(2, 2), iv = v.inertia_b_si(2, 2);
  const double alpha = (c.torque_about_body_z + iv * alpha_est.z()) / (izz + iv);
  EXPECT_LT((body.state().angular_velocity_b_si - Eigen::Vector3d(0.0, 0.0, dt * alpha)).norm(), 1e-15);
}

}  // namespace test_rigid_body
}  // namespace settle::body
