// Newton-Euler equations of a rigid particle with the dual-Euler attitude (Cheng et al.
// 2023, doi:10.1063/5.0165555). See rigid_body.hpp for the equations and the time-step split.
#include "body/rigid_body.hpp"

#include <cmath>
#include <stdexcept>

#include "attitude/integrators.hpp"
#include "attitude/rk4.hpp"

namespace settle::body {
namespace {

using Vector12d = Eigen::Matrix<double, 12, 1>;

Vector12d pack(const RigidBodyState& s) {
  Vector12d y;
  y << s.position_si, s.velocity_si, s.angular_velocity_b_si, s.attitude.angles();
  return y;
}

RigidBodyState unpack(const Vector12d& y, attitude::EulerSet set) {
  return {y.segment<3>(0), y.segment<3>(3), attitude::Attitude(set, y.segment<3>(9)), y.segment<3>(6)};
}

}  // namespace

RigidBody::RigidBody(const MassProperties& mass_properties, const Environment& environment,
                     const RigidBodyState& initial, MotionKind kind)
    : mass_properties_(mass_properties),
      inertia_(mass_properties.inertia),
      environment_(environment),
      state_(initial),
      kind_(kind) {
  if (!(mass_properties.mass > 0.0) || !std::isfinite(mass_properties.mass)) {
    throw std::invalid_argument("rigid body: mass must be finite and > 0");
  }
  if (!(mass_properties.volume > 0.0) || !std::isfinite(mass_properties.volume)) {
    throw std::invalid_argument("rigid body: volume must be finite and > 0");
  }
  enforce_motion_kind();
}

void RigidBody::set_state(const RigidBodyState& state) {
  state_ = state;
  enforce_motion_kind();
}

void RigidBody::enforce_motion_kind() {
  const RigidBodyState& s = state_;
  if (!s.position_si.allFinite() || !s.velocity_si.allFinite() || !s.attitude.angles().allFinite() ||
      !s.angular_velocity_b_si.allFinite()) {
    throw std::invalid_argument("rigid body: state must be finite");
  }
  if (kind_ == MotionKind::fixed) {
    state_.velocity_si.setZero();
    state_.angular_velocity_b_si.setZero();
  }
  if (rotation_locked_ && kind_ == MotionKind::free) state_.angular_velocity_b_si.setZero();
}

void RigidBody::lock_rotation() {
  rotation_locked_ = true;
  enforce_motion_kind();
}

Eigen::Vector3d RigidBody::net_weight_si() const {
  const double displaced_mass = environment_.fluid_density_si * mass_properties_.volume;
  return (mass_properties_.mass - displaced_mass) * environment_.gravity_si;
}

Eigen::Vector3d RigidBody::angular_velocity_n_si() const { return body_to_inertial() * state_.angular_velocity_b_si; }

Eigen::Vector3d RigidBody::angular_momentum_n_si() const {
  return body_to_inertial() * (inertia_.tensor() * state_.angular_velocity_b_si);
}

double RigidBody::kinetic_energy_si() const {
  return 0.5 * mass_properties_.mass * state_.velocity_si.squaredNorm() +
         attitude::rotational_energy(inertia_, state_.angular_velocity_b_si);
}

Pose RigidBody::predict_pose(double dt_si) const {
  Pose pose{state_.position_si + dt_si * state_.velocity_si, state_.attitude};
  const Eigen::Vector3d& omega = state_.angular_velocity_b_si;
  attitude::dual_euler_step(pose.attitude, dt_si, omega, omega);
  return pose;
}

void RigidBody::advance_prescribed(double dt_si) {
  if (kind_ == MotionKind::fixed) return;
  state_.position_si += dt_si * state_.velocity_si;
  const Eigen::Vector3d& omega = state_.angular_velocity_b_si;
  if (attitude::dual_euler_step(state_.attitude, dt_si, omega, omega)) ++switch_count_;
}

void RigidBody::correct(double dt_si, const Wrench& external_n) { correct(dt_si, external_n, VirtualInertia{}); }

void RigidBody::correct(double dt_si, const Wrench& external_n, const VirtualInertia& virtual_inertia) {
  if (kind_ != MotionKind::free) {
    advance_prescribed(dt_si);
    return;
  }
  // Translation: constant force over the step, exact for that force. The virtual mass term
  // (VirtualInertia) adds m_v a_est on the right and m_v on the left.
  const double mass_with_virtual = mass_properties_.mass + virtual_inertia.mass_si;
  const Eigen::Vector3d acceleration =
      (external_n.force_si + net_weight_si() + virtual_inertia.mass_si * virtual_inertia.acceleration_si) /
      mass_with_virtual;
  const Eigen::Vector3d velocity_start = state_.velocity_si;
  state_.velocity_si = velocity_start + dt_si * acceleration;
  state_.position_si += 0.5 * dt_si * (velocity_start + state_.velocity_si);
  if (rotation_locked_) return;

  // Rotation: the torque was measured with the body at the predicted pose, so that pose's
  // matrix brings it into the body frame; it is held constant there over the step.
  const Eigen::Vector3d torque_b = predict_pose(dt_si).attitude.inertial_to_body() * external_n.torque_si;
  const Eigen::Vector3d omega_start = state_.angular_velocity_b_si;
  // With a virtual inertia I_v: (I + I_v) domega/dt = T_b + I_v alpha_est - omega x (I omega); the
  // gyroscopic term keeps the body's own inertia (it is physics, the virtual term is numerics).
  const bool plain = virtual_inertia.inertia_b_si.isZero(0.0);
  const Eigen::Matrix3d inverse_with_virtual =
      plain ? inertia_.inverse() : attitude::BodyInertia(inertia_.tensor() + virtual_inertia.inertia_b_si).inverse();
  const Eigen::Vector3d driving_b = torque_b + virtual_inertia.inertia_b_si * virtual_inertia.angular_acceleration_b_si;
  const auto euler_equations = [&](double, const Eigen::Vector3d& omega) -> Eigen::Vector3d {
    if (plain) return attitude::angular_acceleration_b(inertia_, omega, torque_b);
    return inverse_with_virtual * (driving_b - omega.cross(inertia_.tensor() * omega));
  };
  state_.angular_velocity_b_si = attitude::rk4_step(omega_start, 0.0, dt_si, euler_equations);
  if (attitude::dual_euler_step(state_.attitude, dt_si, omega_start, state_.angular_velocity_b_si)) {
    ++switch_count_;
  }
}

void RigidBody::advance(double t_si, double dt_si, const WrenchFunction& external_n) {
  if (kind_ != MotionKind::free) {
    advance_prescribed(dt_si);
    return;
  }
  if (attitude::apply_switching_rule(state_.attitude)) ++switch_count_;
  const attitude::EulerSet set = state_.attitude.set();
  const Eigen::Vector3d weight = net_weight_si();
  const double mass = mass_properties_.mass;

  const auto newton_euler = [&](double t, const Vector12d& y) -> Vector12d {
    const RigidBodyState stage = unpack(y, set);
    const Wrench external = external_n ? external_n(t, stage) : Wrench{};
    const Eigen::Vector3d torque_b = stage.attitude.inertial_to_body() * external.torque_si;
    // Locked, omega_b stays zero, and with it the attitude's rates.
    const Eigen::Vector3d angular_acceleration_b =
        rotation_locked_ ? Eigen::Vector3d::Zero()
                         : attitude::angular_acceleration_b(inertia_, stage.angular_velocity_b_si, torque_b);
    Vector12d rate;
    rate << stage.velocity_si, (external.force_si + weight) / mass, angular_acceleration_b,
        stage.attitude.angle_rates(stage.angular_velocity_b_si);
    return rate;
  };
  state_ = unpack(attitude::rk4_step(pack(state_), t_si, dt_si, newton_euler), set);
}

}  // namespace settle::body
