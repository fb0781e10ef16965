// Body-body contact (body/pair_contact.hpp): the force law at a state, and free collisions integrated
// by advance_in_contact against closed forms (restitution and duration of head-on impacts with the
// reduced mass, sliding and stuck oblique impacts of spheres) and conservation laws (linear and
// angular momentum, energy never increasing).
#include <algorithm>
#include <cmath>
#include <cstdio>
#include <memory>
#include <numbers>
#include <vector>

#include <gtest/gtest.h>
#include <Eigen/Geometry>

#include "support/matrix_checks.hpp"

#include "body/cuboid.hpp"
#include "body/ellipsoid.hpp"
#include "body/pair_contact.hpp"

namespace settle::body {
namespace test_pair_contact {

using settle::test::rotation_about;

RigidBody body_of(const Shape& shape, double density, const Eigen::Vector3d& position, const Eigen::Vector3d& velocity,
                  const Eigen::Vector3d& omega_b = Eigen::Vector3d::Zero(),
                  const Eigen::Matrix3d& rotation = Eigen::Matrix3d::Identity()) {
  const RigidBodyState state{position, velocity, attitude::Attitude::from_matrix(rotation), omega_b};
  return RigidBody(shape.mass_properties(density), Environment{}, state);
}

PairContactParameters parameters(double restitution, double friction, double collision_time = 0.01,
                                 double contact_distance = 0.05) {
  PairContactParameters p;
  p.restitution = restitution;
  p.friction_coefficient = friction;
  p.collision_time_si = collision_time;
  p.contact_distance_si = contact_distance;
  return p;
}

Eigen::Vector3d linear_momentum(const std::vector<RigidBody>& bodies) {
  Eigen::Vector3d p = Eigen::Vector3d::Zero();
  for (const auto& b : bodies) p += b.mass_properties().mass * b.state().velocity_si;
  return p;
}

// About the inertial origin: the centres' orbital part plus each body's spin.
Eigen::Vector3d angular_momentum(const std::vector<RigidBody>& bodies) {
  Eigen::Vector3d l = Eigen::Vector3d::Zero();
  for (const auto& b : bodies)
    l += b.state().position_si.cross(b.mass_properties().mass * b.state().velocity_si) + b.angular_momentum_n_si();
  return l;
}

// Kinetic energy plus the energy of the springs of the contacts in progress.
double mechanical_energy(const std::vector<RigidBody>& bodies, const std::vector<const Shape*>& shapes,
                         const PairSprings& springs, const PairContactParameters& p) {
  double energy = 0.0;
  for (const auto& b : bodies) energy += b.kinetic_energy_si();
  for (std::size_t i = 0; i < bodies.size(); ++i)
    for (std::size_t j = i + 1; j < bodies.size(); ++j) {
      const auto spring = springs.find({i, j});
      const PairContactForce f =
          pair_contact_force({shapes[i], &bodies[i]}, {shapes[j], &bodies[j]},
                             spring == springs.end() ? Eigen::Vector3d::Zero() : spring->second, p);
      if (!f.touching) continue;
      const double k =
          pair_spring_dashpot(bodies[i].mass_properties().mass, bodies[j].mass_properties().mass, 1.0, p).stiffness;
      const double overlap = p.contact_distance_si - f.separation.distance_si;
      energy += 0.5 * k * overlap * overlap + 0.5 * p.tangential_stiffness_ratio * k * f.spring_si.squaredNorm();
    }
  return energy;
}

struct Collision {
  std::vector<RigidBody> before, after;
  double contact_time = 0.0;         ///< whole fluid steps with a contact force
  double momentum_drift = 0.0;       ///< largest |P(t) - P(0)|
  double angular_drift = 0.0;        ///< largest |L(t) - L(0)| about the origin
  double energy_increase = 0.0;      ///< largest E(t) - E(0), kinetic plus springs
  double largest_energy_step = 0.0;  ///< largest E(t + dt) - E(t)
};

/// Integrates two bodies with fluid steps dt until they have touched and parted again.
Collision collide(std::vector<RigidBody> bodies, const std::vector<const Shape*>& shapes,
                  const PairContactParameters& p, double dt) {
  Collision c;
  c.before = bodies;
  PairSprings springs;
  const Eigen::Vector3d p0 = linear_momentum(bodies), l0 = angular_momentum(bodies);
  const double e0 = mechanical_energy(bodies, shapes, springs, p);
  double previous_energy = e0;
  bool touched = false;
  for (int step = 0; step < 100000; ++step) {
    const PairContactStep s = advance_in_contact(bodies, shapes, springs, dt, p);
    c.momentum_drift = std::max(c.momentum_drift, (linear_momentum(bodies) - p0).norm());
    c.angular_drift = std::max(c.angular_drift, (angular_momentum(bodies) - l0).norm());
    const double energy = mechanical_energy(bodies, shapes, springs, p);
    c.energy_increase = std::max(c.energy_increase, energy - e0);
    c.largest_energy_step = std::max(c.largest_energy_step, energy - previous_energy);
    previous_energy = energy;
    if (s.touching) {
      touched = true;
      c.contact_time += dt;
    } else if (touched) {
      break;
    }
  }
  c.after = bodies;
  return c;
}

// The normal relative velocity of B with respect to A along the line of centres (spheres).
double normal_speed(const std::vector<RigidBody>& b) {
  const Eigen::Vector3d n = (b[1].state().position_si - b[0].state().position_si).normalized();
  return n.dot(b[1].state().velocity_si - b[0].state().velocity_si);
}

// The bound of the rebound ratio's error of the wall test (tests/body/test_contact.cpp): the dashpot
// switching on and off inside a substep costs at most half a substep of dashpot impulse each,
// |ln e| (1 + e) / N of the impact speed; 1e-4 more for the midpoint rule (second order, ~1e-5 at
// N = 100 substeps per collision).
double restitution_bound(const PairContactParameters& p) {
  return std::abs(std::log(p.restitution)) * (1.0 + p.restitution) / p.substeps_per_collision + 1e-4;
}

// ---------------------------------------------------------------------------------------------
// Force law.

TEST(PairContactForce, EqualAndOppositeWithTorquesFromTheContactPoint) {
  const Ellipsoid spheroid(Eigen::Vector3d(0.2, 0.2, 0.5));
  const Cuboid cuboid(Eigen::Vector3d(0.6, 0.4, 0.3));
  const PairContactParameters p = parameters(0.7, 0.4);
  const RigidBody a = body_of(spheroid, 1000.0, Eigen::Vector3d::Zero(), {0.1, 0.0, 0.2}, {0.3, -0.1, 0.2},
                              rotation_about({1.0, 0.0, 1.0}, 0.5));
  // Place the cuboid 0.01 inside the contact distance along some direction.
  const Eigen::Matrix3d rotation_b = rotation_about({0.2, 1.0, -0.4}, 1.1);
  const Eigen::Vector3d direction = Eigen::Vector3d(0.3, -0.5, 1.0).normalized();
  // The centre distance t along `direction` where d = zeta_c - 0.01: d grows with t at the rate
  // n . direction in (0, 1], so t += (target - d) converges.
  double t = 1.0;
  for (int i = 0; i < 100; ++i)
    t += p.contact_distance_si - 0.01 -
         convex_distance({&spheroid, a.state().position_si, a.body_to_inertial()}, {&cuboid, t * direction, rotation_b})
             .distance_si;
  const RigidBody b = body_of(cuboid, 2500.0, t * direction, {-0.2, 0.1, -0.3}, {0.0, 0.5, -0.2}, rotation_b);
  const Eigen::Vector3d spring(0.001, -0.002, 0.0005);
  const PairContactForce f = pair_contact_force({&spheroid, &a}, {&cuboid, &b}, spring, p);
  ASSERT_TRUE(f.touching);
  EXPECT_NEAR(p.contact_distance_si - f.separation.distance_si, 0.01, 1e-9);
  // Equal and opposite at one point: the total torque about any point vanishes.
  const Eigen::Vector3d contact = 0.5 * (f.separation.point_a_si + f.separation.point_b_si);
  EXPECT_LT((f.on_a.force_si + f.on_b.force_si).norm(), 1e-12 * f.on_b.force_si.norm());
  EXPECT_LT((f.on_b.torque_si - (contact - b.state().position_si).cross(f.on_b.force_si)).norm(),
            1e-12 * f.on_b.force_si.norm());
  const Eigen::Vector3d total_torque_about_origin = a.state().position_si.cross(f.on_a.force_si) + f.on_a.torque_si +
                                                    b.state().position_si.cross(f.on_b.force_si) + f.on_b.torque_si;
  EXPECT_LT(total_torque_about_origin.norm(), 1e-12 * f.on_b.force_si.norm() * t);
  // The spring lies in the tangent plane with its length kept (or cut), the force within Coulomb's cone.
  const Eigen::Vector3d n = f.separation.normal;
  EXPECT_LT(std::abs(n.dot(f.spring_si)), 1e-15);
  EXPECT_LE(f.spring_si.norm(), spring.norm() * (1.0 + 1e-15));
  EXPECT_LE(f.tangential_force_si.norm(), p.friction_coefficient * std::max(f.normal_force_si, 0.0) * (1.0 + 1e-15));
  EXPECT_NEAR(n.dot(f.on_b.force_si), f.normal_force_si, 1e-12 * f.on_b.force_si.norm());
}

TEST(PairContactForce, StuckSpringBelowTheCoulombLimitAndCutAboveIt) {
  // Two spheres (closed-form distance) overlapping by 0.01 at rest: F_n = k 0.01, no dashpot.
  const Ellipsoid sphere = Ellipsoid::sphere(1.0);
  PairContactParameters p = parameters(0.8, 0.5);
  const RigidBody a = body_of(sphere, 1000.0, Eigen::Vector3d::Zero(), Eigen::Vector3d::Zero());
  const RigidBody b = body_of(sphere, 1000.0, {1.0 + p.contact_distance_si - 0.01, 0.0, 0.0}, Eigen::Vector3d::Zero());
  const double m = a.mass_properties().mass;
  const double k = pair_spring_dashpot(m, m, 0.5 * m, p).stiffness;
  EXPECT_NEAR(k, 0.5 * m * (std::pow(std::numbers::pi, 2) + std::pow(std::log(0.8), 2)) / 1e-4, 1e-9 * k);
  const double normal = k * 0.01, kt = p.tangential_stiffness_ratio * k;
  // A spring with a normal component: rotated into the plane with its length kept.
  const Eigen::Vector3d small(0.001, 0.002, 0.0);  // |F_t| = k_t |xi| well below mu F_n
  PairContactForce f = pair_contact_force({&sphere, &a}, {&sphere, &b}, small, p);
  EXPECT_NEAR(f.normal_force_si, normal, 1e-12 * normal);
  EXPECT_LT((f.spring_si - Eigen::Vector3d(0.0, small.norm(), 0.0)).norm(), 1e-15);
  EXPECT_LT((f.tangential_force_si + kt * f.spring_si).norm(), 1e-12 * normal);
  // Above the limit: cut to mu F_n, the spring to match.
  const Eigen::Vector3d large(0.0, 0.0, 0.5);
  f = pair_contact_force({&sphere, &a}, {&sphere, &b}, large, p);
  EXPECT_NEAR(f.tangential_force_si.norm(), p.friction_coefficient * normal, 1e-12 * normal);
  EXPECT_LT((f.tangential_force_si.normalized() + Eigen::Vector3d::UnitZ()).norm(), 1e-15);
  EXPECT_NEAR(f.spring_si.norm(), p.friction_coefficient * normal / kt, 1e-12 * large.norm());
  // Beyond the contact distance: nothing.
  const RigidBody apart = body_of(sphere, 1000.0, {1.0 + p.contact_distance_si, 0.0, 0.0}, {-1.0, 0.0, 0.0});
  f = pair_contact_force({&sphere, &a}, {&sphere, &apart}, large, p);
  EXPECT_FALSE(f.touching);
  EXPECT_EQ(f.on_b.force_si.norm(), 0.0);
  p.friction_coefficient = -0.1;
  EXPECT_THROW(validate_pair_contact(p), std::invalid_argument);
}

// ---------------------------------------------------------------------------------------------
// Free collisions.

TEST(PairCollision, EqualSpheresHeadOnReboundWithTheRestitutionAfterTheCollisionTime) {
  const Ellipsoid sphere = Ellipsoid::sphere(1.0);
  const std::vector<const Shape*> shapes{&sphere, &sphere};
  for (double e : {1.0, 0.8, 0.5})
    for (double phase : {0.0, 0.37}) {  // where in a fluid step the contact starts
      const PairContactParameters p = parameters(e, 0.3);
      const double v = 0.2, t_c = p.collision_time_si, dt = t_c / 10.0;
      // Each moves at v/2 towards the other along x: the spring starts at centre distance 1 + zeta_c.
      const double start = 0.5 * (1.0 + p.contact_distance_si) + 0.5 * phase * v * dt;
      const Collision c = collide({body_of(sphere, 1000.0, {-start, 0.0, 0.0}, {0.5 * v, 0.0, 0.0}),
                                   body_of(sphere, 1000.0, {start, 0.0, 0.0}, {-0.5 * v, 0.0, 0.0})},
                                  shapes, p, dt);
      const double ratio = normal_speed(c.after) / v;
      const double momentum_scale = c.before[0].mass_properties().mass * v;
      std::printf(
          "[measured] equal spheres head-on e = %.2f, phase %.2f: rebound ratio %.6f, contact %.2f T_c, momentum drift "
          "%.1e, energy increase %.1e (of m v^2)\n",
          e, phase, ratio, c.contact_time / t_c, c.momentum_drift / momentum_scale,
          c.energy_increase / (momentum_scale * v));
      EXPECT_NEAR(ratio, e, restitution_bound(p));
      EXPECT_NEAR(c.contact_time, t_c, 2.0 * dt + 1e-12);  // T_c in whole fluid steps: one at each end
      // Equal and opposite forces each substep: round-off, a few eps of m v per substep over ~1000.
      EXPECT_LT(c.momentum_drift, 1e-12 * momentum_scale);
      // Head-on: no tangential force, no spin.
      EXPECT_LT(c.after[0].state().angular_velocity_b_si.norm(), 1e-12);
      EXPECT_LT(c.after[1].state().velocity_si.tail<2>().norm(), 1e-12);
    }
}

TEST(PairCollision, UnequalMassesCollideWithTheReducedMass) {
  // Radii 0.5 and 0.3, densities 1000 and 8000: m* = m_a m_b / (m_a + m_b). A centred impact of
  // restitution e leaves with v_a' = v_a - (1 + e) m* / m_a (v_a - v_b) and v_b' = v_b + (1 + e) m* /
  // m_b (v_a - v_b) (Stronge 2000), after T_c.
  const Ellipsoid large = Ellipsoid::sphere(1.0), small = Ellipsoid::sphere(0.6);
  const std::vector<const Shape*> shapes{&large, &small};
  const PairContactParameters p = parameters(0.8, 0.0);
  const double t_c = p.collision_time_si, dt = t_c / 10.0, v_a = 0.15, v_b = -0.1;
  const Eigen::Vector3d axis = Eigen::Vector3d(1.0, 2.0, -0.5).normalized();
  const double gap = p.contact_distance_si + 0.3 * (v_a - v_b) * dt;
  const Collision c = collide({body_of(large, 1000.0, Eigen::Vector3d::Zero(), v_a * axis),
                               body_of(small, 8000.0, (0.8 + gap) * axis, v_b * axis)},
                              shapes, p, dt);
  const double m_a = c.before[0].mass_properties().mass, m_b = c.before[1].mass_properties().mass;
  const double reduced = m_a * m_b / (m_a + m_b), approach = v_a - v_b;
  const double exact_a = v_a - (1.0 + p.restitution) * reduced / m_a * approach;
  const double exact_b = v_b + (1.0 + p.restitution) * reduced / m_b * approach;
  const double after_a = axis.dot(c.after[0].state().velocity_si), after_b = axis.dot(c.after[1].state().velocity_si);
  std::printf(
      "[measured] unequal spheres (m_b / m_a = %.2f): v_a' %.6f (exact %.6f), v_b' %.6f (exact %.6f), contact %.2f "
      "T_c, "
      "momentum drift %.1e\n",
      m_b / m_a, after_a, exact_a, after_b, exact_b, c.contact_time / t_c, c.momentum_drift / (m_a * approach));
  // The rebound ratio's bound, carried by each body's share m* / m of the relative velocity change.
  EXPECT_NEAR(after_a, exact_a, restitution_bound(p) * approach * reduced / m_a);
  EXPECT_NEAR(after_b, exact_b, restitution_bound(p) * approach * reduced / m_b);
  EXPECT_NEAR(c.contact_time, t_c, 2.0 * dt + 1e-12);  // the reduced mass sets the duration
  EXPECT_LT(c.momentum_drift, 1e-12 * m_a * approach);
}

// Two equal spheres of radius R = 0.5 meeting obliquely: B approaches along -x at v_n with
// tangential velocity u_t along y; no spin before. With zeta_c = 0 and a short T_c the arms stay R
// to v_n T_c / (pi R) and the line of centres turns by theta = u_t T_c / (2R) during the contact,
// which changes the normal speed by theta u_t / v_n and moves theta J_n into the fixed y axis
// where the tangential impulse is measured: T_c is chosen to keep these below 1e-4.
struct Oblique {
  Collision collision;
  double normal_impulse = 0.0, tangential_impulse = 0.0;  // on B
  Eigen::Vector3d spin_a, spin_b;                         // inertial, after
  double tangential_after = 0.0;                          // contact point's tangential velocity of B rel. A
};

Oblique oblique(double restitution, double friction, double v_n, double u_t, double collision_time) {
  static const Ellipsoid sphere = Ellipsoid::sphere(1.0);
  const PairContactParameters p = parameters(restitution, friction, collision_time, 0.0);
  const double dt = p.collision_time_si / 10.0;
  Oblique o;
  o.collision = collide({body_of(sphere, 1000.0, Eigen::Vector3d::Zero(), Eigen::Vector3d::Zero()),
                         body_of(sphere, 1000.0, {1.0 + 0.3 * v_n * dt, 0.0, 0.0}, {-v_n, u_t, 0.0})},
                        {&sphere, &sphere}, p, dt);
  const RigidBody& b = o.collision.after[1];
  const Eigen::Vector3d impulse = b.mass_properties().mass * (b.state().velocity_si - Eigen::Vector3d(-v_n, u_t, 0.0));
  o.normal_impulse = impulse.x();
  o.tangential_impulse = std::hypot(impulse.y(), impulse.z());
  o.spin_a = o.collision.after[0].angular_velocity_n_si();
  o.spin_b = b.angular_velocity_n_si();
  // Contact points at +-R along the (final) line of centres.
  const Eigen::Vector3d n = (b.state().position_si - o.collision.after[0].state().position_si).normalized();
  const Eigen::Vector3d u = (b.state().velocity_si - 0.5 * o.spin_b.cross(n)) -
                            (o.collision.after[0].state().velocity_si + 0.5 * o.spin_a.cross(n));
  o.tangential_after = u.y();
  return o;
}

TEST(PairCollision, SlidingObliqueImpactHasTheCoulombImpulse) {
  // Slides throughout when the stuck spring's force would exceed mu F_n from the first instant:
  // for e = 1 both grow as sin(omega t) with ratio (2/7) u_t / v_n (below), here 1.43 > mu = 0.1;
  // the tangential velocity falls by 3.5 mu (1 + e) v_n = 0.14, so it never stops. Then every
  // evaluation has |F_t| = mu F_n: J_t = mu J_n (Coulomb), and I omega = R J_t on each sphere.
  for (double e : {1.0, 0.8}) {
    const double v_n = 0.2, u_t = 1.0, mu = 0.1;
    const Oblique o = oblique(e, mu, v_n, u_t, 1e-5);  // theta = 1e-5: effects <= 1e-4 (above)
    const double m = o.collision.before[0].mass_properties().mass, inertia = 0.4 * m * 0.25;
    std::printf(
        "[measured] sliding e = %.1f, mu = %.1f: J_t / (mu J_n) = %.6f, J_n / (m* (1 + e) v_n) = %.6f, spin / (R J_t / "
        "I) = %.6f, %.6f; momentum drift %.1e, angular momentum drift %.1e, energy increase %.1e\n",
        e, mu, o.tangential_impulse / (mu * o.normal_impulse), o.normal_impulse / (0.5 * m * (1.0 + e) * v_n),
        o.spin_a.norm() / (0.5 * o.tangential_impulse / inertia),
        o.spin_b.norm() / (0.5 * o.tangential_impulse / inertia), o.collision.momentum_drift / (m * u_t),
        o.collision.angular_drift / (m * u_t * 0.5), o.collision.energy_increase / (m * u_t * u_t));
    // Never above the Coulomb bound (the pulling end of a damped rebound transmits no friction and
    // its pull lowers J_n, so the ratio may exceed 1 by the pull's share of J_n: ~|ln e| / N).
    const double pull_share = std::abs(std::log(e)) * e / 100.0;
    EXPECT_LE(o.tangential_impulse, mu * o.normal_impulse * (1.0 + pull_share + 1e-9));
    // Sliding throughout: equal to the bound to the turn of the line of centres (theta / mu = 1e-4)
    // and the start of the spring (it needs the first half substep to reach the limit: 1/200 of a
    // contact's first 1/100, ~1e-4 of J_t); 1e-3 allows for both.
    EXPECT_NEAR(o.tangential_impulse, mu * o.normal_impulse, (1e-3 + pull_share) * mu * o.normal_impulse);
    // I omega = R J_t for each sphere (arms R to v_n T_c / (pi R) = 1.3e-6, and theta).
    EXPECT_NEAR(o.spin_a.norm(), 0.5 * o.tangential_impulse / inertia, 1e-3 * o.spin_a.norm());
    EXPECT_NEAR(o.spin_b.norm(), 0.5 * o.tangential_impulse / inertia, 1e-3 * o.spin_b.norm());
    // The normal impulse of the head-on closed form, m* (1 + e) v_n, to the restitution bound.
    EXPECT_NEAR(o.normal_impulse, 0.5 * m * (1.0 + e) * v_n, (restitution_bound(parameters(e, mu)) + 1e-4) * m * v_n);
    EXPECT_LT(o.collision.momentum_drift, 1e-12 * m * u_t);
    EXPECT_LE(o.collision.energy_increase, 0.0);  // sliding dissipates
  }
}

TEST(PairCollision, StuckObliqueImpactReversesTheTangentialVelocityAndSpinsBothSpheres) {
  // Closed form: while stuck, the contact points' relative tangential motion is an undamped
  // oscillator of mass m_t and stiffness k_t, with 1 / m_t = 1/m* + R^2 / I_a + R^2 / I_b = 7 / (2 m*)
  // for two solid spheres (the impulse relations of Stronge 2000, chapter 3, applied tangentially),
  // so omega_t^2 = k_t / m_t = (2/7) k / ((2/7) m*) = k / m*: for e = 1 the normal frequency, and the
  // tangential force stays (2/7) u_t / v_n times the normal force. With mu = 1 > (2/7) (0.1 / 0.2)
  // the contact sticks throughout, and after the half period T_c the tangential velocity is
  // reversed: J_t = 2 m_t u_t = (2/7) m u_t and each sphere spins up by R J_t / I = (5/7) u_t / R,
  // both in the sense of n x t.
  const double v_n = 0.2, u_t = 0.1, radius = 0.5;
  const Oblique o = oblique(1.0, 1.0, v_n, u_t, 1e-4);
  const double m = o.collision.before[0].mass_properties().mass;
  const Eigen::Vector3d spin = (5.0 / 7.0) * u_t / radius * Eigen::Vector3d::UnitX().cross(Eigen::Vector3d::UnitY());
  std::printf(
      "[measured] stuck e = 1, mu = 1: u_t' / u_t = %.6f, J_t / ((2/7) m u_t) = %.6f, spins / (5/7 u_t / R) = %.6f, "
      "%.6f; angular momentum drift %.1e, energy change %.1e\n",
      o.tangential_after / u_t, o.tangential_impulse / (2.0 / 7.0 * m * u_t), o.spin_a.dot(spin) / spin.squaredNorm(),
      o.spin_b.dot(spin) / spin.squaredNorm(), o.collision.angular_drift / (m * u_t * radius),
      o.collision.energy_increase / (m * v_n * v_n));
  // Errors: the line of centres turns by u_t T_c / (2R) = 1e-5 rad (theta u_t / v_n = 5e-6), the
  // arms are R to 1.3e-5, the midpoint rule ~1e-4 at 100 substeps: 1e-3 of each quantity.
  EXPECT_NEAR(o.tangential_after, -u_t, 1e-3 * u_t);
  EXPECT_NEAR(o.tangential_impulse, 2.0 / 7.0 * m * u_t, 1e-3 * 2.0 / 7.0 * m * u_t);
  EXPECT_LT((o.spin_a - spin).norm(), 1e-3 * spin.norm());
  EXPECT_LT((o.spin_b - spin).norm(), 1e-3 * spin.norm());
}

TEST(PairCollision, AngularMomentumIsConservedAndEnergyNeverIncreases) {
  // A spinning tilted spheroid meets a spinning tilted cuboid off-centre (0.07 m apart at the start,
  // 0.02 outside the contact distance), with friction. Angular
  // momentum about the origin: each evaluation's torques sum to zero about any point (equal and
  // opposite forces at one point), so only the integration moves it. RigidBody::correct holds the
  // torque constant in the body frame over a (sub)step, converted with the attitude at its end (an
  // approximation of first order in the rotation during the step, body/rigid_body.hpp): the drift
  // is first order in the substep and must halve when the substeps double. Energy, kinetic plus the
  // springs', never increases when e < 1 (by more than the midpoint rule's error on an elastic
  // contact, measured here at e = 1).
  const Ellipsoid spheroid(Eigen::Vector3d(0.2, 0.2, 0.5));
  const Cuboid cuboid(Eigen::Vector3d(0.6, 0.4, 0.3));
  const std::vector<const Shape*> shapes{&spheroid, &cuboid};
  const auto run = [&](double e, int substeps) {
    PairContactParameters p = parameters(e, 0.4);
    p.substeps_per_collision = substeps;
    return collide({body_of(spheroid, 1000.0, Eigen::Vector3d::Zero(), {0.2, 0.05, 0.0}, {0.5, -1.0, 0.3},
                            rotation_about({1.0, 0.0, 1.0}, 0.5)),
                    body_of(cuboid, 2500.0, {0.6, 0.11, -0.11}, {-0.2, 0.0, 0.05}, {0.0, 0.8, -0.4},
                            rotation_about({0.2, 1.0, -0.4}, 1.1))},
                   shapes, p, p.collision_time_si / 10.0);
  };
  const Collision elastic = run(1.0, 100), coarse = run(0.7, 100), fine = run(0.7, 200);
  const double m = coarse.before[0].mass_properties().mass, scale = m * 0.4 * 0.6;  // m |v| r
  const double energy = elastic.before[0].kinetic_energy_si() + elastic.before[1].kinetic_energy_si();
  std::printf(
      "[measured] spheroid-cuboid e = 0.7: angular momentum drift %.2e (100 substeps/T_c), %.2e (200), ratio %.2f; "
      "contact %.2f T_c; energy: largest step increase %.1e, final / initial %.4f; elastic e = 1: energy change "
      "%.1e\n",
      coarse.angular_drift / scale, fine.angular_drift / scale, coarse.angular_drift / fine.angular_drift,
      coarse.contact_time / 0.01, coarse.largest_energy_step / energy,
      (coarse.after[0].kinetic_energy_si() + coarse.after[1].kinetic_energy_si()) / energy,
      elastic.energy_increase / energy);
  ASSERT_GT(coarse.contact_time, 0.0);
  EXPECT_LT(coarse.angular_drift, 1e-4 * scale);
  // First order: 2 for halved substeps; 1.8 allows for the second-order parts of opposite sign.
  EXPECT_GT(coarse.angular_drift / fine.angular_drift, 1.8);
  EXPECT_LT(coarse.momentum_drift, 1e-12 * m * 0.4);
  EXPECT_LE(coarse.largest_energy_step, std::max(elastic.energy_increase, 0.0) + 1e-12 * energy);
  EXPECT_LT(coarse.after[0].kinetic_energy_si() + coarse.after[1].kinetic_energy_si(), energy);
}

TEST(PairCollision, ApartBodiesMoveAsWithoutContact) {
  const Ellipsoid sphere = Ellipsoid::sphere(1.0);
  std::vector<RigidBody> bodies{body_of(sphere, 1000.0, Eigen::Vector3d::Zero(), {0.1, 0.0, 0.0}),
                                body_of(sphere, 1000.0, {3.0, 0.0, 0.0}, {0.0, 0.1, 0.0})};
  std::vector<RigidBody> alone = bodies;
  PairSprings springs;
  const PairContactStep s = advance_in_contact(bodies, {&sphere, &sphere}, springs, 1e-3, parameters(0.8, 0.3));
  for (auto& b : alone) b.correct(1e-3, Wrench{});
  EXPECT_EQ(s.substeps, 1);
  EXPECT_FALSE(s.touching);
  EXPECT_EQ(bodies[1].state().position_si, alone[1].state().position_si);  // bit for bit: the same call
  EXPECT_THROW(advance_in_contact(bodies, {&sphere}, springs, 1e-3, parameters(0.8, 0.3)), std::invalid_argument);
}

}  // namespace test_pair_contact
}  // namespace settle::body
