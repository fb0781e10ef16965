#include "attitude/integrators.hpp"

#include "attitude/rk4.hpp"

namespace settle::attitude {

bool apply_switching_rule(Attitude& attitude) {
  const Eigen::Vector3d wrapped = attitude.angles().unaryExpr([](double a) { return wrap_angle(a); });
  attitude = Attitude(attitude.set(), wrapped);
  const EulerSet preferred = attitude.preferred_set();
  if (preferred == attitude.set()) return false;
  attitude = attitude.in_set(preferred);
  return true;
}

Attitude rk4_angles_step(const Attitude& attitude, double t, double dt, const BodyRateFunction& omega_b) {
  const EulerSet set = attitude.set();
  const auto derivative = [&](double time, const Eigen::Vector3d& angles) -> Eigen::Vector3d {
    return angle_rates(set, angles, omega_b(time));
  };
  return {set, rk4_step(attitude.angles(), t, dt, derivative)};
}

bool dual_euler_step(Attitude& attitude, double t, double dt, const BodyRateFunction& omega_b) {
  const bool switched = apply_switching_rule(attitude);
  attitude = rk4_angles_step(attitude, t, dt, omega_b);
  return switched;
}

bool dual_euler_step(Attitude& attitude, double dt, const Eigen::Vector3d& omega_start_b,
                     const Eigen::Vector3d& omega_end_b) {
  const auto interpolated = [&](double time) -> Eigen::Vector3d {
    const double fraction = time / dt;
    return (1.0 - fraction) * omega_start_b + fraction * omega_end_b;
  };
  return dual_euler_step(attitude, 0.0, dt, interpolated);
}

Eigen::Vector4d quaternion_rate(const Eigen::Vector4d& q_coeffs, const Eigen::Vector3d& omega_b) {
  const Eigen::Quaterniond q(q_coeffs[3], q_coeffs[0], q_coeffs[1], q_coeffs[2]);
  const Eigen::Quaterniond pure(0.0, omega_b[0], omega_b[1], omega_b[2]);
  return 0.5 * (q * pure).coeffs();
}

Eigen::Quaterniond quaternion_step(const Eigen::Quaterniond& q, double t, double dt, const BodyRateFunction& omega_b) {
  const auto derivative = [&](double time, const Eigen::Vector4d& coeffs) -> Eigen::Vector4d {
    return quaternion_rate(coeffs, omega_b(time));
  };
  const Eigen::Vector4d next = rk4_step(Eigen::Vector4d(q.coeffs()), t, dt, derivative);
  return Eigen::Quaterniond(next[3], next[0], next[1], next[2]).normalized();
}

}  // namespace settle::attitude
