// A particle settling onto the bottom wall of a small closed box comes to rest on the
// particle-wall contact (body/contact.hpp) wired into the coupled step (coupling/simulation.hpp):
// no NaN, no overlap beyond the model's bound, the speed decays to ~0 and the body rests at the
// contact model's static height. A sphere, and a spheroid released tilted that lands on its tip.
//
// The case: a glass-like particle (2500 kg/m^3) of 0.5 mm in water, Galileo number ~43 (terminal
// Reynolds number ~25), 8 cells per diameter, a 3 x 3 x 4 diameter box with no-slip walls.
#include <algorithm>
#include <cmath>
#include <cstdio>
#include <memory>
#include <numbers>
#include <string>

#include <omp.h>

#include <gtest/gtest.h>
#include <Eigen/Geometry>

#include "body/shape_factory.hpp"
#include "common/error.hpp"
#include "coupling/simulation.hpp"
#include "support/default_setup.hpp"

namespace test_wall_contact {

using namespace settle;
using namespace settle::coupling;

constexpr double kDiameter = 0.5e-3;

std::shared_ptr<const body::Shape> make(const char* name, double aspect_ratio = 1.0) {
  body::ShapeSpec spec;
  spec.shape = name;
  spec.diameter = kDiameter;
  if (aspect_ratio != 1.0) spec.aspect_ratio = aspect_ratio;
  return body::make_shape(spec);
}

SimulationSetup settling_box(std::shared_ptr<const body::Shape> shape, const Eigen::Matrix3d& attitude,
                             double start_height) {
  SimulationSetup s = settle::test::default_setup();
  s.shape = std::move(shape);
  s.particle_density_si = 2500.0;
  s.fluid_density_si = 1000.0;
  s.dynamic_viscosity_si = 1.0e-3;
  s.gravity_si = {0.0, 0.0, -9.81};
  const double d = s.shape->equivalent_diameter();
  s.domain_size_si = Eigen::Vector3d(3.0 * d, 3.0 * d, 4.0 * d);
  s.boundaries = {lbm::Boundary::no_slip, lbm::Boundary::no_slip, lbm::Boundary::no_slip};
  s.cells_per_diameter = 8.0;
  s.initial.position_si = Eigen::Vector3d(1.5 * d, 1.5 * d, start_height);
  s.initial.attitude = attitude::Attitude::from_matrix(attitude);
  s.end_time_si = 1.0;
  return s;
}

struct Settling {
  bool finite = true;
  bool stopped_at_boundary = false;
  double min_gap_si = 1.0;         ///< smallest wall gap over the run
  double max_speed_si = 0.0;       ///< largest |v| + |omega| R_bounding over the run (bounds the impact speed)
  double max_load_si = 0.0;        ///< largest downward non-contact force (net weight + hydrodynamic)
  double late_max_speed_si = 0.0;  ///< largest |v| + |omega| R_bounding over the last quarter of the run
  double late_max_vertical_speed_si = 0.0;
  double late_mean_contact_force_si = 0.0;  ///< mean vertical contact force over the last quarter
  double final_gap_si = 0.0;
  Eigen::Vector3d final_position_si = Eigen::Vector3d::Zero();
  std::int64_t steps = 0;
};

Settling settle_for(Simulation& sim, std::int64_t steps) {
  // One thread: the grid is small, and the CI machine's two cores run other tests at the same time.
  omp_set_num_threads(1);
  Settling r;
  const double net_weight_down = -sim.body().net_weight_si().z();
  const double radius = sim.setup().shape->bounding_radius();
  const std::int64_t late = steps - steps / 4;
  for (std::int64_t n = 0; n < steps; ++n) {
    if (!sim.can_step()) {
      r.stopped_at_boundary = true;
      break;
    }
    sim.step();
    const auto& s = sim.body().state();
    const auto& obs = sim.last_step();
    if (!s.position_si.allFinite() || !s.velocity_si.allFinite() || !s.angular_velocity_b_si.allFinite() ||
        !obs.hydrodynamic.force_si.allFinite() || !obs.contact.force_si.allFinite()) {
      r.finite = false;
      break;
    }
    const double speed = s.velocity_si.norm() + s.angular_velocity_b_si.norm() * radius;
    r.min_gap_si = std::min(r.min_gap_si, obs.wall_gap_si);
    r.max_speed_si = std::max(r.max_speed_si, speed);
    r.max_load_si = std::max(r.max_load_si, net_weight_down - obs.hydrodynamic.force_si.z());
    if (n >= late) {
      r.late_max_speed_si = std::max(r.late_max_speed_si, speed);
      r.late_max_vertical_speed_si = std::max(r.late_max_vertical_speed_si, std::abs(s.velocity_si.z()));
      r.late_mean_contact_force_si += obs.contact.force_si.z() / static_cast<double>(steps - late);
    }
    r.steps = n + 1;
  }
  r.final_gap_si = sim.wall_contact()->min_gap_si(sim.body().state());
  r.final_position_si = sim.body().state().position_si;
  return r;
}

/// The contact model's numbers for this simulation.
struct ContactNumbers {
  double dx_si, zeta_si, stiffness_si, collision_time_si, net_weight_si;
  double rest_gap_si() const { return zeta_si - net_weight_si / stiffness_si; }
};

ContactNumbers contact_numbers(const Simulation& sim) {
  const body::WallContact& contact = *sim.wall_contact();
  const double mass = sim.body().mass_properties().mass;
  return {sim.units().dx_si(), contact.parameters().contact_distance_si,
          body::spring_dashpot(mass, mass, contact.parameters()).stiffness, contact.parameters().collision_time_si,
          -sim.body().net_weight_si().z()};
}

/// The checks both bodies share: comes to rest, no overlap beyond the model's bound, no NaN.
void expect_resting_on_the_floor(const Settling& r, const ContactNumbers& c) {
  ASSERT_TRUE(r.finite);
  // The body's forcing stencils stayed inside the grid all along (Simulation::can_step).
  ASSERT_FALSE(r.stopped_at_boundary);
  // No overlap beyond the model's bound (body/contact.hpp): 2 L / k + v T_c / pi for the largest
  // load L (net weight plus the fluid's push, which the added mass makes large while the body
  // stops) and the largest speed seen. And no physical overlap at all: the gap stays positive.
  const double bound = body::max_overlap_bound(r.max_load_si, r.max_speed_si, c.stiffness_si, c.collision_time_si);
  EXPECT_LE(c.zeta_si - r.min_gap_si, bound);
  EXPECT_GT(r.min_gap_si, 0.0);
  // At rest on the spring: the gap is the model's static one, zeta - W / k. The fluid left in motion
  // pushes by a few per cent of W at most (below), which moves the rest point by ~1e-4 dx; 0.01 dx
  // separates resting on the spring from hovering on the fluid or sinking into the wall.
  EXPECT_NEAR(r.final_gap_si, c.rest_gap_si(), 0.01 * c.dx_si);
  // The contact carries the net weight: at rest the fluid's force is only what is left of the
  // impact's pressure waves in the closed box (a few per cent, decaying).
  EXPECT_NEAR(r.late_mean_contact_force_si / c.net_weight_si, 1.0, 0.05);
  // The vertical motion has stopped: below 1e-3 of the largest speed over the last quarter.
  EXPECT_LT(r.late_max_vertical_speed_si, 1e-3 * r.max_speed_si);
}

void print(const char* name, const Settling& r, const ContactNumbers& c) {
  std::printf(
      "[measured] %s: %lld steps, min gap %.4f dx (zeta %.2f dx, overlap %.4f dx, bound %.4f dx), final gap "
      "%.6f dx (zeta - W/k %.6f dx), last quarter: mean contact force / W %.4f, max speed / run max %.2e, max "
      "vertical speed / run max %.2e\n",
      name, static_cast<long long>(r.steps), r.min_gap_si / c.dx_si, c.zeta_si / c.dx_si,
      (c.zeta_si - r.min_gap_si) / c.dx_si,
      body::max_overlap_bound(r.max_load_si, r.max_speed_si, c.stiffness_si, c.collision_time_si) / c.dx_si,
      r.final_gap_si / c.dx_si, c.rest_gap_si() / c.dx_si, r.late_mean_contact_force_si / c.net_weight_si,
      r.late_max_speed_si / r.max_speed_si, r.late_max_vertical_speed_si / r.max_speed_si);
}

TEST(WallContact, SphereSettlesOntoTheBottomAndComesToRest) {
  const double d = kDiameter;
  Simulation sim(settling_box(make("sphere"), Eigen::Matrix3d::Identity(), 1.5 * d));
  ASSERT_TRUE(sim.wall_contact().has_value());
  const ContactNumbers c = contact_numbers(sim);
  const Settling r = settle_for(sim, 2500);
  print("sphere", r, c);
  expect_resting_on_the_floor(r, c);
  // The sphere rests at height d/2 + gap, straight below where it started (by symmetry).
  EXPECT_NEAR(r.final_position_si.z(), 0.5 * d + c.rest_gap_si(), 0.01 * c.dx_si);
  EXPECT_NEAR(r.final_position_si.x(), 1.5 * d, 0.01 * c.dx_si);
  EXPECT_NEAR(r.final_position_si.y(), 1.5 * d, 0.01 * c.dx_si);
  // Nothing moves any more, rotation included.
  EXPECT_LT(r.late_max_speed_si, 1e-3 * r.max_speed_si);
}

TEST(WallContact, TiltedSpheroidLandsOnItsTipAndComesToRest) {
  // A prolate spheroid (aspect ratio 2) released with its axis 45 degrees from the vertical: it
  // lands on its tip, tips over and must come to rest lying flat.
  const Eigen::Matrix3d tilt = Eigen::AngleAxisd(std::numbers::pi / 4.0, Eigen::Vector3d::UnitX()).toRotationMatrix();
  const auto shape = make("spheroid", 2.0);
  const double d = shape->equivalent_diameter();
  Simulation sim(settling_box(shape, tilt, 1.6 * d));
  const ContactNumbers c = contact_numbers(sim);
  // 6000 steps: the wet contact (the default, body/contact.hpp) takes the bounce out of the tip's
  // landing, so the fluid alone sets how fast the body tips over; at 3000 steps it was still
  // tipping (axis 6e-3 rad off the floor), where the dry contact's bounces had laid it down sooner.
  const Settling r = settle_for(sim, 6000);
  print("spheroid", r, c);
  expect_resting_on_the_floor(r, c);
  const Eigen::Vector3d axis = sim.body().body_to_inertial().col(2);
  std::printf("[measured] spheroid: axis tilt from the floor %.2e rad\n", std::asin(std::abs(axis.z())));
  // Lying flat (the stable rest of a prolate spheroid): its axis within 0.01 rad of the floor.
  EXPECT_LT(std::abs(axis.z()), 0.01);
  // Rolling about its own axis is neutral for a frictionless spheroid on a plane (the height does
  // not change), so only the fluid slows it: measured e-folding ~600 steps here. Over the last
  // quarter the motion must be a small fraction of the landing's.
  EXPECT_LT(r.late_max_speed_si, 0.1 * r.max_speed_si);
}

TEST(WallContact, WiredOnlyWhereABodyCanReachAWall) {
  const double d = kDiameter;
  SimulationSetup setup = settling_box(make("sphere"), Eigen::Matrix3d::Identity(), 1.5 * d);
  setup.boundaries = {lbm::Boundary::periodic, lbm::Boundary::periodic, lbm::Boundary::free_slip};
  {
    const Simulation sim(setup);
    ASSERT_TRUE(sim.wall_contact().has_value());
    EXPECT_EQ(sim.wall_contact()->walls().size(), 2u);  // the free-slip floor and ceiling only
    // Walls at the grid's faces, where the half-way bounce-back puts them: z = 0 and z = cells dx.
    EXPECT_EQ(sim.wall_contact()->walls()[0].offset_si, 0.0);
    EXPECT_NEAR(-sim.wall_contact()->walls()[1].offset_si, sim.derived().cells[2] * sim.units().dx_si(), 1e-18);
    // Default contact distance: the reach of the momentum exchange's links, one cell
    // (coupling_reach_cells); the immersed boundary's is its kernel's half-width.
    EXPECT_NEAR(sim.wall_contact()->parameters().contact_distance_si, 1.0 * sim.units().dx_si(), 1e-18);
    SimulationSetup immersed = setup;
    immersed.coupling = CouplingKind::immersed_boundary;
    EXPECT_NEAR(Simulation(immersed).wall_contact()->parameters().contact_distance_si, 1.5 * sim.units().dx_si(),
                1e-18);
  }
  setup.follow_particle = true;
  EXPECT_FALSE(Simulation(setup).wall_contact().has_value());  // the window keeps the body off the faces
  setup.follow_particle = false;
  setup.motion = body::MotionKind::fixed;
  EXPECT_FALSE(Simulation(setup).wall_contact().has_value());
  setup.motion = body::MotionKind::free;
  setup.wall_contact = false;
  EXPECT_FALSE(Simulation(setup).wall_contact().has_value());
}

TEST(WallContact, RefusesParametersAndStartsThatCannotWork) {
  const double d = kDiameter;
  const SimulationSetup base = settling_box(make("sphere"), Eigen::Matrix3d::Identity(), 1.5 * d);
  const auto refused = [&](auto change, const char* key) {
    SimulationSetup s = base;
    change(s);
    try {
      Simulation sim(s);
      ADD_FAILURE() << "accepted; expected an error naming " << key;
    } catch (const InputError& e) {
      EXPECT_NE(std::string(e.what()).find(key), std::string::npos) << e.what();
    }
  };
  // The ranges of contact.restitution and contact.collision_steps are the case schema's, checked
  // when a case is read (tests/io/test_schema.cpp); here the rules that depend on the coupling.
  // Below reach - 1/2 (coupling_reach_cells) a resting body's links would leave the grid: half a
  // cell for the momentum exchange, 1 cell for the immersed boundary's roma3 stencils.
  refused([](SimulationSetup& s) { s.contact_distance_cells = 0.4; }, "contact.distance_cells");
  refused(
      [](SimulationSetup& s) {
        s.coupling = CouplingKind::immersed_boundary;
        s.contact_distance_cells = 0.9;
      },
      "contact.distance_cells");
  // Starting 0.8 cells above the floor, inside the 1-cell contact distance.
  const double dx = d / base.cells_per_diameter;
  refused([&](SimulationSetup& s) { s.initial.position_si.z() = 0.5 * d + 0.8 * dx; }, "particle.position");
  // Resting on the floor at the static gap is a valid start.
  SimulationSetup resting = base;
  resting.initial.position_si.z() = 0.5 * d + 1.0 * dx - 1e-3 * dx;
  EXPECT_NO_THROW(Simulation{resting});
}

}  // namespace test_wall_contact
