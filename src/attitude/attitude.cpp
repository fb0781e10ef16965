#include "attitude/attitude.hpp"

#include <cmath>
#include <numbers>

namespace settle::attitude {
namespace {

Eigen::Quaterniond about_axis(double angle, const Eigen::Vector3d& axis) {
  return Eigen::Quaterniond(Eigen::AngleAxisd(angle, axis));
}

/// The set-1 pitch of a matrix: -asin(z31), written as in set1_angles_from_matrix.
double pitch_of(const Eigen::Matrix3d& z) { return std::atan2(-z(2, 0), std::hypot(z(2, 1), z(2, 2))); }

}  // namespace

Attitude Attitude::from_set1(double psi, double theta, double gamma) {
  return {EulerSet::set1, Eigen::Vector3d(psi, theta, gamma)};
}

Attitude Attitude::from_set2(double psi_r, double theta_r, double gamma_r) {
  return {EulerSet::set2, Eigen::Vector3d(psi_r, theta_r, gamma_r)};
}

Attitude Attitude::from_matrix(const Eigen::Matrix3d& body_to_inertial, EulerSet set) {
  return {set, angles_from_matrix(set, body_to_inertial)};
}

Attitude Attitude::from_matrix(const Eigen::Matrix3d& body_to_inertial) {
  return from_matrix(body_to_inertial, attitude::preferred_set(body_to_inertial));
}

Attitude Attitude::from_quaternion(const Eigen::Quaterniond& body_to_inertial) {
  return from_matrix(body_to_inertial.normalized().toRotationMatrix());
}

Eigen::Matrix3d Attitude::body_to_inertial() const { return attitude::body_to_inertial(set_, angles_); }

Eigen::Quaterniond Attitude::quaternion() const {
  // C_b^n = Rz(psi) Ry(theta) Rx(gamma) (set 1) or Rz(psi_r) Rx(gamma_r) Ry(theta_r) (set 2);
  // composing the axis quaternions avoids the round trip through a matrix.
  const Eigen::Vector3d& a = angles_;
  Eigen::Quaterniond q = set_ == EulerSet::set1
                             ? about_axis(a[0], Eigen::Vector3d::UnitZ()) * about_axis(a[1], Eigen::Vector3d::UnitY()) *
                                   about_axis(a[2], Eigen::Vector3d::UnitX())
                             : about_axis(a[0], Eigen::Vector3d::UnitZ()) * about_axis(a[2], Eigen::Vector3d::UnitX()) *
                                   about_axis(a[1], Eigen::Vector3d::UnitY());
  if (q.w() < 0.0) q.coeffs() = -q.coeffs();
  return q;
}

Eigen::Vector3d Attitude::set1_angles() const {
  if (set_ == EulerSet::set1) return angles_.unaryExpr([](double a) { return wrap_angle(a); });
  return set1_angles_from_matrix(body_to_inertial());
}

Eigen::Vector3d Attitude::set2_angles() const {
  if (set_ == EulerSet::set2) return angles_.unaryExpr([](double a) { return wrap_angle(a); });
  return set2_angles_from_matrix(body_to_inertial());
}

Attitude Attitude::in_set(EulerSet set) const {
  if (set == set_) return *this;
  return from_matrix(body_to_inertial(), set);
}

Eigen::Vector3d Attitude::angle_rates(const Eigen::Vector3d& omega_b) const {
  return attitude::angle_rates(set_, angles_, omega_b);
}

EulerSet Attitude::preferred_set() const {
  // Set 1 carries its own pitch, which may lie outside [-pi/2, pi/2] (the seed's
  // |theta| > 3pi/4 branch); set 2's attitude gives the set-1 pitch through the matrix.
  const double theta = set_ == EulerSet::set1 ? angles_[1] : pitch_of(body_to_inertial());
  return preferred_set_for_pitch(theta);
}

EulerSet preferred_set_for_pitch(double theta) {
  constexpr double quarter_pi = std::numbers::pi / 4.0;
  const double magnitude = std::abs(wrap_angle(theta));
  return (magnitude <= quarter_pi || magnitude > 3.0 * quarter_pi) ? EulerSet::set1 : EulerSet::set2;
}

EulerSet preferred_set(const Eigen::Matrix3d& body_to_inertial) {
  return preferred_set_for_pitch(pitch_of(body_to_inertial));
}

}  // namespace settle::attitude
