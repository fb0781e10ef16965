#pragma once
// The attitude state of the dual-Euler whole-attitude solver (Cheng et al. 2023,
// doi:10.1063/5.0165555, supplementary material; Singla, Mortari & Junkins 2005).
#include <Eigen/Core>
#include <Eigen/Geometry>

#include "attitude/euler.hpp"

namespace settle::attitude {

/// Orientation of the body frame b relative to the inertial frame n, stored as one chart of
/// an atlas of two: the active Euler set and its three angles (order in euler.hpp: set 1 =
/// (psi, theta, gamma), set 2 = (psi_r, theta_r, gamma_r)). The attitude matrix and the
/// quaternion are derived on demand and never stored, so nothing can drift apart.
///
/// body_to_inertial() is C_b^n (v_n = C_b^n v_b). quaternion() is the unit quaternion of the
/// same rotation (q v_b q* = v_n), with non-negative scalar part.
class Attitude {
 public:
  /// The identity attitude in set 1.
  Attitude() = default;
  /// A chart given directly: the set and its angles (no conversion).
  Attitude(EulerSet set, const Eigen::Vector3d& angles) : set_(set), angles_(angles) {}

  /// Set-1 chart (sequence psi -> theta -> gamma), angles in rad.
  [[nodiscard]] static Attitude from_set1(double psi, double theta, double gamma);
  /// Set-2 chart (sequence psi_r -> gamma_r -> theta_r), angles in rad.
  [[nodiscard]] static Attitude from_set2(double psi_r, double theta_r, double gamma_r);
  /// The rotation C_b^n (orthonormal, det +1) in the given chart.
  [[nodiscard]] static Attitude from_matrix(const Eigen::Matrix3d& body_to_inertial, EulerSet set);
  /// The rotation C_b^n in the chart the switching rule prefers for it.
  [[nodiscard]] static Attitude from_matrix(const Eigen::Matrix3d& body_to_inertial);
  /// The rotation of a unit quaternion (body to inertial) in the preferred chart.
  [[nodiscard]] static Attitude from_quaternion(const Eigen::Quaterniond& body_to_inertial);

  [[nodiscard]] EulerSet set() const { return set_; }
  /// The active set's angles, in the order of euler.hpp.
  [[nodiscard]] const Eigen::Vector3d& angles() const { return angles_; }

  /// C_b^n from the active chart (S5 or S8).
  [[nodiscard]] Eigen::Matrix3d body_to_inertial() const;
  /// C_n^b = (C_b^n)^T.
  [[nodiscard]] Eigen::Matrix3d inertial_to_body() const { return body_to_inertial().transpose(); }
  /// The unit quaternion composed from the active set's elementary rotations.
  [[nodiscard]] Eigen::Quaterniond quaternion() const;

  /// Set-1 angles (psi, theta, gamma): the active angles wrapped into (-pi, pi] when set 1 is
  /// active, else converted through the matrix (S12).
  [[nodiscard]] Eigen::Vector3d set1_angles() const;
  /// Set-2 angles (psi_r, theta_r, gamma_r), likewise (S11 when set 1 is active).
  [[nodiscard]] Eigen::Vector3d set2_angles() const;

  /// The same attitude in the given chart, converted exactly through the matrix when the
  /// chart changes (S10-S12); unchanged when it is already active.
  [[nodiscard]] Attitude in_set(EulerSet set) const;

  /// S7 or S9: rates of the active angles for the body angular velocity omega_b (rad/s).
  [[nodiscard]] Eigen::Vector3d angle_rates(const Eigen::Vector3d& omega_b) const;

  /// The switching rule of the seed: set 1 while the set-1 pitch |theta| <= pi/4 or
  /// |theta| > 3pi/4 (theta wrapped into (-pi, pi]), else set 2. Either way the chosen set is
  /// at least pi/4 away from its own singularity (theta = +-pi/2 for set 1, gamma_r = +-pi/2
  /// for set 2).
  [[nodiscard]] EulerSet preferred_set() const;

 private:
  EulerSet set_ = EulerSet::set1;
  Eigen::Vector3d angles_ = Eigen::Vector3d::Zero();
};

/// The set the switching rule picks for a set-1 pitch angle theta (rad, any value).
[[nodiscard]] EulerSet preferred_set_for_pitch(double theta);

/// The set the switching rule picks for a rotation matrix C_b^n.
[[nodiscard]] EulerSet preferred_set(const Eigen::Matrix3d& body_to_inertial);

}  // namespace settle::attitude
