// A following window along a periodic axis (docs/user-guide.md, domain.follow_particle): a periodic
// axis is a ring, so the window does not shift along it and the body crosses the wrap instead. A
// shift there would drop the layer the body leaves and refill the opposite face with fluid at rest,
// a seam across which the fluid wraps; the checks below would see it.
//
// An immersed-boundary sphere (d = 6 cells) towed along +x at 0.04 lattice units through a box
// periodic on every axis, 10 cells of travel: the forcing adds momentum but no mass, and the
// populations are stored in double, so the fluid's mass is conserved to round-off. Each refilled
// layer changes it by the layer's density deviation: shifting along x as along a wall axis (as
// settle did before 2026-12-02), the nine shifts of this tow took 1.67 of the 6144 cells' mass
// (2.7e-4), the layer just ahead of the body leaving at a density of about 1 + 7e-4.
#include <algorithm>
#include <cmath>
#include <memory>

#include <gtest/gtest.h>

#include "body/shape_factory.hpp"
#include "coupling/simulation.hpp"
#include "support/default_setup.hpp"

namespace test_periodic_window {

using namespace settle;
using namespace settle::coupling;

constexpr double kDiameter = 6.0;   // cells = metres (dx = dt = 1)
constexpr double kTowSpeed = 0.04;  // lattice units
constexpr int kSteps = 250;         // 10 cells of travel

SimulationSetup towed_across_a_ring(bool follow) {
  SimulationSetup s = settle::test::default_setup();
  body::ShapeSpec spec;
  spec.shape = "sphere";
  spec.diameter = kDiameter;
  s.shape = std::shared_ptr<const body::Shape>(body::make_shape(spec));
  s.motion = body::MotionKind::towed;
  s.coupling = CouplingKind::immersed_boundary;
  s.particle_density_si = 2.0;
  s.fluid_density_si = 1.0;
  s.dynamic_viscosity_si = 0.04;  // Re = U d / nu = 6
  s.gravity_si = Eigen::Vector3d::Zero();
  s.domain_size_si = Eigen::Vector3d(24.0, 16.0, 16.0);
  s.boundaries = {lbm::Boundary::periodic, lbm::Boundary::periodic, lbm::Boundary::periodic};
  s.follow_particle = follow;
  s.precision = lbm::Precision::float64;
  s.cells_per_diameter = kDiameter;
  s.tau = 0.5 + 3.0 * 0.04;
  s.max_lattice_velocity = kTowSpeed * 1.01;
  // Off the cell centres, so the body crosses cell faces at generic fractions; it reaches the wrap
  // at x = 24 after 6 cells of travel.
  s.initial.position_si = Eigen::Vector3d(18.3, 8.2, 7.9);
  s.initial.velocity_si = Eigen::Vector3d(kTowSpeed, 0.0, 0.0);
  s.end_time_si = kSteps;
  return s;
}

TEST(PeriodicWindow, AFollowingWindowKeepsTheFluidsMassOnAPeriodicAxis) {
  Simulation sim(towed_across_a_ring(true));
  const double mass_before = sim.fluid().total_mass();
  for (int n = 0; n < kSteps; ++n) sim.step();
  // Round-off of summing 6144 cells of O(1) each step, 250 steps: well below 1e-12 relative,
  // seven orders below the 3e-5 that one refilled layer moved.
  EXPECT_NEAR(sim.fluid().total_mass(), mass_before, 1e-12 * mass_before);
  // The body crossed the wrap and the window stayed: 10 cells along x from 18.3.
  EXPECT_NEAR(sim.body().state().position_si.x(), 18.3 + kSteps * kTowSpeed, 1e-9);
  EXPECT_EQ(sim.frame().window_origin_si.x(), 0.0);
}

TEST(PeriodicWindow, FollowingAlongARingIsNotFollowing) {
  // The same tow with the window fixed: the same force, step for step, to the bit.
  Simulation following(towed_across_a_ring(true)), fixed(towed_across_a_ring(false));
  for (int n = 0; n < kSteps; ++n) {
    following.step();
    fixed.step();
    ASSERT_EQ(following.last_step().hydrodynamic.force_si, fixed.last_step().hydrodynamic.force_si) << "step " << n;
  }
}

// A momentum-exchange sphere that turns as it moves (towed along -z at 0.02 and turning about z at
// 0.0025 rad per step, its surface at 0.01) while it straddles the wrap at x = 0, the cells it
// uncovers on its upper half on both sides of it; the same tow 16 cells further along x (the same
// sub-cell geometry) lies clear of the wrap. A periodic lattice has no place of its own, so the two
// feel the same force and torque, step by step. Until 2026-12-02 they did not: the cells uncovered
// across the wrap were refilled with the body's velocity at their wrapped place, a lever arm of a
// whole lattice (32 cells instead of at most 4), and the force jumped when a free sphere crossed
// the wrap (Uhlmann and Dusek's case C with periodic sides, docs/notes.md). Populations in double:
// the two differ only in the order of the covered cells' torque sum.
SimulationSetup momentum_exchange_turning_tow(double centre_x) {
  SimulationSetup s = settle::test::default_setup();
  body::ShapeSpec spec;
  spec.shape = "sphere";
  spec.diameter = 8.0;
  s.shape = std::shared_ptr<const body::Shape>(body::make_shape(spec));
  s.motion = body::MotionKind::towed;
  s.coupling = CouplingKind::momentum_exchange;
  s.particle_density_si = 2.0;
  s.fluid_density_si = 1.0;
  s.dynamic_viscosity_si = 0.02;  // Re = U d / nu = 8
  s.gravity_si = Eigen::Vector3d::Zero();
  s.domain_size_si = Eigen::Vector3d(32.0, 24.0, 24.0);
  s.boundaries = {lbm::Boundary::periodic, lbm::Boundary::periodic, lbm::Boundary::periodic};
  s.precision = lbm::Precision::float64;
  s.cells_per_diameter = 8.0;
  s.tau = 0.5 + 3.0 * 0.02;
  s.max_lattice_velocity = 0.04;
  s.initial.position_si = Eigen::Vector3d(centre_x, 12.2, 11.9);
  s.initial.velocity_si = Eigen::Vector3d(0.0, 0.0, -0.02);
  s.initial.angular_velocity_b_si = Eigen::Vector3d(0.0, 0.0, 0.0025);
  s.end_time_si = 200.0;
  return s;
}

TEST(PeriodicWindow, AMomentumExchangeBodyFeelsTheSameForceAcrossTheWrapAsAwayFromIt) {
  Simulation across(momentum_exchange_turning_tow(1.3)), away(momentum_exchange_turning_tow(17.3));
  double largest_force = 0.0, largest_torque = 0.0;
  for (int n = 0; n < 200; ++n) {
    across.step();
    away.step();
    const body::Wrench& a = across.last_step().hydrodynamic;
    const body::Wrench& b = away.last_step().hydrodynamic;
    largest_force = std::max(largest_force, b.force_si.norm());
    largest_torque = std::max(largest_torque, b.torque_si.norm());
    // Round-off of sums of some hundred terms: 1e-10 of the largest force and torque so far
    // leaves five orders of room and catches any refill with a wrong velocity.
    ASSERT_LE((a.force_si - b.force_si).norm(), 1e-10 * largest_force) << "step " << n;
    ASSERT_LE((a.torque_si - b.torque_si).norm(), 1e-10 * largest_torque) << "step " << n;
  }
}

}  // namespace test_periodic_window
