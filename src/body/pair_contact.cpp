#include "body/pair_contact.hpp"

#include <algorithm>
#include <cmath>
#include <stdexcept>

namespace settle::body {
namespace {

Wrench operator+(const Wrench& a, const Wrench& b) { return {a.force_si + b.force_si, a.torque_si + b.torque_si}; }

Eigen::Matrix3d inverse_inertia_n(const RigidBody& body) {
  const Eigen::Matrix3d rotation = body.body_to_inertial();
  return rotation * body.mass_properties().inertia.inverse() * rotation.transpose();
}

// The velocity of the body point at offset `arm` (inertial) from its centre of mass.
Eigen::Vector3d point_velocity(const RigidBody& body, const Eigen::Vector3d& arm) {
  return body.state().velocity_si + body.angular_velocity_n_si().cross(arm);
}

// Luding's rule: the spring turned into the plane normal to n with its length kept.
Eigen::Vector3d into_tangent_plane(const Eigen::Vector3d& spring, const Eigen::Vector3d& normal) {
  const Eigen::Vector3d tangential = spring - normal * normal.dot(spring);
  const double length = tangential.norm();
  return length > 0.0 ? Eigen::Vector3d(tangential * (spring.norm() / length)) : Eigen::Vector3d::Zero();
}

// Sets the tangential force and the spring of a touching contact: the stuck spring's force, cut to
// the Coulomb limit on sliding with the spring cut to match (Luding 2008).
void apply_friction(PairContactForce& f, const Eigen::Vector3d& spring, double stiffness,
                    const PairContactParameters& parameters) {
  const double tangential_stiffness = parameters.tangential_stiffness_ratio * stiffness;
  f.spring_si = into_tangent_plane(spring, f.separation.normal);
  f.tangential_force_si = -tangential_stiffness * f.spring_si;
  // A pulling contact (the dashpot near the end of a rebound) transmits no friction.
  const double limit = parameters.friction_coefficient * std::max(f.normal_force_si, 0.0);
  const double magnitude = f.tangential_force_si.norm();
  if (magnitude > limit) {
    f.tangential_force_si *= limit / magnitude;
    f.spring_si = -f.tangential_force_si / tangential_stiffness;
  }
}

bool bounding_spheres_within(const ContactBody& a, const ContactBody& b, double reach_si) {
  const double between = (b.body->state().position_si - a.body->state().position_si).norm();
  return between - a.shape->bounding_radius() - b.shape->bounding_radius() < reach_si;
}

// Every pair's contact: the wrench on each body, and the springs and tangential velocities of the
// pairs that touch.
struct ContactField {
  std::vector<Wrench> wrenches;
  PairSprings springs, tangential_velocities;
  bool touching = false;
};

ContactField contact_field(const std::vector<RigidBody>& bodies, const std::vector<const Shape*>& shapes,
                           const PairSprings& springs, const PairContactParameters& parameters) {
  ContactField field;
  field.wrenches.resize(bodies.size());
  for (std::size_t i = 0; i < bodies.size(); ++i)
    for (std::size_t j = i + 1; j < bodies.size(); ++j) {
      const ContactBody a{shapes[i], &bodies[i]}, b{shapes[j], &bodies[j]};
      if (!bounding_spheres_within(a, b, parameters.contact_distance_si)) continue;
      const auto spring = springs.find({i, j});
      const PairContactForce f =
          pair_contact_force(a, b, spring == springs.end() ? Eigen::Vector3d::Zero() : spring->second, parameters);
      if (!f.touching) continue;
      field.wrenches[i] = field.wrenches[i] + f.on_a;
      field.wrenches[j] = field.wrenches[j] + f.on_b;
      field.springs[{i, j}] = f.spring_si;
      field.tangential_velocities[{i, j}] = f.tangential_velocity_si;
      field.touching = true;
    }
  return field;
}

// Whether any pair can come within zeta_c during the step: twice the distance the fastest points
// cover at the current speeds, as the wall contact reckons it.
bool any_pair_within_reach(const std::vector<RigidBody>& bodies, const std::vector<const Shape*>& shapes, double dt_si,
                           double contact_distance_si) {
  for (std::size_t i = 0; i < bodies.size(); ++i)
    for (std::size_t j = i + 1; j < bodies.size(); ++j) {
      const auto speed = [&](std::size_t k) {
        return bodies[k].state().velocity_si.norm() +
               bodies[k].state().angular_velocity_b_si.norm() * shapes[k]->bounding_radius();
      };
      const double reach = contact_distance_si + 2.0 * (speed(i) + speed(j)) * dt_si;
      if (bounding_spheres_within({shapes[i], &bodies[i]}, {shapes[j], &bodies[j]}, reach)) return true;
    }
  return false;
}

}  // namespace

void validate_pair_contact(const PairContactParameters& p) {
  if (!(p.restitution > 0.0 && p.restitution <= 1.0))
    throw std::invalid_argument("pair contact: restitution must be in (0, 1]");
  if (!(p.friction_coefficient >= 0.0) || !std::isfinite(p.friction_coefficient))
    throw std::invalid_argument("pair contact: friction coefficient must be >= 0");
  if (!(p.collision_time_si > 0.0) || !std::isfinite(p.collision_time_si))
    throw std::invalid_argument("pair contact: collision time must be > 0");
  if (!(p.contact_distance_si >= 0.0) || !std::isfinite(p.contact_distance_si))
    throw std::invalid_argument("pair contact: contact distance must be >= 0");
  if (!(p.tangential_stiffness_ratio > 0.0) || !std::isfinite(p.tangential_stiffness_ratio))
    throw std::invalid_argument("pair contact: tangential stiffness ratio must be > 0");
  if (p.substeps_per_collision < 1) throw std::invalid_argument("pair contact: at least one substep per collision");
}

double pair_effective_mass(double mass_a_si, const Eigen::Matrix3d& inverse_inertia_a_n,
                           const Eigen::Vector3d& arm_a_si, double mass_b_si,
                           const Eigen::Matrix3d& inverse_inertia_b_n, const Eigen::Vector3d& arm_b_si,
                           const Eigen::Vector3d& normal) {
  const Eigen::Vector3d lever_a = arm_a_si.cross(normal), lever_b = arm_b_si.cross(normal);
  return 1.0 / (1.0 / mass_a_si + 1.0 / mass_b_si + lever_a.dot(inverse_inertia_a_n * lever_a) +
                lever_b.dot(inverse_inertia_b_n * lever_b));
}

SpringDashpot pair_spring_dashpot(double mass_a_si, double mass_b_si, double effective_mass_si,
                                  const PairContactParameters& parameters) {
  ContactParameters wall;
  wall.restitution = parameters.restitution;
  wall.collision_time_si = parameters.collision_time_si;
  return spring_dashpot(mass_a_si * mass_b_si / (mass_a_si + mass_b_si), effective_mass_si, wall);
}

PairContactForce pair_contact_force(const ContactBody& a, const ContactBody& b, const Eigen::Vector3d& spring_si,
                                    const PairContactParameters& parameters) {
  const RigidBody& body_a = *a.body;
  const RigidBody& body_b = *b.body;
  PairContactForce f;
  f.separation = convex_distance({a.shape, body_a.state().position_si, body_a.body_to_inertial()},
                                 {b.shape, body_b.state().position_si, body_b.body_to_inertial()});
  const double overlap = parameters.contact_distance_si - f.separation.distance_si;
  if (!(overlap > 0.0)) return f;
  f.touching = true;
  const Eigen::Vector3d n = f.separation.normal;
  const Eigen::Vector3d contact = 0.5 * (f.separation.point_a_si + f.separation.point_b_si);
  const Eigen::Vector3d arm_a = contact - body_a.state().position_si, arm_b = contact - body_b.state().position_si;
  const Eigen::Vector3d u = point_velocity(body_b, arm_b) - point_velocity(body_a, arm_a);
  f.tangential_velocity_si = u - n * n.dot(u);
  const double mass_a = body_a.mass_properties().mass, mass_b = body_b.mass_properties().mass;
  const double effective =
      pair_effective_mass(mass_a, inverse_inertia_n(body_a), arm_a, mass_b, inverse_inertia_n(body_b), arm_b, n);
  const SpringDashpot law = pair_spring_dashpot(mass_a, mass_b, effective, parameters);
  f.normal_force_si = law.stiffness * overlap - law.damping * n.dot(u);
  apply_friction(f, spring_si, law.stiffness, parameters);
  const Eigen::Vector3d force = f.normal_force_si * n + f.tangential_force_si;
  f.on_b = {force, arm_b.cross(force)};
  f.on_a = {-force, arm_a.cross(-force)};
  return f;
}

PairContactStep advance_in_contact(std::vector<RigidBody>& bodies, const std::vector<const Shape*>& shapes,
                                   PairSprings& springs, double dt_si, const PairContactParameters& parameters) {
  validate_pair_contact(parameters);
  if (shapes.size() != bodies.size() || std::count(shapes.begin(), shapes.end(), nullptr) > 0)
    throw std::invalid_argument("advance_in_contact: one shape per body expected");
  PairContactStep step;
  if (!any_pair_within_reach(bodies, shapes, dt_si, parameters.contact_distance_si)) {
    for (auto& body : bodies) body.correct(dt_si, Wrench{});
    springs.clear();
    return step;
  }
  const double substeps = std::ceil(dt_si * parameters.substeps_per_collision / parameters.collision_time_si);
  step.substeps = std::max(1, static_cast<int>(std::min(substeps, 1.0e6)));
  const double h = dt_si / step.substeps;
  for (int s = 0; s < step.substeps; ++s) {
    // Explicit midpoint rule, the spring advanced with the bodies.
    const ContactField start = contact_field(bodies, shapes, springs, parameters);
    std::vector<RigidBody> midpoint = bodies;
    PairSprings midpoint_springs = start.springs;
    for (std::size_t i = 0; i < bodies.size(); ++i) midpoint[i].correct(0.5 * h, start.wrenches[i]);
    for (auto& [pair, spring] : midpoint_springs) spring += 0.5 * h * start.tangential_velocities.at(pair);
    const ContactField middle = contact_field(midpoint, shapes, midpoint_springs, parameters);
    for (std::size_t i = 0; i < bodies.size(); ++i) bodies[i].correct(h, middle.wrenches[i]);
    springs.clear();
    for (const auto& [pair, velocity] : middle.tangential_velocities) {
      const auto begun = start.springs.find(pair);
      springs[pair] = (begun == start.springs.end() ? Eigen::Vector3d::Zero() : begun->second) + h * velocity;
    }
    step.touching = step.touching || middle.touching;
  }
  return step;
}

}  // namespace settle::body
