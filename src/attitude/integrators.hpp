#pragma once
// Kinematic attitude integrators: given the body angular velocity omega_b(t), advance the
// attitude. The dual-Euler solver follows Cheng et al. (2023), Phys. Fluids 35,
// doi:10.1063/5.0165555 (supplementary material, S7, S9 and the switching rule); the unit
// quaternion integrator is the reference method.
//
// Both solve d(C_b^n)/dt = C_b^n [omega_b]x with classical RK4 and take omega_b in the
// body frame (rad/s) as a function of time (s).
#include <functional>

#include <Eigen/Core>
#include <Eigen/Geometry>

#include "attitude/attitude.hpp"

namespace settle::attitude {

/// Body angular velocity (body frame, rad/s) as a function of time (s).
using BodyRateFunction = std::function<Eigen::Vector3d(double t)>;

/// The switching rule, applied at the start of every step: the angles of the active set are
/// wrapped into (-pi, pi] (the same attitude, so that long runs keep full precision), then
/// the chart moves to the preferred set (Attitude::preferred_set) through the matrix.
/// Returns true when the active set changed.
///
/// Applying it at step starts only (not inside the RK4 stages) keeps every step a smooth
/// RK4 step in one chart; within a step the pitch can pass pi/4 by at most |omega| dt, far
/// from the singularity at pi/2 for any usable dt.
bool apply_switching_rule(Attitude& attitude);

/// One classical RK4 step of the active set's angles (S7 or S9) from t to t + dt, without
/// switching.
[[nodiscard]] Attitude rk4_angles_step(const Attitude& attitude, double t, double dt, const BodyRateFunction& omega_b);

/// One dual-Euler step: the switching rule, then one RK4 step of the active set's angles.
/// Returns true when the rule switched the set at the start of this step.
bool dual_euler_step(Attitude& attitude, double t, double dt, const BodyRateFunction& omega_b);

/// The coupled solver's form of dual_euler_step: the body rates are known at the start and
/// end of the step and interpolated linearly in time for the RK4 stages (so the middle
/// stages see their mean). Returns true when the set switched.
bool dual_euler_step(Attitude& attitude, double dt, const Eigen::Vector3d& omega_start_b,
                     const Eigen::Vector3d& omega_end_b);

/// q' = 0.5 q (x) (0, omega_b) for the body-to-inertial unit quaternion q, as Eigen's
/// coefficient vector (x, y, z, w).
[[nodiscard]] Eigen::Vector4d quaternion_rate(const Eigen::Vector4d& q_coeffs, const Eigen::Vector3d& omega_b);

/// One RK4 step of q' = 0.5 q (x) (0, omega_b), normalised afterwards (RK4 does not keep
/// |q| = 1 exactly; renormalising removes that drift without changing the rotation).
[[nodiscard]] Eigen::Quaterniond quaternion_step(const Eigen::Quaterniond& q, double t, double dt,
                                                 const BodyRateFunction& omega_b);

}  // namespace settle::attitude
