// Particle-wall contact (body/contact.hpp): the contact point and gap of every shape against
// closed forms, the force law's range and continuity, and dry impacts against the spring-dashpot's
// closed forms (restitution, duration, overlap) and energy conservation.
#include <algorithm>
#include <cmath>
#include <cstdio>
#include <limits>
#include <memory>
#include <numbers>
#include <random>
#include <utility>
#include <vector>

#include <gtest/gtest.h>
#include <Eigen/Geometry>

#include "shape_test_support.hpp"
#include "support/matrix_checks.hpp"

#include "body/contact.hpp"
#include "body/cuboid.hpp"
#include "body/cylinder.hpp"
#include "body/ellipsoid.hpp"
#include "body/mesh_shape.hpp"
#include "body/superellipsoid.hpp"

namespace settle::body {
namespace test_contact {

using settle::test::rotation_about;

/// Body-frame directions: the axes, a few generic ones and one 1e-3 rad off an axis.
std::vector<Eigen::Vector3d> test_directions() {
  std::vector<Eigen::Vector3d> d = {Eigen::Vector3d::UnitX(), -Eigen::Vector3d::UnitY(), -Eigen::Vector3d::UnitZ(),
                                    {1.0, 2.0, -3.0},         {-0.3, 0.1, 0.9},          {0.7, -0.7, 0.1},
                                    {1e-3, 0.0, -1.0},        {-2.0, -1.0, -0.5}};
  for (auto& v : d) v.normalize();
  return d;
}

/// Attitudes (body to inertial) at which the gap is checked.
std::vector<Eigen::Matrix3d> test_attitudes() {
  return {Eigen::Matrix3d::Identity(), rotation_about({1.0, 2.0, 3.0}, 0.7),
          rotation_about(Eigen::Vector3d::UnitX(), std::numbers::pi / 2.0), rotation_about({-1.0, 0.5, 0.2}, 2.9)};
}

// ---------------------------------------------------------------------------------------------
// Contact point: the support point of each shape.

TEST(SupportPoint, EllipsoidMatchesClosedForm) {
  // The support point of an ellipsoid x^T A^-1 x = 1, A = diag(a^2), is A u / sqrt(u^T A u).
  const Eigen::Vector3d a(0.5, 1.0, 1.5);
  const Ellipsoid ellipsoid(a);
  const Eigen::Matrix3d A = a.cwiseProduct(a).asDiagonal();
  double worst = 0.0;
  for (const auto& u : test_directions()) {
    const Eigen::Vector3d exact = A * u / std::sqrt(u.dot(A * u));
    worst = std::max(worst, (support_point(ellipsoid, u) - exact).norm());
  }
  std::printf("[measured] ellipsoid support point error %.2e (semi-axes 0.5, 1, 1.5)\n", worst);
  // Central differences with step 1e-4: truncation (step^2 / 6) h''' with |h'''| of order
  // a_max (a_max / a_min)^2 = 13.5 gives ~2e-8; round-off eps / step ~ 2e-12.
  EXPECT_LT(worst, 1e-7);
}

TEST(SupportPoint, SphereCylinderAndCuboidMatchClosedForms) {
  const Ellipsoid sphere(Eigen::Vector3d::Constant(0.8), "sphere");
  const double radius = 0.5, length = 2.0;
  const Cylinder cylinder(2.0 * radius, length);
  const Eigen::Vector3d size(1.0, 2.0, 0.5);
  const Cuboid cuboid(size);
  double worst = 0.0;
  for (const auto& u : test_directions()) {
    worst = std::max(worst, (support_point(sphere, u) - 0.8 * u).norm());
    const Eigen::Vector2d radial = u.head<2>();
    const Eigen::Vector3d rim(radius * radial.x() / radial.norm(), radius * radial.y() / radial.norm(),
                              0.5 * length * std::copysign(1.0, u.z()));
    // The generic directions touch one rim point and one corner (no zero components).
    if (u.cwiseAbs().minCoeff() > 1e-2) {
      worst = std::max(worst, (support_point(cylinder, u) - rim).norm());
      const Eigen::Vector3d corner = 0.5 * size.cwiseProduct(u.cwiseSign());
      worst = std::max(worst, (support_point(cuboid, u) - corner).norm());
    }
  }
  // Faces and edges parallel to the wall: the middle of the touching set (file comment of contact.hpp).
  worst = std::max(worst, (support_point(cylinder, -Eigen::Vector3d::UnitZ()) - Eigen::Vector3d(0, 0, -1.0)).norm());
  worst = std::max(worst, (support_point(cylinder, Eigen::Vector3d::UnitY()) - Eigen::Vector3d(0, radius, 0)).norm());
  worst = std::max(worst, (support_point(cuboid, -Eigen::Vector3d::UnitZ()) - Eigen::Vector3d(0, 0, -0.25)).norm());
  const Eigen::Vector3d edge_direction = Eigen::Vector3d(1.0, 0.0, -1.0).normalized();
  worst = std::max(worst, (support_point(cuboid, edge_direction) - Eigen::Vector3d(0.5, 0.0, -0.25)).norm());
  std::printf("[measured] sphere/cylinder/cuboid support point error %.2e\n", worst);
  // The cuboid's support function is piecewise linear and the sphere's tangential differences
  // cancel exactly: round-off, eps / step ~ 1e-12. The cylinder's rim term R |u_xy| is smooth:
  // truncation (step^2 / 6) R / |u_xy|^2 ~ 1e-8 R for |u_xy| >= 0.3 as here.
  EXPECT_LT(worst, 1e-7);
}

TEST(SupportPoint, SuperellipsoidPointIsOnTheSurfaceWithNormalAlongTheDirection) {
  // No closed form used: a point of a smooth convex surface whose outward normal is u is the
  // support point in direction u. The shape's own signed distance and normal check it.
  double worst_distance = 0.0, worst_normal = 0.0;
  for (const auto& [e1, e2] : {std::pair{0.5, 0.5}, std::pair{1.5, 0.8}, std::pair{0.8, 1.2}}) {
    const Superellipsoid shape(Eigen::Vector3d(0.6, 1.0, 0.8), e1, e2);
    for (const auto& u : test_directions()) {
      if (u.cwiseAbs().minCoeff() < 1e-2) continue;  // edges of the flattest exponents are very sharp
      const Eigen::Vector3d p = support_point(shape, u);
      worst_distance = std::max(worst_distance, std::abs(shape.signed_distance(p)));
      worst_normal = std::max(worst_normal, 1.0 - shape.outward_normal(p).dot(u));
    }
  }
  std::printf("[measured] superellipsoid support point: |distance| %.2e, 1 - cos(normal, u) %.2e\n", worst_distance,
              worst_normal);
  // Central-difference truncation ~1e-8 of the size (curvature radii down to ~0.1 here) moves the
  // point along the surface by that much, tilting the normal by ~1e-7; 1e-6 leaves a margin.
  EXPECT_LT(worst_distance, 1e-6);
  EXPECT_LT(worst_normal, 1e-6);
}

TEST(SupportPoint, MeshTouchesWithItsNearestVertexOrTheMiddleOfAFace) {
  const TriangleMesh sphere_mesh = testing::icosphere(2, 1.0);
  const MeshShape mesh(sphere_mesh, "icosphere");
  const Eigen::Vector3d centroid = mesh.volume_moments().centroid;
  double worst = 0.0;
  for (const auto& u : test_directions()) {
    Eigen::Vector3d best = sphere_mesh.vertices.front();
    for (const auto& v : sphere_mesh.vertices)
      if (u.dot(v) > u.dot(best)) best = v;
    // MeshShape moves the origin to the centroid.
    worst = std::max(worst, (support_point(mesh, u) - (best - centroid)).norm());
  }
  const MeshShape box(testing::box_mesh(Eigen::Vector3d(1.0, 2.0, 0.5)), "box");
  worst = std::max(worst, (support_point(box, -Eigen::Vector3d::UnitZ()) - Eigen::Vector3d(0, 0, -0.25)).norm());
  std::printf("[measured] mesh support point error %.2e\n", worst);
  EXPECT_LT(worst, 1e-10);  // the maximising vertex exactly, up to round-off eps / step
}

// ---------------------------------------------------------------------------------------------
// Gap to a wall.

TEST(WallGap, TiltedSpheroidMatchesClosedFormAndItsSurfaceMarkers) {
  const Eigen::Vector3d a(0.5, 0.5, 1.0);  // prolate spheroid, axis body z
  const auto spheroid = std::make_shared<Ellipsoid>(a, "spheroid");
  const Eigen::Matrix3d A = a.cwiseProduct(a).asDiagonal();
  const SurfaceMarkers markers = spheroid->surface_markers(0.03);
  const Eigen::Vector3d centre(0.1, -0.2, 1.3);
  const double height = 3.0;
  const std::vector<WallPlane> walls{{Eigen::Vector3d::UnitZ(), 0.0}, {-Eigen::Vector3d::UnitZ(), -height}};
  double worst_closed = 0.0, worst_markers = 0.0;
  for (const auto& rotation : test_attitudes())
    for (const auto& wall : walls) {
      const Eigen::Vector3d d = rotation.transpose() * (-wall.normal);
      const double exact = wall.normal.dot(centre) - std::sqrt(d.dot(A * d)) - wall.offset_si;
      const WallProximity p = nearest_to_wall(*spheroid, centre, rotation, wall);
      worst_closed = std::max(worst_closed, std::abs(p.gap_si - exact));
      // The contact point lies on the wall-parallel plane at that gap.
      worst_closed = std::max(worst_closed, std::abs(wall.normal.dot(p.point_si) - wall.offset_si - exact));
      double nearest_marker = std::numeric_limits<double>::infinity();
      for (const auto& m : markers.positions)
        nearest_marker = std::min(nearest_marker, wall.normal.dot(centre + rotation * m) - wall.offset_si);
      EXPECT_GE(nearest_marker, exact - 1e-12);  // markers lie on the surface: never nearer
      worst_markers = std::max(worst_markers, nearest_marker - exact);
    }
  std::printf("[measured] spheroid gap: closed form %.2e, nearest surface marker %.2e farther\n", worst_closed,
              worst_markers);
  EXPECT_LT(worst_closed, 1e-12);  // both are the support function: round-off
  // The nearest of markers spaced s = 0.03 is within ~s of the contact point; the surface rises
  // from the tangent plane by s^2 / (2 rho) with the smallest curvature radius rho = 0.25: 1.8e-3.
  EXPECT_LT(worst_markers, 1.8e-3);
}

// ---------------------------------------------------------------------------------------------
// Force law.

struct Rig {
  std::shared_ptr<const Shape> shape;
  MassProperties mass;
  ContactParameters parameters;
  WallPlane floor{Eigen::Vector3d::UnitZ(), 0.0};
};

Rig sphere_rig(double restitution) {
  Rig rig;
  rig.shape = std::make_shared<Ellipsoid>(Eigen::Vector3d::Constant(0.5), "sphere");
  rig.mass = rig.shape->mass_properties(1000.0);
  rig.parameters.restitution = restitution;
  rig.parameters.collision_time_si = 0.01;
  rig.parameters.contact_distance_si = 0.05;
  return rig;
}

RigidBody body_at(const Rig& rig, const Eigen::Vector3d& position, const Eigen::Vector3d& velocity,
                  const Eigen::Matrix3d& rotation = Eigen::Matrix3d::Identity(),
                  const Eigen::Vector3d& omega_b = Eigen::Vector3d::Zero(), const Environment& environment = {}) {
  RigidBodyState s{position, velocity, attitude::Attitude::from_matrix(rotation), omega_b};
  return RigidBody(rig.mass, environment, s);
}

TEST(ContactForce, ZeroBeyondTheContactDistanceAndTheSpringIsContinuous) {
  const Rig rig = sphere_rig(0.8);
  const WallContact contact(rig.shape, {rig.floor}, rig.parameters);
  const double zeta = rig.parameters.contact_distance_si, radius = 0.5;
  const SpringDashpot law = spring_dashpot(rig.mass.mass, rig.mass.mass, rig.parameters);
  const Eigen::Vector3d approaching(0.0, 0.0, -0.3);
  for (double gap : {zeta, zeta * (1.0 + 1e-12), 2.0 * zeta, 10.0}) {
    const RigidBody b = body_at(rig, {0.0, 0.0, radius + gap}, approaching);
    EXPECT_EQ(contact.wrench(b, b.state()).force_si.norm(), 0.0) << "gap " << gap;  // exactly zero outside
  }
  // Inside, at rest: the spring alone, k (zeta - g), which goes to zero continuously at zeta.
  for (double overlap : {1e-9, 1e-6, 1e-3}) {
    const RigidBody b = body_at(rig, {0.0, 0.0, radius + zeta - overlap}, Eigen::Vector3d::Zero());
    const Wrench w = contact.wrench(b, b.state());
    // Round-off of the centre's height (a few eps of 0.55 m) is all that separates them.
    EXPECT_NEAR(w.force_si.z(), law.stiffness * overlap, law.stiffness * 4.0 * 0.55 * 2.2e-16);
    EXPECT_NEAR(w.force_si.head<2>().norm(), 0.0, 1e-12);
    EXPECT_NEAR(w.torque_si.norm(), 0.0, 1e-12 * w.force_si.norm());  // a sphere's contact force is central
  }
  // Moving: the dashpot adds c |v_n| (it switches on with the contact; contact.hpp).
  const RigidBody moving = body_at(rig, {0.0, 0.0, radius + zeta - 1e-6}, approaching);
  EXPECT_NEAR(contact.wrench(moving, moving.state()).force_si.z(), law.stiffness * 1e-6 + law.damping * 0.3,
              1e-9 * law.damping * 0.3);
}

TEST(ContactForce, TiltedSpheroidIsPushedAtItsNearestPointWithTheMatchingTorque) {
  Rig rig = sphere_rig(0.5);
  const Eigen::Vector3d a(0.25, 0.25, 0.75);
  rig.shape = std::make_shared<Ellipsoid>(a, "spheroid");
  rig.mass = rig.shape->mass_properties(1000.0);
  const WallContact contact(rig.shape, {rig.floor}, rig.parameters);
  const Eigen::Matrix3d rotation = rotation_about(Eigen::Vector3d::UnitX(), 0.6);
  const Eigen::Matrix3d A = a.cwiseProduct(a).asDiagonal();
  const Eigen::Vector3d d = rotation.transpose() * (-Eigen::Vector3d::UnitZ());
  const Eigen::Vector3d arm = rotation * (A * d / std::sqrt(d.dot(A * d)));  // closed-form contact point
  const double overlap = 0.01;
  const Eigen::Vector3d centre(0.0, 0.0, -arm.z() + rig.parameters.contact_distance_si - overlap);
  const Eigen::Vector3d omega_b(0.4, -0.2, 0.3), velocity(0.1, 0.0, -0.2);
  const RigidBody b = body_at(rig, centre, velocity, rotation, omega_b);
  const Wrench w = contact.wrench(b, b.state());

  const Eigen::Matrix3d inverse_inertia_n = rotation * rig.mass.inertia.inverse() * rotation.transpose();
  const double m_eff = effective_mass(rig.mass.mass, inverse_inertia_n, arm, Eigen::Vector3d::UnitZ());
  const SpringDashpot law = spring_dashpot(rig.mass.mass, m_eff, rig.parameters);
  const double v_n = (velocity + (rotation * omega_b).cross(arm)).z();
  const Eigen::Vector3d force(0.0, 0.0, law.stiffness * overlap - law.damping * v_n);
  EXPECT_LT((w.force_si - force).norm(), 1e-8 * force.norm());  // gap and point to ~1e-8 (support_point)
  EXPECT_LT((w.torque_si - arm.cross(force)).norm(), 1e-7 * arm.norm() * force.norm());
  EXPECT_LT(m_eff, rig.mass.mass);  // the tip of a tilted spheroid moves more easily than its centre
}

TEST(ContactForce, EffectiveMassIsTheInverseOfTheContactPointsNormalMobility) {
  // Apply a normal impulse J at the contact point of a free body: the point's normal velocity must
  // change by J / m_eff (Newton and Euler for an impulse, independent of the formula's form).
  const auto shape = std::make_shared<Cuboid>(Eigen::Vector3d(0.3, 0.6, 1.2));
  const MassProperties mp = shape->mass_properties(800.0);
  const Eigen::Matrix3d rotation = rotation_about({1.0, -2.0, 0.5}, 1.1);
  const Eigen::Matrix3d inverse_inertia_n = rotation * mp.inertia.inverse() * rotation.transpose();
  const Eigen::Vector3d n = Eigen::Vector3d::UnitZ();
  const Eigen::Vector3d arm = rotation * support_point(*shape, rotation.transpose() * (-n));
  const double impulse = 2.5;
  const Eigen::Vector3d dv = impulse * n / mp.mass;
  const Eigen::Vector3d domega = inverse_inertia_n * arm.cross(impulse * n);
  const double dv_n = n.dot(dv + domega.cross(arm));
  EXPECT_NEAR(effective_mass(mp.mass, inverse_inertia_n, arm, n), impulse / dv_n, 1e-12 * mp.mass);  // round-off
}

// ---------------------------------------------------------------------------------------------
// Dry impacts through WallContact::advance (no fluid, no gravity unless stated).

struct Impact {
  double rebound_ratio = 0.0;  ///< normal speed after / before
  double contact_time = 0.0;   ///< time with a non-zero contact force
  double max_overlap = 0.0;    ///< largest zeta_c - gap seen at a substep's end
  double energy_before = 0.0, energy_after = 0.0;
  RigidBodyState after;
};

/// Runs a body into the floor with fluid steps dt until it has left the contact distance again.
Impact bounce(RigidBody body, WallContact contact, double dt) {
  Impact r;
  const double zeta = contact.parameters().contact_distance_si;
  const double v_in = body.state().velocity_si.z();
  r.energy_before = body.kinetic_energy_si();
  bool touched = false;
  for (int step = 0; step < 100000; ++step) {
    const ContactStep s = contact.advance(body, dt, Wrench{});
    if (s.touching) {
      touched = true;
      r.contact_time += dt;
    }
    r.max_overlap = std::max(r.max_overlap, zeta - s.min_gap_si);
    if (touched && !s.touching && s.min_gap_si > zeta) break;
  }
  r.rebound_ratio = -body.state().velocity_si.z() / v_in;
  r.energy_after = body.kinetic_energy_si();
  r.after = body.state();
  return r;
}

TEST(DryImpact, SphereReboundsWithTheRestitutionAfterTheCollisionTime) {
  for (double e : {1.0, 0.9, 0.5, 0.1})
    for (double phase : {0.0, 0.25, 0.5, 0.77}) {  // where in a fluid step the contact starts
      const Rig rig = sphere_rig(e);
      const WallContact contact(rig.shape, {rig.floor}, rig.parameters);
      const double v = 0.2, t_c = rig.parameters.collision_time_si, dt = t_c / 10.0;  // 10 fluid steps per collision
      const double zeta = rig.parameters.contact_distance_si;
      const Impact r = bounce(body_at(rig, {0.0, 0.0, 0.5 + zeta + phase * v * dt}, {0.0, 0.0, -v}), contact, dt);
      std::printf(
          "[measured] dry sphere impact e = %.2f, phase %.2f: rebound ratio %.6f, contact %.2f T_c, max overlap "
          "%.4f v T_c/pi\n",
          e, phase, r.rebound_ratio, r.contact_time / t_c, r.max_overlap / (v * t_c / std::numbers::pi));
      // Error sources: the explicit midpoint rule (second order: ~1e-5 with N = 100 substeps per
      // collision) and the dashpot switching on and off inside a substep, at most half a substep of
      // dashpot impulse each, c v h / 2, i.e. |ln e| / N of the incoming speed at the start and
      // |ln e| e / N at the end (contact.hpp). The tolerance is that bound plus 1e-4.
      const double switching = std::abs(std::log(e)) * (1.0 + e) / rig.parameters.substeps_per_collision;
      EXPECT_NEAR(r.rebound_ratio, e, switching + 1e-4);
      // Contact duration T_c, counted in whole fluid steps: within one step at each end.
      EXPECT_NEAR(r.contact_time, t_c, 2.0 * dt + 1e-12);
      // The largest overlap is below the undamped amplitude v T_c / pi (reached when e = 1).
      EXPECT_LE(r.max_overlap, max_overlap_bound(0.0, v, 1.0, t_c) * 1.001);
      if (e == 1.0) {
        EXPECT_NEAR(r.max_overlap, v * t_c / std::numbers::pi, 0.01 * v * t_c / std::numbers::pi);  // sampled peak
        EXPECT_NEAR(r.energy_after, r.energy_before, 1e-4 * r.energy_before);  // midpoint rule, ~1e-4 per contact
      }
      EXPECT_LT(r.after.angular_velocity_b_si.norm(), 1e-9);  // central force: no spin
    }
}

TEST(DryImpact, FlatCuboidBouncesFlatWithTheRestitution) {
  Rig rig = sphere_rig(0.7);
  rig.shape = std::make_shared<Cuboid>(Eigen::Vector3d(1.0, 0.6, 0.3));
  rig.mass = rig.shape->mass_properties(2500.0);
  const WallContact contact(rig.shape, {rig.floor}, rig.parameters);
  const double v = 0.2, dt = rig.parameters.collision_time_si / 10.0;
  const double zeta = rig.parameters.contact_distance_si;
  const Impact r = bounce(body_at(rig, {0.0, 0.0, 0.15 + zeta + 0.1 * v * dt}, {0.0, 0.0, -v}), contact, dt);
  std::printf("[measured] dry flat cuboid impact e = 0.7: rebound ratio %.6f, spin after %.2e rad/s\n", r.rebound_ratio,
              r.after.angular_velocity_b_si.norm());
  EXPECT_NEAR(r.rebound_ratio, 0.7, std::abs(std::log(0.7)) * 1.7 / 100.0 + 1e-4);  // as for the sphere
  // The face is pushed at its centre (support_point's central differences): no torque beyond
  // round-off, ~1e-12 of the force times the size.
  EXPECT_LT(r.after.angular_velocity_b_si.norm(), 1e-8);
}

TEST(DryImpact, ElasticImpactsOfTiltedBodiesConserveEnergy) {
  // With e = 1 the contact force is the gradient of k delta(pose)^2 / 2 (force and torque): a
  // wrong contact point or torque arm would create or destroy energy.
  std::vector<std::pair<const char*, std::shared_ptr<const Shape>>> shapes = {
      {"spheroid", std::make_shared<Ellipsoid>(Eigen::Vector3d(0.25, 0.25, 0.75), "spheroid")},
      {"cuboid", std::make_shared<Cuboid>(Eigen::Vector3d(1.0, 0.6, 0.3))},
      {"cylinder", std::make_shared<Cylinder>(0.5, 1.2)},
      {"superellipsoid", std::make_shared<Superellipsoid>(Eigen::Vector3d(0.3, 0.5, 0.7), 0.6, 0.9)},
      {"mesh", std::make_shared<MeshShape>(testing::box_mesh(Eigen::Vector3d(0.4, 0.8, 1.0)), "box")}};
  for (const auto& [name, shape] : shapes) {
    const auto drift_with = [&, name = name, &shape = shape](int substeps) {
      Rig rig = sphere_rig(1.0);
      rig.shape = shape;
      rig.mass = shape->mass_properties(1500.0);
      rig.parameters.substeps_per_collision = substeps;
      const WallContact contact(rig.shape, {rig.floor}, rig.parameters);
      const Eigen::Matrix3d rotation = rotation_about({1.0, 0.4, -0.3}, 0.5);
      const double v = 0.2, dt = rig.parameters.collision_time_si / 10.0;
      const double lowest = shape->support(rotation.transpose() * (-Eigen::Vector3d::UnitZ()));
      const Eigen::Vector3d start(0.0, 0.0, lowest + rig.parameters.contact_distance_si + 0.1 * v * dt);
      const Impact r = bounce(body_at(rig, start, {0.05, 0.0, -v}, rotation, {0.5, -1.0, 0.2}), contact, dt);
      EXPECT_GT(r.after.angular_velocity_b_si.norm(), 0.5) << name;  // an off-centre impact: the spin changed
      return std::abs(r.energy_after - r.energy_before) / r.energy_before;
    };
    const double drift = drift_with(100), drift_fine = drift_with(800);
    std::printf(
        "[measured] elastic tilted %s impact: relative energy change %.2e (100 substeps per collision), "
        "%.2e (800)\n",
        name, drift, drift_fine);
    // The integration error: second order in the substep where the force is smooth, first order
    // across the kinks (entry, exit, a faceted body's touching corner changing). With the default
    // N = 100 it stays below 1e-3. It must vanish as the substep shrinks: a wrong contact point or
    // torque arm would leave a drift that does not (8x smaller substeps: at least first order).
    EXPECT_LT(drift, 1e-3) << name;
    EXPECT_LT(drift_fine, std::max(drift / 8.0, 1e-8)) << name;
  }
}

TEST(RestingContact, BodyUnderItsWeightSettlesAtTheStaticCompression) {
  // Gravity in vacuum onto the floor: it must come to rest at g = zeta_c - m g / k.
  const Rig rig = sphere_rig(0.3);
  WallContact contact(rig.shape, {rig.floor}, rig.parameters);
  const Environment environment{0.0, {0.0, 0.0, -9.81}};
  const double dt = rig.parameters.collision_time_si / 10.0, zeta = rig.parameters.contact_distance_si;
  RigidBody body = body_at(rig, {0.0, 0.0, 0.5 + zeta + 1e-3}, Eigen::Vector3d::Zero(), Eigen::Matrix3d::Identity(),
                           Eigen::Vector3d::Zero(), environment);
  double min_gap = 1.0;
  for (int step = 0; step < 2000; ++step) min_gap = std::min(min_gap, contact.advance(body, dt, Wrench{}).min_gap_si);
  const SpringDashpot law = spring_dashpot(rig.mass.mass, rig.mass.mass, rig.parameters);
  const double weight = rig.mass.mass * 9.81;
  const double rest_gap = zeta - weight / law.stiffness;
  const double gap = contact.min_gap_si(body.state());
  std::printf("[measured] resting sphere: gap %.6e m vs zeta - mg/k %.6e m, speed %.2e m/s\n", gap, rest_gap,
              body.state().velocity_si.norm());
  ASSERT_TRUE(std::isfinite(gap));
  // 2000 steps = 200 T_c; the damping ratio for e = 0.3 is 0.36, so the oscillation has decayed
  // by exp(-0.36 pi 200 / 1.07) ~ 1e-90: only round-off of the balance is left.
  EXPECT_NEAR(gap, rest_gap, 1e-9 * zeta);
  EXPECT_LT(body.state().velocity_si.norm(), 1e-9);
  // Dropped from 1 mm above the contact distance: overlap bounded by the stated bound.
  const double impact_speed = std::sqrt(2.0 * 9.81 * 1e-3);
  EXPECT_LE(zeta - min_gap, max_overlap_bound(weight, impact_speed, law.stiffness, rig.parameters.collision_time_si));
}

TEST(WallContactAdvance, AwayFromTheWallsItIsThePlainCorrector) {
  const Rig rig = sphere_rig(0.5);
  WallContact contact(rig.shape, {rig.floor}, rig.parameters);
  const Environment environment{1000.0, {0.0, 0.0, -9.81}};
  const Wrench external{{0.1, -0.2, 3.0}, {0.01, 0.02, -0.03}};
  RigidBody a =
      body_at(rig, {0.0, 0.0, 2.0}, {0.0, 0.0, -0.1}, rotation_about({1, 1, 0}, 0.3), {0.1, 0.2, 0.3}, environment);
  RigidBody b = a;
  const ContactStep s = contact.advance(a, 1e-3, external);
  b.correct(1e-3, external);
  EXPECT_EQ(s.substeps, 1);
  EXPECT_FALSE(s.touching);
  EXPECT_EQ(a.state().position_si, b.state().position_si);  // bit for bit: the same call
  EXPECT_EQ(a.state().angular_velocity_b_si, b.state().angular_velocity_b_si);
  EXPECT_NEAR(s.min_gap_si, contact.min_gap_si(a.state()), 0.0);
}

TEST(WallContactAdvance, RejectsInvalidParameters) {
  const Rig rig = sphere_rig(0.5);
  auto with = [&](auto change) {
    ContactParameters p = rig.parameters;
    change(p);
    return p;
  };
  EXPECT_THROW(WallContact(nullptr, {}, rig.parameters), std::invalid_argument);
  EXPECT_THROW(WallContact(rig.shape, {{Eigen::Vector3d(0, 0, 2), 0.0}}, rig.parameters), std::invalid_argument);
  EXPECT_THROW(WallContact(rig.shape, {}, with([](auto& p) { p.restitution = 0.0; })), std::invalid_argument);
  EXPECT_THROW(WallContact(rig.shape, {}, with([](auto& p) { p.restitution = 1.1; })), std::invalid_argument);
  EXPECT_THROW(WallContact(rig.shape, {}, with([](auto& p) { p.collision_time_si = 0.0; })), std::invalid_argument);
  EXPECT_THROW(WallContact(rig.shape, {}, with([](auto& p) { p.contact_distance_si = -1e-3; })), std::invalid_argument);
  EXPECT_THROW(WallContact(rig.shape, {}, with([](auto& p) { p.substeps_per_collision = 0; })), std::invalid_argument);
  EXPECT_THROW(WallContact(rig.shape, {}, with([](auto& p) { p.wet_stokes_scale = -1.0; })), std::invalid_argument);
  EXPECT_THROW(WallContact(rig.shape, {}, with([](auto& p) { p.wet_stokes_scale = 35.0; })),  // no viscosity
               std::invalid_argument);
  WallContact contact(rig.shape, {rig.floor}, rig.parameters);
  EXPECT_THROW(contact.restore_impact_speeds({}), std::invalid_argument);  // one entry per wall
}

// ---------------------------------------------------------------------------------------------
// Wet impacts: the restitution e_dry exp(-beta / St) of Legendre et al. 2006, fixed at impact.

TEST(WetImpact, RestitutionFollowsTheImpactStokesNumber) {
  // Closed form: St = rho_p v d / (9 mu); e = e_dry exp(-35 / St), floored at 1e-3 e_dry.
  ContactParameters p;
  p.restitution = 0.9;
  p.wet_stokes_scale = 35.0;
  EXPECT_NEAR(impact_stokes_number(7800.0, -0.5, 2e-3, 1e-3), 7800.0 * 0.5 * 2e-3 / 9e-3, 1e-12);
  EXPECT_NEAR(contact_restitution(p, 35.0 / std::log(2.0)), 0.45, 1e-15);
  EXPECT_NEAR(contact_restitution(p, 1e9), 0.9, 1e-7);
  EXPECT_EQ(contact_restitution(p, 1.0), 0.9 * kMinimumWetRestitutionRatio);  // exp(-35) is below the floor
  EXPECT_EQ(contact_restitution(p, 0.0), 0.9 * kMinimumWetRestitutionRatio);  // arriving at rest
  p.wet_stokes_scale = 0.0;
  EXPECT_EQ(contact_restitution(p, 1.0), 0.9);  // dry
}

TEST(WetImpact, SphereReboundsWithTheRestitutionOfItsImpactSpeed) {
  // The rig's sphere (d = 1 m, 1000 kg/m^3) at v = 0.2 m/s in a liquid of viscosity mu: St = 200 /
  // (9 mu). Each mu below sets St, hence e, and the rebound must have that e although the normal
  // speed falls to zero during the contact: the restitution is fixed when the contact begins.
  const double v = 0.2, e_dry = 0.9;
  for (double stokes : {35.0 / std::log(2.0), 35.0 / std::log(10.0), 500.0, 2.0}) {
    Rig rig = sphere_rig(e_dry);
    rig.parameters.wet_stokes_scale = 35.0;
    rig.parameters.fluid_dynamic_viscosity_si = 1000.0 * v * 1.0 / (9.0 * stokes);
    const WallContact contact(rig.shape, {rig.floor}, rig.parameters);
    const double e = contact_restitution(rig.parameters, stokes);
    const double t_c = rig.parameters.collision_time_si, dt = t_c / 10.0;
    const double zeta = rig.parameters.contact_distance_si;
    const Impact r = bounce(body_at(rig, {0.0, 0.0, 0.5 + zeta + 0.3 * v * dt}, {0.0, 0.0, -v}), contact, dt);
    std::printf(
        "[measured] wet sphere impact St = %.1f: e = %.6f, rebound ratio %.6f, contact %.2f T_c, max overlap "
        "%.3f v T_c / pi\n",
        stokes, e, r.rebound_ratio, r.contact_time / t_c, r.max_overlap / (v * t_c / std::numbers::pi));
    // The dry test's bound for the dashpot switching on and off inside a substep, |ln e| (1 + e) / N,
    // plus 1e-4 (DryImpact above); at the floor (St = 2) it is 7% of the impact speed.
    EXPECT_NEAR(r.rebound_ratio, e, std::abs(std::log(e)) * (1.0 + e) / rig.parameters.substeps_per_collision + 1e-4);
    // The contact lasts the damped half period with the dry k, T_c sqrt((pi^2 + ln^2 e) / (pi^2 +
    // ln^2 e_dry)) (contact.hpp), in whole fluid steps: within one step at each end.
    const double pi2 = std::numbers::pi * std::numbers::pi;
    const double duration = t_c * std::sqrt((pi2 + std::pow(std::log(e), 2)) / (pi2 + std::pow(std::log(e_dry), 2)));
    EXPECT_NEAR(r.contact_time, duration, 2.0 * dt + 1e-12);
    // The overlap stays below the undamped amplitude v T_c / pi.
    EXPECT_LE(r.max_overlap, v * t_c / std::numbers::pi);
  }
}

TEST(WetImpact, ARestingBodyKeepsItsContactAndLeavingEndsIt) {
  Rig rig = sphere_rig(0.9);
  rig.parameters.wet_stokes_scale = 35.0;
  rig.parameters.fluid_dynamic_viscosity_si = 1.0;
  WallContact contact(rig.shape, {rig.floor}, rig.parameters);
  const double zeta = rig.parameters.contact_distance_si, dt = rig.parameters.collision_time_si / 10.0;
  RigidBody body = body_at(rig, {0.0, 0.0, 0.5 + zeta + 0.5e-4}, {0.0, 0.0, -0.1});  // enters mid-step
  EXPECT_FALSE(contact.impact_speeds_si()[0].has_value());
  contact.advance(body, dt, Wrench{});
  ASSERT_TRUE(contact.impact_speeds_si()[0].has_value());
  // Recorded at the first midpoint inside zeta_c, before any contact force acted: the approach speed
  // (no other force here), to round-off.
  EXPECT_NEAR(*contact.impact_speeds_si()[0], 0.1, 1e-15);
  // Restored as saved, whatever it was.
  contact.restore_impact_speeds({0.05});
  EXPECT_EQ(*contact.impact_speeds_si()[0], 0.05);
  // Lifted away from the wall: the record ends.
  RigidBody away = body_at(rig, {0.0, 0.0, 2.0}, Eigen::Vector3d::Zero());
  contact.advance(away, dt, Wrench{});
  EXPECT_FALSE(contact.impact_speeds_si()[0].has_value());
}

}  // namespace test_contact
}  // namespace settle::body
