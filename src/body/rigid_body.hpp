#pragma once
// Rigid-body dynamics of a particle: Newton's law for the centre of mass in the inertial
// frame and Euler's equations in the body frame with the full inertia tensor and the
// gyroscopic term, the orientation carried by the dual-Euler whole-attitude solver
// (Cheng et al. 2023, Phys. Fluids 35, doi:10.1063/5.0165555, supplementary material).
//
// Conventions: inertial frame n (z up in settle's cases, gravity a free vector), body frame
// b (the shape's own axes; docs/architecture.md, "Frames and attitude"). Positions, velocities, forces and torques
// are inertial; the angular velocity and the inertia tensor are body-frame; the attitude maps
// body to inertial (v_n = C_b^n v_b). Torques are about the centre of mass (or, for a body
// on a fixed pivot, about the pivot with the inertia tensor taken about it).
//
// Two ways to advance:
//
// 1. advance(): one classical RK4 step of the whole Newton-Euler system, calling the
//    external-wrench function at every stage. For forces that are known functions of time
//    and state (tests, a heavy top, the attitude command). Fourth order.
//
// 2. The coupled time step's split (docs/architecture.md, "The coupled time step"), for a wrench that is only known
//    once per step because it comes from the fluid:
//      step 1, predict_pose(dt): where the body will be at t + dt if its current velocities
//        are kept (x + v dt; the attitude advanced by the dual-Euler solver with omega_b held
//        constant). The fluid places the surface markers there; the body does not change.
//      step 4 (fluid): hydrodynamic force and torque on the body at that predicted pose.
//      step 5, correct(dt, wrench): Newton's law with that force plus gravity and buoyancy
//        (force constant over the step: v += a dt, x += (v_old + v_new) dt / 2, exact for a
//        constant force); Euler's equations for omega_b by RK4 with the torque, converted to
//        the body frame with the predicted attitude it was measured at, held constant over the
//        step (an approximation of first order in the rotation during one step); then the
//        attitude by the dual-Euler solver from the step's start with omega_b interpolated
//        linearly between its start and end values for the RK4 stages (second-order accurate,
//        the order of the coupling itself).
//
// Motion kinds: free (dynamics as above), towed (velocity and body angular velocity held at
// their prescribed constant values: the position moves linearly, the attitude rotates at the
// constant body rate; forces are ignored), fixed (nothing moves). A free body's rotation may be
// locked (lock_rotation): it then translates by Newton's law and keeps its attitude.
#include <functional>

#include <Eigen/Core>

#include "attitude/attitude.hpp"
#include "attitude/rotational_dynamics.hpp"
#include "body/mass_properties.hpp"

namespace settle::body {

/// How the body moves.
enum class MotionKind { free, towed, fixed };

/// The surroundings that act on every body: a fluid of uniform density at rest (for
/// buoyancy) and gravity.
struct Environment {
  double fluid_density_si = 0.0;                         ///< kg/m^3; 0 is vacuum
  Eigen::Vector3d gravity_si = Eigen::Vector3d::Zero();  ///< m/s^2, inertial
};

/// The dynamic state. The attitude is the dual-Euler atlas chart; matrix and quaternion are
/// derived from it. Write zero vectors as Eigen::Vector3d::Zero() when listing the members:
/// a member given as {} is an uninitialised Eigen vector, not zero.
struct RigidBodyState {
  Eigen::Vector3d position_si = Eigen::Vector3d::Zero();            ///< centre of mass, inertial, m
  Eigen::Vector3d velocity_si = Eigen::Vector3d::Zero();            ///< inertial, m/s
  attitude::Attitude attitude;                                      ///< body to inertial
  Eigen::Vector3d angular_velocity_b_si = Eigen::Vector3d::Zero();  ///< body frame, rad/s
};

/// Where the body is: centre of mass and attitude.
struct Pose {
  Eigen::Vector3d position_si = Eigen::Vector3d::Zero();  ///< inertial, m
  attitude::Attitude attitude;                            ///< body to inertial
};

/// Force and torque in the inertial frame; torque about the centre of mass (N, N m).
struct Wrench {
  Eigen::Vector3d force_si = Eigen::Vector3d::Zero();
  Eigen::Vector3d torque_si = Eigen::Vector3d::Zero();
};

/// Virtual mass and inertia of the coupled step's corrector (Schwarz, Kempe and Froehlich 2015,
/// J. Comput. Phys. 281, 591, doi:10.1016/j.jcp.2014.10.039): the same term is added to both sides
/// of Newton-Euler, implicitly on the left and with an estimate of the step's acceleration on the
/// right,
///     (m + m_v) a = F + (m - rho_f V) g + m_v a_est,
///     (I + I_v) domega_b/dt = T_b - omega_b x (I omega_b) + I_v alpha_est.
/// An approximation that acts on transients only: when the acceleration does not change from one
/// step to the next (a = a_est), the added terms cancel exactly, so steady motion and terminal
/// states are those of the plain equations. docs/coupling.md, "Stability of light bodies".
struct VirtualInertia {
  double mass_si = 0.0;                                                 ///< m_v, kg
  Eigen::Matrix3d inertia_b_si = Eigen::Matrix3d::Zero();               ///< I_v, body frame, kg m^2
  Eigen::Vector3d acceleration_si = Eigen::Vector3d::Zero();            ///< a_est, inertial, m/s^2
  Eigen::Vector3d angular_acceleration_b_si = Eigen::Vector3d::Zero();  ///< alpha_est, body frame, rad/s^2
};

/// External wrench (beyond gravity and buoyancy) as a function of time (s) and state.
using WrenchFunction = std::function<Wrench(double t_si, const RigidBodyState& state)>;

/// One rigid particle. See the file comment for the equations and the two ways to advance.
class RigidBody {
 public:
  /// Uses mass (kg), volume (m^3, for buoyancy) and inertia (kg m^2, about the centre of
  /// mass in body axes, any orientation: it need not be diagonal) of the mass properties
  /// the shapes compute. Throws std::invalid_argument for non-positive mass or volume, an
  /// inertia tensor that is not symmetric positive definite, or a non-finite state. For a towed body the initial velocity and body
  /// angular velocity are the prescribed ones; a fixed body's are set to zero.
  RigidBody(const MassProperties& mass_properties, const Environment& environment, const RigidBodyState& initial,
            MotionKind kind = MotionKind::free);

  [[nodiscard]] const RigidBodyState& state() const { return state_; }
  [[nodiscard]] const MassProperties& mass_properties() const { return mass_properties_; }
  [[nodiscard]] const Environment& environment() const { return environment_; }
  [[nodiscard]] MotionKind motion_kind() const { return kind_; }
  /// Locks a free body's rotation: from now on it keeps its attitude and a zero angular velocity,
  /// Newton's law alone moves it, and the torques it is given are ignored. A control experiment
  /// on what the body's rotation does in a path instability (particle.lock_rotation,
  /// docs/rigid-body.md). Towed and fixed bodies follow their prescribed motion anyway.
  void lock_rotation();
  [[nodiscard]] bool rotation_locked() const { return rotation_locked_; }
  /// Number of Euler-set switches made so far (a diagnostic, not state).
  [[nodiscard]] long switch_count() const { return switch_count_; }

  /// Replaces the state (e.g. from a checkpoint). The motion kind's rules apply as in the
  /// constructor.
  void set_state(const RigidBodyState& state);

  /// Gravity minus buoyancy, (m - rho_f V) g, inertial, N.
  [[nodiscard]] Eigen::Vector3d net_weight_si() const;
  /// C_b^n of the current attitude.
  [[nodiscard]] Eigen::Matrix3d body_to_inertial() const { return state_.attitude.body_to_inertial(); }
  /// Angular velocity in the inertial frame, rad/s.
  [[nodiscard]] Eigen::Vector3d angular_velocity_n_si() const;
  /// Angular momentum about the centre of mass, inertial frame, kg m^2/s.
  [[nodiscard]] Eigen::Vector3d angular_momentum_n_si() const;
  /// Translational plus rotational kinetic energy, J.
  [[nodiscard]] double kinetic_energy_si() const;

  /// Step 1 of the coupled step: the pose at t + dt from the current velocities. Does not
  /// change the body.
  [[nodiscard]] Pose predict_pose(double dt_si) const;

  /// Step 5 of the coupled step: advances the state over one step of dt with the external
  /// wrench (inertial; e.g. hydrodynamic, measured at predict_pose(dt)) held constant, plus
  /// gravity and buoyancy. Towed and fixed bodies follow their prescribed motion instead.
  void correct(double dt_si, const Wrench& external_n);
  /// The same with the virtual mass and inertia stabilisation (VirtualInertia) of light bodies; with
  /// a zero VirtualInertia it is exactly correct(dt, external_n).
  void correct(double dt_si, const Wrench& external_n, const VirtualInertia& virtual_inertia);

  /// Moves the body for one step of dt with its current velocity and body angular velocity held
  /// (as a towed body moves), whatever its motion kind but fixed: a free body held before its
  /// release (SimulationSetup::release_time_si).
  void hold(double dt_si) { advance_prescribed(dt_si); }

  /// One RK4 step of the full Newton-Euler system from t to t + dt, with gravity, buoyancy
  /// and the external wrench evaluated at every stage (an empty function means none).
  /// Towed and fixed bodies follow their prescribed motion instead.
  void advance(double t_si, double dt_si, const WrenchFunction& external_n = {});

 private:
  void advance_prescribed(double dt_si);
  void enforce_motion_kind();

  MassProperties mass_properties_;
  attitude::BodyInertia inertia_;
  Environment environment_;
  RigidBodyState state_;
  MotionKind kind_;
  bool rotation_locked_ = false;
  long switch_count_ = 0;
};

}  // namespace settle::body
