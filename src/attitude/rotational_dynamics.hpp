#pragma once
// Rotational dynamics integrated together with the attitude: Euler's equations in the body
// frame with the full inertia tensor and the gyroscopic term,
//     I_b domega_b/dt = T_b - omega_b x (I_b omega_b),
// advanced by classical RK4 in the same stages as the attitude (dual-Euler angles or a unit
// quaternion). Torque-free motion (the `settle attitude` command) is the case T_b = 0.
#include <functional>

#include <Eigen/Core>
#include <Eigen/Geometry>

#include "attitude/attitude.hpp"

namespace settle::attitude {

/// A body-frame inertia tensor (kg m^2, about the reference point the rotation is about)
/// with its inverse, checked once on construction to be symmetric positive definite.
class BodyInertia {
 public:
  /// Throws std::invalid_argument unless the tensor is symmetric (to 1e-12 relative) and
  /// positive definite. It need not be diagonal.
  explicit BodyInertia(const Eigen::Matrix3d& tensor_b);
  [[nodiscard]] const Eigen::Matrix3d& tensor() const { return tensor_; }
  [[nodiscard]] const Eigen::Matrix3d& inverse() const { return inverse_; }

 private:
  Eigen::Matrix3d tensor_;
  Eigen::Matrix3d inverse_;
};

/// domega_b/dt from Euler's equations: I^-1 (T_b - omega_b x (I omega_b)). Body frame.
[[nodiscard]] Eigen::Vector3d angular_acceleration_b(const BodyInertia& inertia, const Eigen::Vector3d& omega_b,
                                                     const Eigen::Vector3d& torque_b);

/// Body-frame torque (N m) as a function of time (s), body rates (rad/s) and the attitude
/// matrix C_b^n. An empty function means no torque.
using BodyTorqueFunction =
    std::function<Eigen::Vector3d(double t, const Eigen::Vector3d& omega_b, const Eigen::Matrix3d& body_to_inertial)>;

/// Body rates and attitude in the dual-Euler atlas.
struct SpinState {
  Eigen::Vector3d omega_b = Eigen::Vector3d::Zero();  ///< body frame, rad/s
  Attitude attitude;                                  ///< body to inertial
};

/// Body rates and attitude as a unit quaternion (the reference method).
struct QuaternionSpinState {
  Eigen::Vector3d omega_b = Eigen::Vector3d::Zero();                ///< body frame, rad/s
  Eigen::Quaterniond orientation = Eigen::Quaterniond::Identity();  ///< body to inertial
};

/// One step of the rotational dynamics with the dual-Euler attitude: the switching rule at
/// the step start, then one RK4 step of (omega_b, active angles) in the same stages.
/// Returns true when the set switched.
bool dual_euler_spin_step(SpinState& state, const BodyInertia& inertia, double t, double dt,
                          const BodyTorqueFunction& torque_b = {});

/// One step of the rotational dynamics with the quaternion attitude: RK4 of
/// (omega_b, q), q normalised after the step.
void quaternion_spin_step(QuaternionSpinState& state, const BodyInertia& inertia, double t, double dt,
                          const BodyTorqueFunction& torque_b = {});

/// Rotational kinetic energy 0.5 omega_b . (I omega_b), J.
[[nodiscard]] double rotational_energy(const BodyInertia& inertia, const Eigen::Vector3d& omega_b);

}  // namespace settle::attitude
