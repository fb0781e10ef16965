// The dual-Euler whole-attitude solver (Cheng et al. 2023, doi:10.1063/5.0165555,
// supplementary material) against the unit-quaternion RK4, closed-form rigid-body motions
// and the invariants of torque-free motion.
#include <algorithm>
#include <cmath>
#include <cstdio>
#include <numbers>

#include <gtest/gtest.h>
#include <Eigen/Geometry>

#include "support/matrix_checks.hpp"

#include "attitude/attitude.hpp"
#include "attitude/integrators.hpp"
#include "attitude/rotational_dynamics.hpp"

namespace settle::attitude {
namespace test_integrators {

constexpr double pi = std::numbers::pi;

using settle::test::max_abs_difference;
using settle::test::raise_to;
using settle::test::rotation_about;

// ---------------------------------------------------------------------------------------
// Torque-free asymmetric top near its intermediate axis: the body tumbles (repeated flips
// of the intermediate axis), so the pitch sweeps through +-pi/2 and the solver must switch
// sets many times.

struct TopComparison {
  int switches = 0;
  int quaternion_rule_switches = 0;
  double max_matrix_difference = 0.0;
  double max_energy_drift = 0.0;
  double max_momentum_drift = 0.0;
  double max_orthonormality_error = 0.0;
};

TopComparison run_intermediate_axis_top(double dt, double t_end) {
  const BodyInertia inertia(Eigen::Vector3d(1.0, 2.0, 3.0).asDiagonal());
  const Eigen::Vector3d omega0(0.01, 1.0, 0.01);
  SpinState dual{omega0, Attitude()};
  QuaternionSpinState quaternion{omega0, Eigen::Quaterniond::Identity()};
  const double energy0 = rotational_energy(inertia, omega0);
  const Eigen::Vector3d momentum0 = inertia.tensor() * omega0;  // inertial = body at identity

  TopComparison result;
  EulerSet previous_rule_set = Attitude::from_quaternion(quaternion.orientation).set();
  const auto steps = static_cast<int>(std::lround(t_end / dt));
  for (int i = 0; i < steps; ++i) {
    const double t = i * dt;
    if (dual_euler_spin_step(dual, inertia, t, dt)) ++result.switches;
    quaternion_spin_step(quaternion, inertia, t, dt);

    const Eigen::Matrix3d r_dual = dual.attitude.body_to_inertial();
    const Eigen::Matrix3d r_quaternion = quaternion.orientation.toRotationMatrix();
    raise_to(result.max_matrix_difference, max_abs_difference(r_dual, r_quaternion));
    raise_to(result.max_energy_drift, std::abs(rotational_energy(inertia, dual.omega_b) - energy0) / energy0);
    const Eigen::Vector3d momentum = r_dual * (inertia.tensor() * dual.omega_b);
    raise_to(result.max_momentum_drift, (momentum - momentum0).norm() / momentum0.norm());
    raise_to(result.max_orthonormality_error,
             max_abs_difference(r_dual.transpose() * r_dual, Eigen::Matrix3d::Identity()));
    // The rule's choice for the quaternion's attitude, tracked independently.
    const EulerSet rule_set = Attitude::from_quaternion(quaternion.orientation).set();
    if (rule_set != previous_rule_set) ++result.quaternion_rule_switches;
    previous_rule_set = rule_set;
  }
  return result;
}

TEST(DualEulerTorqueFree, IntermediateAxisTopAgreesWithQuaternion) {
  const TopComparison r = run_intermediate_axis_top(1e-3, 40.0);
  std::printf(
      "[measured] intermediate-axis top, dt=1e-3, t=40: switches %d, max |R_dual - R_quat| %.3g, "
      "energy drift %.3g, |L_n| drift %.3g, orthonormality %.3g\n",
      r.switches, r.max_matrix_difference, r.max_energy_drift, r.max_momentum_drift, r.max_orthonormality_error);
  // The body flips about its intermediate axis; each half turn of pitch is two switches.
  EXPECT_GE(r.switches, 10);
  // The dual-Euler switches whenever the rule, applied to the quaternion's attitude, would
  // (the two attitudes agree to 1e-13, far closer than any step start lies to pi/4).
  EXPECT_EQ(r.switches, r.quaternion_rule_switches);
  // Both are RK4 with identical body-rate stages; they differ only by their own O(dt^4)
  // truncation errors in two parametrisations, ~(|omega| dt)^4 * t = 1e-12 * 40 at most. The
  // first measurement was 3e-14; 1e-10 is the bound beyond which it is a bug, not truncation.
  EXPECT_LT(r.max_matrix_difference, 1e-10);
  // Energy and angular momentum are exact invariants; RK4 with dt = 1e-3 drifts by
  // O(dt^4) = 1e-12 per unit time at most.
  EXPECT_LT(r.max_energy_drift, 1e-10);
  EXPECT_LT(r.max_momentum_drift, 1e-10);
  // The matrix is built from three angles: orthonormal to rounding, whatever the history.
  EXPECT_LT(r.max_orthonormality_error, 1e-12);
}

// ---------------------------------------------------------------------------------------
// Symmetric top (I1 = I2): torque-free regular precession in closed form. With
// L_n = C_b^n I omega_b constant, C_b^n(t) = Rot(L_n/|L|, |L| t / I1) C_b^n(0) Rot(e3, -Omega t)
// and omega_b(t) = Rot(e3, Omega t) omega_b(0), Omega = (I3 - I1)/I1 * omega3 (e.g. Goldstein,
// Classical Mechanics, sec. 5.6; obtained here by substitution into C^T dC/dt = [omega_b]x).

struct SymmetricTop {
  double i1 = 1.0;
  double i3 = 1.7;
  Eigen::Vector3d omega0{0.6, -0.4, 1.3};
  Attitude initial = Attitude::from_set1(0.3, -0.5, 1.2);

  [[nodiscard]] BodyInertia inertia() const { return BodyInertia(Eigen::Vector3d(i1, i1, i3).asDiagonal()); }
  [[nodiscard]] double precession_rate_b() const { return (i3 - i1) / i1 * omega0[2]; }
  [[nodiscard]] Eigen::Vector3d momentum_n() const {
    return initial.body_to_inertial() * Eigen::Vector3d(i1 * omega0[0], i1 * omega0[1], i3 * omega0[2]);
  }
  [[nodiscard]] Eigen::Vector3d omega_b(double t) const {
    return rotation_about(Eigen::Vector3d::UnitZ(), precession_rate_b() * t) * omega0;
  }
  [[nodiscard]] Eigen::Matrix3d attitude(double t) const {
    const Eigen::Vector3d l = momentum_n();
    return rotation_about(l, l.norm() / i1 * t) * initial.body_to_inertial() *
           rotation_about(Eigen::Vector3d::UnitZ(), -precession_rate_b() * t);
  }
};

struct ClosedFormErrors {
  double attitude = 0.0;
  double omega = 0.0;
  int switches = 0;
};

ClosedFormErrors symmetric_top_dual_euler(const SymmetricTop& top, double dt, double t_end) {
  const BodyInertia inertia = top.inertia();
  SpinState state{top.omega0, top.initial};
  ClosedFormErrors errors;
  const auto steps = static_cast<int>(std::lround(t_end / dt));
  for (int i = 0; i < steps; ++i) {
    if (dual_euler_spin_step(state, inertia, i * dt, dt)) ++errors.switches;
    const double t = (i + 1) * dt;
    raise_to(errors.attitude, max_abs_difference(state.attitude.body_to_inertial(), top.attitude(t)));
    raise_to(errors.omega, (state.omega_b - top.omega_b(t)).cwiseAbs().maxCoeff());
  }
  return errors;
}

TEST(DualEulerTorqueFree, SymmetricTopFollowsRegularPrecession) {
  const SymmetricTop top;
  const ClosedFormErrors e = symmetric_top_dual_euler(top, 1e-3, 20.0);
  std::printf("[measured] symmetric top, dt=1e-3, t=20: max attitude error %.3g, omega error %.3g, switches %d\n",
              e.attitude, e.omega, e.switches);
  // The cone is wide enough that the pitch leaves the set-1 band: both charts are exercised.
  EXPECT_GE(e.switches, 2);
  // RK4 global error C t |omega|^5 dt^4 with |omega| ~ 1.5, t = 20, dt = 1e-3: ~1e-10 for
  // C ~ 1; the convergence test below measures the constant (error 1e-12 level here).
  EXPECT_LT(e.attitude, 1e-10);
  EXPECT_LT(e.omega, 1e-10);
}

TEST(QuaternionTorqueFree, SymmetricTopFollowsRegularPrecession) {
  const SymmetricTop top;
  const BodyInertia inertia = top.inertia();
  QuaternionSpinState state{top.omega0, top.initial.quaternion()};
  double error = 0.0;
  const double dt = 1e-3;
  for (int i = 0; i < 20000; ++i) {
    quaternion_spin_step(state, inertia, i * dt, dt);
    raise_to(error, max_abs_difference(state.orientation.toRotationMatrix(), top.attitude((i + 1) * dt)));
  }
  // Same RK4 error estimate as for the dual-Euler solver.
  EXPECT_LT(error, 1e-10);
}

TEST(DualEulerTorqueFree, ConvergesAtFourthOrder) {
  // Smooth case: the symmetric top above over 10 time units (several set switches). dt from
  // 0.04 down to 0.01 keeps the error (1e-6 .. 1e-9) far above round-off (1e-14).
  const SymmetricTop top;
  const double coarse = symmetric_top_dual_euler(top, 0.04, 10.0).attitude;
  const double medium = symmetric_top_dual_euler(top, 0.02, 10.0).attitude;
  const double fine = symmetric_top_dual_euler(top, 0.01, 10.0).attitude;
  const double order_coarse = std::log2(coarse / medium);
  const double order_fine = std::log2(medium / fine);
  std::printf("[measured] convergence: errors %.3g %.3g %.3g, observed orders %.3f %.3f\n", coarse, medium, fine,
              order_coarse, order_fine);
  // Classical RK4 is fourth order; the window allows for the rounding left at the finest step.
  EXPECT_GT(order_fine, 3.8);
  EXPECT_LT(order_fine, 4.2);
  EXPECT_GT(order_coarse, 3.8);
  EXPECT_LT(order_coarse, 4.2);
}

// ---------------------------------------------------------------------------------------
// Kinematics with prescribed body rates.

TEST(DualEulerKinematics, ConstantRotationAboutBodyYThroughManyTurns) {
  const double rate = 2.0;
  const double dt = 1e-3;
  for (const Attitude& initial : {Attitude(), Attitude::from_set1(0.4, 0.2, -0.7)}) {
    Attitude attitude = initial;
    const BodyRateFunction omega_b = [rate](double) { return Eigen::Vector3d(0.0, rate, 0.0); };
    int switches = 0;
    double error = 0.0;
    for (int i = 0; i < 20000; ++i) {  // 40 rad: 6.4 turns, pitch through +-pi/2 25 times
      if (dual_euler_step(attitude, i * dt, dt, omega_b)) ++switches;
      const Eigen::Matrix3d r = attitude.body_to_inertial();
      ASSERT_TRUE(r.allFinite()) << "step " << i;
      const Eigen::Matrix3d exact =
          initial.body_to_inertial() * rotation_about(Eigen::Vector3d::UnitY(), rate * (i + 1) * dt);
      raise_to(error, max_abs_difference(r, exact));
    }
    std::printf("[measured] constant body-y rotation: %d switches, max error %.3g\n", switches, error);
    EXPECT_GE(switches, 20);
    // From the identity the angles are linear in t (RK4 exact up to rounding accumulated
    // over 20000 steps, at most 2e4 * eps ~ 4e-12; measured 4e-13); from a generic start the
    // RK4 error adds ~ t |omega|^5 dt^4 = 20 * 32 * 1e-12 at most (measured 4e-12). 1e-10
    // is 25 times the larger measured error.
    EXPECT_LT(error, 1e-10);
  }
}

TEST(DualEulerKinematics, TwoPointFormEqualsLinearRateFunction) {
  // The coupled solver's form interpolates linearly between the step's end rates; for body
  // rates that are linear in time it must be the function form itself.
  const Eigen::Vector3d start(0.3, -1.2, 0.8), end(-0.5, 0.9, 1.4);
  const double dt = 0.05;
  for (const Attitude& initial : {Attitude::from_set1(0.2, 0.1, -0.4), Attitude::from_set1(1.0, 1.2, 0.3)}) {
    Attitude two_point = initial;
    Attitude function_form = initial;
    const bool switched = dual_euler_step(two_point, dt, start, end);
    const bool switched_too = dual_euler_step(
        function_form, 10.0, dt, [&](double t) -> Eigen::Vector3d { return start + (t - 10.0) / dt * (end - start); });
    EXPECT_EQ(switched, switched_too);
    // Same arithmetic up to the rounding of the interpolation weights: a few ulps.
    EXPECT_LT(max_abs_difference(two_point.body_to_inertial(), function_form.body_to_inertial()), 1e-15);
  }
}

TEST(DualEulerKinematics, TimeVaryingRatesAgreeWithQuaternion) {
  // Rates with all three components varying in time, through both charts.
  const BodyRateFunction omega_b = [](double t) {
    return Eigen::Vector3d(0.7 * std::sin(1.3 * t), 1.1 + 0.4 * std::cos(0.7 * t), -0.5 * std::cos(2.1 * t));
  };
  Attitude attitude = Attitude::from_set1(-0.6, 0.3, 2.0);
  Eigen::Quaterniond q = attitude.quaternion();
  const double dt = 1e-3;
  int switches = 0;
  double difference = 0.0;
  for (int i = 0; i < 20000; ++i) {
    if (dual_euler_step(attitude, i * dt, dt, omega_b)) ++switches;
    q = quaternion_step(q, i * dt, dt, omega_b);
    raise_to(difference, max_abs_difference(attitude.body_to_inertial(), q.toRotationMatrix()));
  }
  std::printf("[measured] time-varying rates: %d switches, max |R_dual - R_quat| %.3g\n", switches, difference);
  EXPECT_GE(switches, 4);
  // Both RK4 with the same rate samples: O(dt^4) truncation differences, 1e-12 per unit time.
  EXPECT_LT(difference, 1e-10);
}

TEST(DualEulerKinematics, SwitchIsExactAndChangesNoAttitude) {
  // Pitch just past pi/4 in set 1: the rule moves to set 2 through the matrix.
  Attitude attitude = Attitude::from_set1(0.5, pi / 4 + 0.01, -0.3);
  const Eigen::Matrix3d before = attitude.body_to_inertial();
  EXPECT_TRUE(apply_switching_rule(attitude));
  EXPECT_EQ(attitude.set(), EulerSet::set2);
  // One conversion of unit-size entries: rounding level.
  EXPECT_LT(max_abs_difference(attitude.body_to_inertial(), before), 1e-15);
  EXPECT_FALSE(apply_switching_rule(attitude));  // already in the preferred chart
}

TEST(DualEulerKinematics, PitchExactlyHalfPiStepsWithoutNaN) {
  // A start exactly at the set-1 singularity: the rule must leave set 1 before S7 is used.
  const BodyRateFunction omega_b = [](double) { return Eigen::Vector3d(0.4, -0.3, 0.9); };
  for (double sign : {1.0, -1.0}) {
    Attitude attitude = Attitude::from_set1(0.3, sign * pi / 2, -0.8);
    Eigen::Quaterniond q = attitude.quaternion();
    const double dt = 1e-3;
    for (int i = 0; i < 100; ++i) {
      dual_euler_step(attitude, i * dt, dt, omega_b);
      q = quaternion_step(q, i * dt, dt, omega_b);
    }
    EXPECT_EQ(attitude.set(), EulerSet::set2);
    ASSERT_TRUE(attitude.angles().allFinite());
    // 100 steps with local truncation ~ (|omega| dt)^5 / 120 ~ 1e-17 each: rounding level.
    EXPECT_LT(max_abs_difference(attitude.body_to_inertial(), q.toRotationMatrix()), 1e-14);
  }
}

TEST(QuaternionKinematics, ConstantRateIsExactRotation) {
  const Eigen::Vector3d omega(0.3, -0.2, 0.9);
  Eigen::Quaterniond q = Eigen::Quaterniond::Identity();
  const double dt = 1e-2;
  for (int i = 0; i < 1000; ++i) q = quaternion_step(q, i * dt, dt, [&](double) { return omega; });
  const Eigen::Matrix3d exact = rotation_about(omega, omega.norm() * 10.0);
  // Constant rate: RK4 of a linear ODE, error (|omega| dt)^5 / 120 ~ 1e-14 per step, times
  // 1000 steps.
  EXPECT_LT(max_abs_difference(q.toRotationMatrix(), exact), 1e-10);
  EXPECT_NEAR(q.norm(), 1.0, 1e-15);
}

TEST(RotationalDynamics, GyroscopicTermOfFullTensor) {
  // Euler's equations with a non-diagonal tensor: I domega/dt = T - omega x (I omega).
  Eigen::Matrix3d tensor;
  tensor << 2.0, 0.3, -0.1,  //
      0.3, 1.5, 0.2,         //
      -0.1, 0.2, 1.0;
  const BodyInertia inertia(tensor);
  const Eigen::Vector3d omega(0.4, -1.1, 0.7), torque(0.2, 0.0, -0.3);
  const Eigen::Vector3d acceleration = angular_acceleration_b(inertia, omega, torque);
  // Residual of the defining equation: rounding of unit-size products, ~1e-15.
  EXPECT_LT((tensor * acceleration + omega.cross(tensor * omega) - torque).cwiseAbs().maxCoeff(), 1e-14);
}

TEST(RotationalDynamics, RejectsInvalidTensors) {
  Eigen::Matrix3d asymmetric = Eigen::Matrix3d::Identity();
  asymmetric(0, 1) = 0.1;
  EXPECT_THROW(BodyInertia{asymmetric}, std::invalid_argument);
  EXPECT_THROW(BodyInertia{Eigen::Matrix3d(Eigen::Vector3d(1.0, -1.0, 1.0).asDiagonal())}, std::invalid_argument);
  EXPECT_THROW(BodyInertia{Eigen::Matrix3d::Zero()}, std::invalid_argument);
}

}  // namespace test_integrators
}  // namespace settle::attitude
