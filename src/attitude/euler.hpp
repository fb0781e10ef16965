#pragma once
// The two Euler-angle sets of the dual-Euler whole-attitude solver: elementary rotations,
// attitude matrices, angle-rate maps and the conversion between the sets.
//
// Source: X. Cheng, Z. Cao, J. Li, A. Borthwick, "A numerical study of the settling of
// non-spherical particles in quiescent water", Phys. Fluids 35 (2023), supplementary
// material, Eqs. (S1)-(S12), doi:10.1063/5.0165555; the idea of switching between two Euler
// sets is from P. Singla, D. Mortari, J.L. Junkins, "How to avoid singularity when using
// Euler angles?", Adv. Astron. Sci. 119, 1409-1426 (2005).
//
// Conventions (used throughout settle::attitude):
// - Frames: n is the inertial frame, b the body frame.
// - The elementary matrices C_psi, C_theta, C_gamma (S1-S3) are frame-rotation (passive)
//   matrices about z, y and x: they map components in the old frame to components in the
//   frame rotated by the angle. Their transposes are the active rotations Rz, Ry, Rx.
// - "body_to_inertial" is C_b^n: v_n = C_b^n v_b. Its transpose C_n^b maps inertial
//   components to body components.
// - Body angular velocity omega_b is the angular velocity of frame b relative to n, in b
//   components, so that d(C_b^n)/dt = C_b^n [omega_b]x.
// - Angle vectors (Eigen::Vector3d), in this order:
//     set 1 (sequence psi -> theta -> gamma):       (psi, theta, gamma)
//     set 2 (sequence psi_r -> gamma_r -> theta_r):  (psi_r, theta_r, gamma_r)
//   Angle-rate vectors use the same order. (The seed writes its rate vectors in the order
//   (gamma, theta, psi); only the storage order differs, not the equations.)
// - Set 1 is the z-y-x (yaw, pitch, roll) sequence: C_b^n = Rz(psi) Ry(theta) Rx(gamma).
//   Set 2 is the z-x-y sequence: (C_b^n)_r = Rz(psi_r) Rx(gamma_r) Ry(theta_r).
#include <Eigen/Core>

namespace settle::attitude {

/// Which Euler set a chart of the attitude atlas uses. The values are the numbers written
/// in the euler_set output column.
enum class EulerSet : int { set1 = 1, set2 = 2 };

/// S1: frame rotation by psi about z.
[[nodiscard]] Eigen::Matrix3d elementary_psi(double psi);
/// S2: frame rotation by theta about y.
[[nodiscard]] Eigen::Matrix3d elementary_theta(double theta);
/// S3: frame rotation by gamma about x.
[[nodiscard]] Eigen::Matrix3d elementary_gamma(double gamma);

/// S5: C_b^n of set 1, written out; equals (C_gamma C_theta C_psi)^T (S4).
/// angles = (psi, theta, gamma).
[[nodiscard]] Eigen::Matrix3d set1_body_to_inertial(const Eigen::Vector3d& angles);
/// S8: (C_b^n)_r of set 2, written out; equals (C_theta_r C_gamma_r C_psi_r)^T.
/// angles = (psi_r, theta_r, gamma_r).
[[nodiscard]] Eigen::Matrix3d set2_body_to_inertial(const Eigen::Vector3d& angles);
/// S5 or S8 according to the set.
[[nodiscard]] Eigen::Matrix3d body_to_inertial(EulerSet set, const Eigen::Vector3d& angles);

/// S6: body rates from set-1 angle rates, omega_b = (gamma_dot,0,0) + C_gamma (0,theta_dot,0)
/// + C_gamma C_theta (0,0,psi_dot). Regular everywhere.
[[nodiscard]] Eigen::Vector3d set1_body_rates(const Eigen::Vector3d& angles, const Eigen::Vector3d& angle_rates);
/// Set-2 counterpart of S6 (derived here from the sequence psi_r -> gamma_r -> theta_r):
/// omega_b = (0,theta_r_dot,0) + C_theta_r (gamma_r_dot,0,0) + C_theta_r C_gamma_r (0,0,psi_r_dot).
[[nodiscard]] Eigen::Vector3d set2_body_rates(const Eigen::Vector3d& angles, const Eigen::Vector3d& angle_rates);

/// S7: set-1 angle rates (psi_dot, theta_dot, gamma_dot) from body rates. Singular at
/// cos(theta) = 0; the dual-Euler rule keeps |cos(theta)| >= cos(pi/4) when it is used.
[[nodiscard]] Eigen::Vector3d set1_angle_rates(const Eigen::Vector3d& angles, const Eigen::Vector3d& omega_b);
/// S9: set-2 angle rates (psi_r_dot, theta_r_dot, gamma_r_dot) from body rates. Singular at
/// cos(gamma_r) = 0.
[[nodiscard]] Eigen::Vector3d set2_angle_rates(const Eigen::Vector3d& angles, const Eigen::Vector3d& omega_b);
/// S7 or S9 according to the set.
[[nodiscard]] Eigen::Vector3d angle_rates(EulerSet set, const Eigen::Vector3d& angles, const Eigen::Vector3d& omega_b);

/// S12: set-1 angles of a rotation matrix C_b^n (assumed orthonormal). Results lie in
/// psi in (-pi, pi], theta in [-pi/2, pi/2], gamma in (-pi, pi]. See euler.cpp for how the
/// seed's formulas are made robust at and near the singular point theta = +-pi/2, where
/// only psi - gamma (theta = pi/2) or psi + gamma (theta = -pi/2) is defined.
[[nodiscard]] Eigen::Vector3d set1_angles_from_matrix(const Eigen::Matrix3d& body_to_inertial);
/// S11: set-2 angles of a rotation matrix C_b^n. Results lie in psi_r in (-pi, pi],
/// theta_r in (-pi, pi], gamma_r in [-pi/2, pi/2].
[[nodiscard]] Eigen::Vector3d set2_angles_from_matrix(const Eigen::Matrix3d& body_to_inertial);
/// S11 or S12 according to the set.
[[nodiscard]] Eigen::Vector3d angles_from_matrix(EulerSet set, const Eigen::Matrix3d& body_to_inertial);

/// The angle wrapped into (-pi, pi].
[[nodiscard]] double wrap_angle(double angle);

}  // namespace settle::attitude
