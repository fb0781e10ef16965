#include "body/contact.hpp"

#include <algorithm>
#include <cmath>
#include <numbers>
#include <stdexcept>
#include <utility>

namespace settle::body {
namespace {

// Relative step of the support function's central differences: truncation O(step^2) of the body's
// size where h is smooth, round-off O(eps / step); 1e-4 balances them near 1e-8.
constexpr double kSupportStep = 1.0e-4;

// The support function extended to any non-zero vector by homogeneity, h(v) = |v| h(v / |v|).
double support_of(const Shape& shape, const Eigen::Vector3d& v) {
  const double length = v.norm();
  return length * shape.support(v / length);
}

// Two unit vectors completing the unit vector u to a right-handed orthonormal basis.
std::pair<Eigen::Vector3d, Eigen::Vector3d> tangent_basis(const Eigen::Vector3d& u) {
  Eigen::Index smallest = 0;
  u.cwiseAbs().minCoeff(&smallest);
  const Eigen::Vector3d t1 = u.cross(Eigen::Vector3d::Unit(smallest)).normalized();
  return {t1, u.cross(t1)};
}

Wrench operator+(const Wrench& a, const Wrench& b) { return {a.force_si + b.force_si, a.torque_si + b.torque_si}; }

}  // namespace

Eigen::Vector3d support_point(const Shape& shape, const Eigen::Vector3d& direction_b) {
  const Eigen::Vector3d u = direction_b.normalized();
  // The gradient's component along u is h(u) exactly (Euler's relation for the 1-homogeneous h),
  // so only the two tangential derivatives are differenced; the point then lies on the supporting
  // plane u . x = h(u) whatever the shape.
  const auto [t1, t2] = tangent_basis(u);
  const auto derivative = [&](const Eigen::Vector3d& t) {
    return (support_of(shape, u + kSupportStep * t) - support_of(shape, u - kSupportStep * t)) / (2.0 * kSupportStep);
  };
  return shape.support(u) * u + derivative(t1) * t1 + derivative(t2) * t2;
}

double wall_gap(const Shape& shape, const Eigen::Vector3d& position_si, const Eigen::Matrix3d& body_to_inertial,
                const WallPlane& wall) {
  // min over the body of n . x = n . c - h(-n), with -n taken into the body frame.
  const Eigen::Vector3d towards_wall_b = body_to_inertial.transpose() * (-wall.normal);
  return wall.normal.dot(position_si) - shape.support(towards_wall_b) - wall.offset_si;
}

WallProximity nearest_to_wall(const Shape& shape, const Eigen::Vector3d& position_si,
                              const Eigen::Matrix3d& body_to_inertial, const WallPlane& wall) {
  const Eigen::Vector3d towards_wall_b = body_to_inertial.transpose() * (-wall.normal);
  WallProximity p;
  p.gap_si = wall_gap(shape, position_si, body_to_inertial, wall);
  p.point_si = position_si + body_to_inertial * support_point(shape, towards_wall_b);
  return p;
}

SpringDashpot spring_dashpot(double mass_si, double effective_mass_si, const ContactParameters& parameters,
                             double restitution) {
  // Damped oscillator M x'' + c x' + k x = 0 with M = m_eff: half period pi / sqrt(k/M - (c/2M)^2)
  // and velocity ratio exp(-pi zeta / sqrt(1 - zeta^2)) = e for the damping ratio
  // zeta = c / (2 sqrt(k M)) = -ln e / sqrt(pi^2 + ln^2 e), whatever k and M. k is the dry one,
  // m (pi^2 + ln^2 e_dry) / T_c^2, so the half period is T_c when M = m and e = e_dry; then
  // c = 2 zeta sqrt(k M) = -2 ln e sqrt(m m_eff) / T_c.
  constexpr double pi2 = std::numbers::pi * std::numbers::pi;
  const double log_dry = std::log(parameters.restitution), log_e = std::log(restitution);
  const double t = parameters.collision_time_si;
  const double stiffness = mass_si * (pi2 + log_dry * log_dry) / (t * t);
  const double damping_ratio = -log_e / std::sqrt(pi2 + log_e * log_e);
  return {stiffness, 2.0 * damping_ratio * std::sqrt(stiffness * effective_mass_si)};
}

SpringDashpot spring_dashpot(double mass_si, double effective_mass_si, const ContactParameters& parameters) {
  return spring_dashpot(mass_si, effective_mass_si, parameters, parameters.restitution);
}

double impact_stokes_number(double body_density_si, double impact_speed_si, double diameter_si, double viscosity_si) {
  return body_density_si * std::abs(impact_speed_si) * diameter_si / (9.0 * viscosity_si);
}

double contact_restitution(const ContactParameters& parameters, double impact_stokes_number) {
  if (parameters.wet_stokes_scale == 0.0) return parameters.restitution;
  const double ratio = impact_stokes_number > 0.0 ? std::exp(-parameters.wet_stokes_scale / impact_stokes_number) : 0.0;
  return parameters.restitution * std::max(ratio, kMinimumWetRestitutionRatio);
}

double effective_mass(double mass_si, const Eigen::Matrix3d& inverse_inertia_n, const Eigen::Vector3d& offset_si,
                      const Eigen::Vector3d& normal) {
  const Eigen::Vector3d arm = offset_si.cross(normal);
  return 1.0 / (1.0 / mass_si + arm.dot(inverse_inertia_n * arm));
}

double max_overlap_bound(double load_si, double impact_speed_si, double stiffness_si, double collision_time_si) {
  return 2.0 * std::max(load_si, 0.0) / stiffness_si + std::abs(impact_speed_si) * collision_time_si / std::numbers::pi;
}

namespace {

// The lever arm from the body's centre to its point nearest the wall (inertial frame).
Eigen::Vector3d arm_to_wall(const Shape& shape, const RigidBodyState& state, const Eigen::Matrix3d& rotation,
                            const WallPlane& wall) {
  return nearest_to_wall(shape, state.position_si, rotation, wall).point_si - state.position_si;
}

// The velocity of the body point at `arm` along the wall's normal (negative: approaching).
double normal_speed(const RigidBodyState& state, const Eigen::Vector3d& omega_n, const Eigen::Vector3d& arm,
                    const WallPlane& wall) {
  return wall.normal.dot(state.velocity_si + omega_n.cross(arm));
}

}  // namespace

WallContact::WallContact(std::shared_ptr<const Shape> shape, std::vector<WallPlane> walls,
                         const ContactParameters& parameters)
    : shape_(std::move(shape)), walls_(std::move(walls)), parameters_(parameters) {
  if (!shape_) throw std::invalid_argument("WallContact: no shape");
  for (const auto& wall : walls_)
    if (!(std::abs(wall.normal.norm() - 1.0) < 1e-12) || !std::isfinite(wall.offset_si))
      throw std::invalid_argument("WallContact: wall normals must be unit vectors and offsets finite");
  if (!(parameters_.restitution > 0.0 && parameters_.restitution <= 1.0))
    throw std::invalid_argument("WallContact: restitution must be in (0, 1]");
  if (!(parameters_.collision_time_si > 0.0) || !std::isfinite(parameters_.collision_time_si))
    throw std::invalid_argument("WallContact: collision time must be > 0");
  if (!(parameters_.contact_distance_si >= 0.0) || !std::isfinite(parameters_.contact_distance_si))
    throw std::invalid_argument("WallContact: contact distance must be >= 0");
  if (parameters_.substeps_per_collision < 1)
    throw std::invalid_argument("WallContact: at least one substep per collision");
  if (!(parameters_.wet_stokes_scale >= 0.0) || !std::isfinite(parameters_.wet_stokes_scale))
    throw std::invalid_argument("WallContact: the wet Stokes scale must be >= 0");
  if (parameters_.wet_stokes_scale > 0.0 &&
      (!(parameters_.fluid_dynamic_viscosity_si > 0.0) || !std::isfinite(parameters_.fluid_dynamic_viscosity_si)))
    throw std::invalid_argument("WallContact: a wet contact needs the liquid's viscosity (> 0)");
  impact_speeds_si_.assign(walls_.size(), std::nullopt);
}

void WallContact::restore_impact_speeds(std::vector<std::optional<double>> speeds_si) {
  if (speeds_si.size() != walls_.size())
    throw std::invalid_argument("WallContact::restore_impact_speeds: one entry per wall expected");
  impact_speeds_si_ = std::move(speeds_si);
}

double WallContact::restitution_at(double impact_speed_si, double mass_si) const {
  if (parameters_.wet_stokes_scale == 0.0) return parameters_.restitution;
  const double stokes = impact_stokes_number(mass_si / shape_->volume(), impact_speed_si, shape_->equivalent_diameter(),
                                             parameters_.fluid_dynamic_viscosity_si);
  return contact_restitution(parameters_, stokes);
}

double WallContact::min_gap_si(const RigidBodyState& state) const {
  const Eigen::Matrix3d rotation = state.attitude.body_to_inertial();
  double gap = std::numeric_limits<double>::infinity();
  for (const auto& wall : walls_) gap = std::min(gap, wall_gap(*shape_, state.position_si, rotation, wall));
  return gap;
}

Wrench WallContact::wrench(const RigidBody& body, const RigidBodyState& state) const {
  const Eigen::Matrix3d rotation = state.attitude.body_to_inertial();
  const Eigen::Vector3d omega_n = rotation * state.angular_velocity_b_si;
  const MassProperties& mass = body.mass_properties();
  const Eigen::Matrix3d inverse_inertia_n = rotation * mass.inertia.inverse() * rotation.transpose();
  Wrench total;
  for (std::size_t i = 0; i < walls_.size(); ++i) {
    const WallPlane& wall = walls_[i];
    const double overlap = parameters_.contact_distance_si - wall_gap(*shape_, state.position_si, rotation, wall);
    if (!(overlap > 0.0)) continue;
    const Eigen::Vector3d arm = arm_to_wall(*shape_, state, rotation, wall);
    const double speed_n = normal_speed(state, omega_n, arm, wall);
    const double impact_speed = impact_speeds_si_[i].value_or(std::max(-speed_n, 0.0));
    const SpringDashpot law = spring_dashpot(mass.mass, effective_mass(mass.mass, inverse_inertia_n, arm, wall.normal),
                                             parameters_, restitution_at(impact_speed, mass.mass));
    const Eigen::Vector3d force = (law.stiffness * overlap - law.damping * speed_n) * wall.normal;
    total.force_si += force;
    total.torque_si += arm.cross(force);
  }
  return total;
}

bool WallContact::within_reach(const RigidBodyState& state, double dt_si) const {
  // A wall can come within zeta_c during the step if the body moves that far: twice the distance
  // its fastest point covers at the current speeds, so a moderate acceleration is still caught.
  const double speed = state.velocity_si.norm() + state.angular_velocity_b_si.norm() * shape_->bounding_radius();
  return min_gap_si(state) < parameters_.contact_distance_si + 2.0 * speed * dt_si;
}

int WallContact::substep_count(double dt_si) const {
  const double substeps = std::ceil(dt_si * parameters_.substeps_per_collision / parameters_.collision_time_si);
  return std::max(1, static_cast<int>(std::min(substeps, 1.0e6)));
}

double WallContact::update_impacts(const RigidBodyState& state) {
  const Eigen::Matrix3d rotation = state.attitude.body_to_inertial();
  const Eigen::Vector3d omega_n = rotation * state.angular_velocity_b_si;
  double min_gap = std::numeric_limits<double>::infinity();
  for (std::size_t i = 0; i < walls_.size(); ++i) {
    const WallPlane& wall = walls_[i];
    const double gap = wall_gap(*shape_, state.position_si, rotation, wall);
    min_gap = std::min(min_gap, gap);
    if (!(gap < parameters_.contact_distance_si)) {
      impact_speeds_si_[i].reset();
    } else if (!impact_speeds_si_[i]) {
      const Eigen::Vector3d arm = arm_to_wall(*shape_, state, rotation, wall);
      impact_speeds_si_[i] = std::max(-normal_speed(state, omega_n, arm, wall), 0.0);
    }
  }
  return min_gap;
}

ContactStep WallContact::advance(RigidBody& body, double dt_si, const Wrench& external) {
  return advance(body, dt_si, external, VirtualInertia{});
}

ContactStep WallContact::advance(RigidBody& body, double dt_si, const Wrench& external,
                                 const VirtualInertia& virtual_inertia) {
  ContactStep step;
  if (body.motion_kind() != MotionKind::free || !within_reach(body.state(), dt_si)) {
    body.correct(dt_si, external, virtual_inertia);
    step.min_gap_si = update_impacts(body.state());
    return step;
  }
  step.substeps = substep_count(dt_si);
  const double h = dt_si / step.substeps;
  // Each substep starts where the previous one ended, so the records are updated (and the gaps
  // measured) once per state: here for the start, then at every substep's midpoint and end.
  step.min_gap_si = update_impacts(body.state());
  for (int s = 0; s < step.substeps; ++s) {
    // Explicit midpoint rule for the contact wrench: predict half a substep with the wrench at the
    // start, then take the whole substep with the wrench at that midpoint.
    RigidBody midpoint = body;
    midpoint.correct(0.5 * h, external + wrench(body, body.state()), virtual_inertia);
    // A contact that begins within this substep is recorded at the midpoint, before any dashpot
    // impulse has slowed the body: its impact speed is the approach speed.
    update_impacts(midpoint.state());
    const Wrench contact = wrench(midpoint, midpoint.state());
    body.correct(h, external + contact, virtual_inertia);
    step.mean_wrench.force_si += contact.force_si * (h / dt_si);
    step.mean_wrench.torque_si += contact.torque_si * (h / dt_si);
    step.touching = step.touching || !contact.force_si.isZero(0.0);
    step.min_gap_si = std::min(step.min_gap_si, update_impacts(body.state()));
  }
  return step;
}

}  // namespace settle::body
