// Equations (S1)-(S12) of Cheng, Cao, Li & Borthwick (2023), Phys. Fluids 35,
// doi:10.1063/5.0165555, supplementary material. See euler.hpp for the conventions.
#include "attitude/euler.hpp"

#include <cmath>
#include <numbers>

namespace settle::attitude {

Eigen::Matrix3d elementary_psi(double psi) {
  const double c = std::cos(psi);
  const double s = std::sin(psi);
  Eigen::Matrix3d m;
  m << c, s, 0.0,  //
      -s, c, 0.0,  //
      0.0, 0.0, 1.0;
  return m;
}

Eigen::Matrix3d elementary_theta(double theta) {
  const double c = std::cos(theta);
  const double s = std::sin(theta);
  Eigen::Matrix3d m;
  m << c, 0.0, -s,    //
      0.0, 1.0, 0.0,  //
      s, 0.0, c;
  return m;
}

Eigen::Matrix3d elementary_gamma(double gamma) {
  const double c = std::cos(gamma);
  const double s = std::sin(gamma);
  Eigen::Matrix3d m;
  m << 1.0, 0.0, 0.0,  //
      0.0, c, s,       //
      0.0, -s, c;
  return m;
}

Eigen::Matrix3d set1_body_to_inertial(const Eigen::Vector3d& angles) {
  const double cps = std::cos(angles[0]), sps = std::sin(angles[0]);
  const double cth = std::cos(angles[1]), sth = std::sin(angles[1]);
  const double cga = std::cos(angles[2]), sga = std::sin(angles[2]);
  Eigen::Matrix3d m;
  m << cps * cth, cps * sth * sga - sps * cga, cps * sth * cga + sps * sga,  //
      sps * cth, sps * sth * sga + cps * cga, sps * sth * cga - cps * sga,   //
      -sth, cth * sga, cth * cga;
  return m;
}

Eigen::Matrix3d set2_body_to_inertial(const Eigen::Vector3d& angles) {
  const double cps = std::cos(angles[0]), sps = std::sin(angles[0]);
  const double cth = std::cos(angles[1]), sth = std::sin(angles[1]);
  const double cga = std::cos(angles[2]), sga = std::sin(angles[2]);
  Eigen::Matrix3d m;
  m << cth * cps - sth * sga * sps, -cga * sps, sth * cps + cth * sga * sps,  //
      cth * sps + sth * sga * cps, cga * cps, sth * sps - cth * sga * cps,    //
      -sth * cga, sga, cth * cga;
  return m;
}

Eigen::Matrix3d body_to_inertial(EulerSet set, const Eigen::Vector3d& angles) {
  return set == EulerSet::set1 ? set1_body_to_inertial(angles) : set2_body_to_inertial(angles);
}

Eigen::Vector3d set1_body_rates(const Eigen::Vector3d& angles, const Eigen::Vector3d& angle_rates) {
  const Eigen::Matrix3d c_gamma = elementary_gamma(angles[2]);
  const Eigen::Matrix3d c_theta = elementary_theta(angles[1]);
  return Eigen::Vector3d(angle_rates[2], 0.0, 0.0) + c_gamma * Eigen::Vector3d(0.0, angle_rates[1], 0.0) +
         c_gamma * c_theta * Eigen::Vector3d(0.0, 0.0, angle_rates[0]);
}

Eigen::Vector3d set2_body_rates(const Eigen::Vector3d& angles, const Eigen::Vector3d& angle_rates) {
  // The last rotation of the sequence (theta_r about y) is seen directly in the body frame;
  // the earlier ones are carried through the later elementary rotations.
  const Eigen::Matrix3d c_theta = elementary_theta(angles[1]);
  const Eigen::Matrix3d c_gamma = elementary_gamma(angles[2]);
  return Eigen::Vector3d(0.0, angle_rates[1], 0.0) + c_theta * Eigen::Vector3d(angle_rates[2], 0.0, 0.0) +
         c_theta * c_gamma * Eigen::Vector3d(0.0, 0.0, angle_rates[0]);
}

Eigen::Vector3d set1_angle_rates(const Eigen::Vector3d& angles, const Eigen::Vector3d& omega_b) {
  const double cth = std::cos(angles[1]), sth = std::sin(angles[1]);
  const double cga = std::cos(angles[2]), sga = std::sin(angles[2]);
  const double wx = omega_b[0], wy = omega_b[1], wz = omega_b[2];
  // S7, rows (gamma, theta, psi) of the seed, stored as (psi, theta, gamma).
  const double gamma_rate = (cth * wx + sga * sth * wy + cga * sth * wz) / cth;
  const double theta_rate = cga * wy - sga * wz;
  const double psi_rate = (sga * wy + cga * wz) / cth;
  return {psi_rate, theta_rate, gamma_rate};
}

Eigen::Vector3d set2_angle_rates(const Eigen::Vector3d& angles, const Eigen::Vector3d& omega_b) {
  const double cth = std::cos(angles[1]), sth = std::sin(angles[1]);
  const double cga = std::cos(angles[2]), sga = std::sin(angles[2]);
  const double wx = omega_b[0], wy = omega_b[1], wz = omega_b[2];
  // S9, rows (gamma_r, theta_r, psi_r) of the seed, stored as (psi_r, theta_r, gamma_r).
  const double gamma_rate = cth * wx + sth * wz;
  const double theta_rate = (sth * sga * wx + cga * wy - cth * sga * wz) / cga;
  const double psi_rate = (-sth * wx + cth * wz) / cga;
  return {psi_rate, theta_rate, gamma_rate};
}

Eigen::Vector3d angle_rates(EulerSet set, const Eigen::Vector3d& angles, const Eigen::Vector3d& omega_b) {
  return set == EulerSet::set1 ? set1_angle_rates(angles, omega_b) : set2_angle_rates(angles, omega_b);
}

// The middle angle of each sequence is the seed's arcsine (theta = -asin(z31) in S12,
// gamma_r = asin(z32) in S11), evaluated as atan2(sin, cos) with the cosine taken as the
// length of the rest of its matrix row. For an orthonormal matrix the two are identical; the
// arcsine, however, has an infinite slope at +-1: within 1e-8 rad of the singular angle
// sin() rounds to exactly 1 and asin() returns the singular angle itself, an error of 1e-8
// in the reconstructed matrix, while the cosine entries still carry the angle to full
// precision. atan2 also needs no clamping of a rounded argument slightly beyond [-1, 1].
//
// The first two angles are the supplement's, with two-argument arctangents of matrix entries
// (docs/architecture.md, "Frames and attitude"). The
// third is taken from what is left of the matrix once the other two rotations are
// removed. Away from the singular point that equals the seed's formula (psi = atan2(z21, z11),
// psi_r = atan2(-z12, z22)) algebraically; at and near the singular point the seed's
// entries for both outer angles are rounding noise, so two separate arctangents would pick
// two unrelated angles and rebuild a wrong matrix, whereas the remainder picks the one
// angle consistent with the first, so the matrix is always reproduced.

Eigen::Vector3d set1_angles_from_matrix(const Eigen::Matrix3d& z) {
  const double theta = std::atan2(-z(2, 0), std::hypot(z(2, 1), z(2, 2)));
  const double gamma = std::atan2(z(2, 1), z(2, 2));
  // Rz(psi) = z Rx(gamma)^T Ry(theta)^T; its first column is (cos psi, sin psi, 0).
  const double cth = std::cos(theta), sth = std::sin(theta);
  const double cga = std::cos(gamma), sga = std::sin(gamma);
  const Eigen::Vector3d first_column = cth * z.col(0) + sth * sga * z.col(1) + sth * cga * z.col(2);
  const double psi = std::atan2(first_column[1], first_column[0]);
  return {psi, theta, gamma};
}

Eigen::Vector3d set2_angles_from_matrix(const Eigen::Matrix3d& z) {
  const double gamma_r = std::atan2(z(2, 1), std::hypot(z(2, 0), z(2, 2)));
  const double theta_r = std::atan2(-z(2, 0), z(2, 2));
  // Rz(psi_r) = z Ry(theta_r)^T Rx(gamma_r)^T; its first column is (cos psi_r, sin psi_r, 0).
  const Eigen::Vector3d first_column = std::cos(theta_r) * z.col(0) + std::sin(theta_r) * z.col(2);
  const double psi_r = std::atan2(first_column[1], first_column[0]);
  return {psi_r, theta_r, gamma_r};
}

Eigen::Vector3d angles_from_matrix(EulerSet set, const Eigen::Matrix3d& body_to_inertial) {
  return set == EulerSet::set1 ? set1_angles_from_matrix(body_to_inertial) : set2_angles_from_matrix(body_to_inertial);
}

double wrap_angle(double angle) {
  constexpr double two_pi = 2.0 * std::numbers::pi;
  double wrapped = std::remainder(angle, two_pi);  // in [-pi, pi]
  if (wrapped <= -std::numbers::pi) wrapped += two_pi;
  return wrapped;
}

}  // namespace settle::attitude
