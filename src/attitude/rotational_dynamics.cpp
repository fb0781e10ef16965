#include "attitude/rotational_dynamics.hpp"

#include <stdexcept>

#include <Eigen/Cholesky>

#include "attitude/integrators.hpp"
#include "attitude/rk4.hpp"

namespace settle::attitude {
namespace {

using Vector6d = Eigen::Matrix<double, 6, 1>;
using Vector7d = Eigen::Matrix<double, 7, 1>;

}  // namespace

BodyInertia::BodyInertia(const Eigen::Matrix3d& tensor_b) : tensor_(tensor_b) {
  const double scale = tensor_b.cwiseAbs().maxCoeff();
  if (!tensor_b.allFinite() || !(scale > 0.0)) {
    throw std::invalid_argument("inertia tensor must be finite and non-zero");
  }
  // Tensors from exact mass-property integrals are symmetric to round-off.
  if ((tensor_b - tensor_b.transpose()).cwiseAbs().maxCoeff() > 1e-12 * scale) {
    throw std::invalid_argument("inertia tensor must be symmetric");
  }
  const Eigen::LLT<Eigen::Matrix3d> cholesky(tensor_b);
  if (cholesky.info() != Eigen::Success) {
    throw std::invalid_argument("inertia tensor must be positive definite");
  }
  // Column by column: a matrix right-hand side takes Eigen's blocked triangular solve, whose
  // AVX-512 code GCC 12 reports as reading uninitialised vectors (a false positive, GCC bug 105593).
  for (int axis = 0; axis < 3; ++axis) inverse_.col(axis) = cholesky.solve(Eigen::Vector3d::Unit(axis));
}

Eigen::Vector3d angular_acceleration_b(const BodyInertia& inertia, const Eigen::Vector3d& omega_b,
                                       const Eigen::Vector3d& torque_b) {
  const Eigen::Vector3d gyroscopic = omega_b.cross(inertia.tensor() * omega_b);
  return inertia.inverse() * (torque_b - gyroscopic);
}

bool dual_euler_spin_step(SpinState& state, const BodyInertia& inertia, double t, double dt,
                          const BodyTorqueFunction& torque_b) {
  const bool switched = apply_switching_rule(state.attitude);
  const EulerSet set = state.attitude.set();
  const auto derivative = [&](double time, const Vector6d& y) -> Vector6d {
    const Eigen::Vector3d omega = y.head<3>();
    const Eigen::Vector3d angles = y.tail<3>();
    const Eigen::Vector3d torque =
        torque_b ? torque_b(time, omega, body_to_inertial(set, angles)) : Eigen::Vector3d::Zero();
    Vector6d rate;
    rate << angular_acceleration_b(inertia, omega, torque), angle_rates(set, angles, omega);
    return rate;
  };
  Vector6d y;
  y << state.omega_b, state.attitude.angles();
  const Vector6d next = rk4_step(y, t, dt, derivative);
  state.omega_b = next.head<3>();
  state.attitude = Attitude(set, next.tail<3>());
  return switched;
}

void quaternion_spin_step(QuaternionSpinState& state, const BodyInertia& inertia, double t, double dt,
                          const BodyTorqueFunction& torque_b) {
  const auto derivative = [&](double time, const Vector7d& y) -> Vector7d {
    const Eigen::Vector3d omega = y.head<3>();
    const Eigen::Vector4d coeffs = y.tail<4>();
    // Stage quaternions are not exactly unit; the torque sees the rotation they represent.
    const Eigen::Vector3d torque =
        torque_b
            ? torque_b(time, omega,
                       Eigen::Quaterniond(coeffs[3], coeffs[0], coeffs[1], coeffs[2]).normalized().toRotationMatrix())
            : Eigen::Vector3d::Zero();
    Vector7d rate;
    rate << angular_acceleration_b(inertia, omega, torque), quaternion_rate(coeffs, omega);
    return rate;
  };
  Vector7d y;
  y << state.omega_b, state.orientation.coeffs();
  const Vector7d next = rk4_step(y, t, dt, derivative);
  state.omega_b = next.head<3>();
  state.orientation = Eigen::Quaterniond(next[6], next[3], next[4], next[5]).normalized();
}

double rotational_energy(const BodyInertia& inertia, const Eigen::Vector3d& omega_b) {
  return 0.5 * omega_b.dot(inertia.tensor() * omega_b);
}

}  // namespace settle::attitude
