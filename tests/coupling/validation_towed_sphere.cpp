// Validation (label `validation`): drag of a sphere towed through fluid at rest at Re = 20, 50,
// 100 and 300 against the standard drag curve (towed_sphere.hpp), and its grid convergence at
// Re = 20.
// Environment: SETTLE_TOWED_CELLS (cells per diameter, default 16), SETTLE_TOWED_COUPLING,
// SETTLE_TOWED_WALL_RULE (the momentum exchange's numerics.wall_rule, default bouzidi),
// SETTLE_TOWED_COLLISION (numerics.collision, default trt), SETTLE_TOWED_RAMP (the towing speed
// ramped up from rest over this many diameters of travel, default 0: an impulsive start).
#include <cmath>
#include <cstdio>
#include <cstdlib>

#include <gtest/gtest.h>

#include "towed_sphere.hpp"

namespace {

using namespace settle::coupling::testing;

double resolution_from_environment(double fallback) {
  const char* value = std::getenv("SETTLE_TOWED_CELLS");
  return value ? std::atof(value) : fallback;
}

// SETTLE_TOWED_COUPLING: momentum_exchange (default, as in a case) or immersed_boundary.
settle::coupling::CouplingKind coupling_from_environment() {
  const char* value = std::getenv("SETTLE_TOWED_COUPLING");
  return value ? settle::coupling::parse_coupling(value, "SETTLE_TOWED_COUPLING") : settle::coupling::kDefaultCoupling;
}

settle::lbm::CollisionKind collision_from_environment() {
  const char* value = std::getenv("SETTLE_TOWED_COLLISION");
  return value ? settle::lbm::parse_collision(value, "SETTLE_TOWED_COLLISION") : settle::lbm::CollisionKind::trt;
}

double ramp_from_environment() {
  const char* value = std::getenv("SETTLE_TOWED_RAMP");
  return value ? std::atof(value) : 0.0;
}

settle::lbm::WallRule wall_rule_from_environment() {
  const char* value = std::getenv("SETTLE_TOWED_WALL_RULE");
  return value ? settle::lbm::parse_wall_rule(value, "SETTLE_TOWED_WALL_RULE") : settle::lbm::kDefaultWallRule;
}

void check(double reynolds, double travel_diameters) {
  TowedSphereOptions o;
  o.reynolds = reynolds;
  o.travel_diameters = travel_diameters;
  o.cells_per_diameter = resolution_from_environment(16.0);
  o.coupling = coupling_from_environment();
  o.wall_rule = wall_rule_from_environment();
  o.collision = collision_from_environment();
  o.ramp_diameters = ramp_from_environment();
  const TowedSphereResult r = run_towed_sphere_printed(o);
  // Start-up transient over: the mean drag of the last fifth of the travel differs from the fifth
  // before by less than a tenth of the 3% budget.
  EXPECT_NEAR(r.drag_coefficient, r.previous_fifth, 0.003 * r.drag_coefficient);
  // Issue 20's criterion at 16 cells: within 3% of the standard drag curve (Clift et al. 1978 fit
  // the measurements to a few percent themselves).
  EXPECT_NEAR(r.drag_coefficient, r.reference, 0.03 * r.reference);
  // An axisymmetric steady wake (Re < 210) exerts no lateral force.
  EXPECT_LT(r.lateral_ratio, 1e-3);
}

// The start-up transient is longest at the lowest Re (viscous diffusion of the wake): 30 diameters
// of travel there, 20 at Re = 50 and 100; the drift check below confirms each.
TEST(TowedSphereValidation, Re20) { check(20.0, 30.0); }
TEST(TowedSphereValidation, Re50) { check(50.0, 20.0); }
TEST(TowedSphereValidation, Re100) { check(100.0, 20.0); }

// Above Re of about 210 a sphere's wake turns oblique, above about 275 it sheds (Johnson and Patel
// 1999, J. Fluid Mech. 378, 19): the sphere starts 0.3 and 0.2 cells off the window's axis to seed
// the symmetry breaking, as cases/fixed_sphere_stream.toml does, and travels 40 diameters (the
// fixed sphere's lift took 20-30 d/U to grow, docs/validation.md). The default operator (TRT) at
// tau 0.506 (16 cells) runs the impulsive start. Criteria of the issue for Re = 300: C_D within
// 3% of the standard curve at 16 cells; and the wake must break its symmetry: a lateral force above
// 1% of the drag (Johnson and Patel's C_L / C_D at Re = 300 is 0.069 / 0.656 = 0.11; an
// axisymmetric wake gives at most 1e-7 of the drag: 1e-14 with the linear wall rule and 6e-8 with
// the quadratic one at Re = 100, docs/validation.md).
TEST(TowedSphereValidation, Re300) {
  TowedSphereOptions o;
  o.reynolds = 300.0;
  o.travel_diameters = 40.0;
  o.cells_per_diameter = resolution_from_environment(16.0);
  o.coupling = coupling_from_environment();
  o.wall_rule = wall_rule_from_environment();
  o.collision = collision_from_environment();
  o.ramp_diameters = ramp_from_environment();
  o.offset_cells = Eigen::Vector2d(0.3, 0.2);
  const TowedSphereResult r = run_towed_sphere_printed(o);
  // A drift of 1% (a third of the 3% budget) between the last two fifths (8 d of travel each,
  // about one shedding period at Johnson and Patel's St = 0.137) means the start-up is not over.
  EXPECT_NEAR(r.drag_coefficient, r.previous_fifth, 0.01 * r.drag_coefficient);
  EXPECT_NEAR(r.drag_coefficient, r.reference, 0.03 * r.reference);
  EXPECT_GT(r.lateral_ratio, 0.01);
}

}  // namespace
