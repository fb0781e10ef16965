// Stokes drag of a simple cubic array of spheres (a fixed sphere in a periodic box, flow
// driven by a body force) at 16 cells per diameter, against Sangani and Acrivos 1982 (see
// periodic_sphere.hpp). The acceptance criterion is 2% at 16 cells per diameter for at
// least two solid fractions; the finer check is validation_periodic_sphere.cpp.
//
// Measured (Release, this set-up): phi = 0.0654: K = 2.8460 vs 2.8420 (+0.14%); phi = 0.155:
// K = 5.1981 vs 5.1798 (+0.35%); phi = 0.268: K = 10.136 vs 10.065 (+0.70%).
// With interior markers and their calibrated r_d = 0.5: K = 2.8495 (+0.26%), 5.2092 (+0.57%),
// 10.181 (+1.15%); at r_d = 0.4 they gave +3.41% at phi = 0.0654, outside the 2%.
#include <cmath>
#include <cstdio>

#include <gtest/gtest.h>

#include "periodic_sphere.hpp"

namespace test_periodic_sphere {

using namespace settle::coupling::testing;
using settle::coupling::CouplingKind;
using settle::coupling::Simulation;
using settle::coupling::SimulationSetup;

void check(int box_cells, bool interior_markers = false) {
  PeriodicSphereOptions o;
  o.cells_per_diameter = 16.0;
  o.box_cells = box_cells;
  o.interior_markers = interior_markers;
  o.retraction = settle::coupling::calibrated_marker_retraction_cells(interior_markers);
  o.steady_tolerance = 1e-5;
  const PeriodicSphereResult r = run_periodic_sphere(o);
  std::printf(
      "d = 16 cells, L = %d, interior markers %d: phi = %.4f, K = %.4f, Sangani-Acrivos %.4f (%+.2f%%), Re = %.1e, "
      "%lld steps\n",
      box_cells, int(interior_markers), r.solid_fraction, r.k, r.k_reference, 100.0 * (r.k / r.k_reference - 1.0),
      r.reynolds, static_cast<long long>(r.steps));
  // Creeping flow: Re << 1 (inertia changes K by O(Re) ~ 1e-2 of a percent here).
  EXPECT_LT(r.reynolds, 0.01);
  // Steady: K changed by less than 1e-5 over the last tenth of the slowest viscous decay time,
  // so the remaining transient is far below the tolerance.
  EXPECT_LT(r.last_relative_change, 1e-5);
  // The criterion (2% at 16 cells per diameter). The Sangani-Acrivos series agrees with
  // Zick and Homsy's tabulated values to 0.1% at these fractions (reference-data.json).
  EXPECT_NEAR(r.k, r.k_reference, 0.02 * r.k_reference);
}

TEST(PeriodicSphereArray, DilutePhi0065At16CellsPerDiameter) { check(32); }
TEST(PeriodicSphereArray, ModeratePhi0155At16CellsPerDiameter) { check(24); }
TEST(PeriodicSphereArray, DensePhi0268At16CellsPerDiameter) { check(20); }
// The same criterion for numerics.interior_markers with its own calibrated retraction.
TEST(PeriodicSphereArray, InteriorMarkersDilutePhi0065At16CellsPerDiameter) { check(32, true); }
TEST(PeriodicSphereArray, InteriorMarkersDensePhi0268At16CellsPerDiameter) { check(20, true); }

}  // namespace test_periodic_sphere

namespace test_periodic_sphere {

double momentum_exchange_k_error(int box_cells, settle::lbm::WallRule rule) {
  PeriodicSphereOptions o;
  o.cells_per_diameter = 16.0;
  o.box_cells = box_cells;
  o.coupling = settle::coupling::CouplingKind::momentum_exchange;
  o.wall_rule = rule;
  o.steady_tolerance = 1e-5;
  const PeriodicSphereResult r = run_periodic_sphere(o);
  std::printf(
      "momentum exchange (%s), d = 16 cells, L = %d: phi = %.4f, K = %.4f, Sangani-Acrivos %.4f (%+.2f%%), "
      "Re = %.1e, %lld steps\n",
      settle::lbm::to_string(rule).c_str(), box_cells, r.solid_fraction, r.k, r.k_reference,
      100.0 * (r.k / r.k_reference - 1.0), r.reynolds, static_cast<long long>(r.steps));
  EXPECT_LT(r.reynolds, 0.01);
  EXPECT_LT(r.last_relative_change, 1e-5);
  return r.k / r.k_reference - 1.0;
}

// The case's TRT magic parameter is the fluid's, and it changes the flow: the same driven array
// after 30 steps with Lambda = 3/16 and 1/12 (the odd moments relax at other rates, so the
// velocities near the walls differ well above round-off).
TEST(PeriodicSphereArray, TheSetupsTrtMagicIsTheFluids) {
  PeriodicSphereOptions o;
  o.cells_per_diameter = 6.0;
  o.box_cells = 16;
  o.coupling = CouplingKind::momentum_exchange;
  const auto velocity_after_30_steps = [&o](double magic) {
    SimulationSetup s = periodic_sphere_setup(o);
    s.body_force_si = Eigen::Vector3d(1e-5, 0.0, 0.0);
    s.trt_magic = magic;
    Simulation sim(s);
    EXPECT_EQ(sim.fluid().config().magic, magic);
    for (int n = 0; n < 30; ++n) sim.step();
    return sim.superficial_velocity_si().x();
  };
  const double wall_exact = velocity_after_30_steps(3.0 / 16.0), low = velocity_after_30_steps(1.0 / 12.0);
  EXPECT_GT(std::abs(wall_exact - low), 1e-6 * std::abs(wall_exact)) << wall_exact << " " << low;
}

// The sharp interface at tau = 1 (TRT, magic 3/16): interpolated bounce-back puts the wall at
// the sphere's true surface, with nothing calibrated. Measured: phi = 0.0654: K -0.51%; phi =
// 0.268 (4 cells between neighbouring spheres): -1.60%. The dilute array is held to 1%; the
// dense one to the 2% of the immersed-boundary checks above, its gaps being too narrow for more.
TEST(PeriodicSphereArray, MomentumExchangeDilutePhi0065At16CellsPerDiameter) {
  EXPECT_NEAR(momentum_exchange_k_error(32, settle::lbm::WallRule::bouzidi), 0.0, 0.01);
}

TEST(PeriodicSphereArray, MomentumExchangeDensePhi0268At16CellsPerDiameter) {
  EXPECT_NEAR(momentum_exchange_k_error(20, settle::lbm::WallRule::bouzidi), 0.0, 0.02);
}

// The quadratic rule through the whole coupling (case plan, links from the shape, force): the same
// criterion on the dilute array (measured -1.16%, against the linear rule's -0.51%). On the dense
// array it gives -2.67% under TRT at tau = 1 and does not meet it (docs/lbm.md): the quadratic rule
// lowers the drag by 1-2% at 16 cells whatever the operator, which helps where the linear rule's
// drag is too high (a fixed sphere at Re = 100, docs/validation.md) and not here.
TEST(PeriodicSphereArray, MomentumExchangeQuadraticDilutePhi0065At16CellsPerDiameter) {
  EXPECT_NEAR(momentum_exchange_k_error(32, settle::lbm::WallRule::quadratic), 0.0, 0.02);
}

}  // namespace test_periodic_sphere
