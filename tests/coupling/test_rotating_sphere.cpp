// Torque on a sphere turning at a prescribed constant rate in creeping flow, against Stokes'
// exact T = 8 pi mu a^3 Omega for the unbounded fluid (Lamb 1932, Hydrodynamics, 6th ed., ch. XI;
// Happel and Brenner 1965, Low Reynolds Number Hydrodynamics). No change to the coupling was
// needed: a towed body keeps its initial body angular velocity and turns its attitude
// (RigidBody::advance_prescribed), and the markers carry v + omega x r.
// Checks the torque half of the immersed-boundary coupling (marker moments, internal angular
// momentum, rotating markers of a towed body); test_periodic_sphere.cpp checks the force half.
//
// The sphere sits in a periodic cube, i.e. in a simple cubic array of co-rotating spheres. The
// array's correction decays like (a / L)^3: the box's mean vorticity is zero, so the rigidly
// turning solid (vorticity 2 Omega over a fraction phi) leaves a counter-rotation of about
// -Omega phi in the fluid, and the torque grows by about (1 + phi). Two boxes are run and
// ratio(L) = ratio_inf (1 + c phi) is solved for ratio_inf (periodic_sphere.hpp). Boxes of 2 and
// 3 diameters (phi = 0.065 and 0.019) keep this test at about 8 s; a box large enough for the
// correction to fall below 1% would need L > 3.9 d (phi < 0.009; measured: 0.96% at L = 4 d),
// so the extrapolation is both cheaper and more accurate. The (1 + phi) argument is a heuristic
// estimate, not used by the test. The form is checked in validation_rotating_sphere.cpp: fitted from
// L = 32 and 48 at d = 16 it predicts the torque at L = 64 to 0.07%, and c = 1.08 at d = 12, 16
// and 24 (the mean-vorticity estimate above gives c = 1).
//
// Measured (Release): d = 16: ratio 1.0512 (L = 32), 1.0025 (L = 48), extrapolated 0.9819
// (-1.81%). Resolution: d = 12: -1.80%; d = 16: -1.81%; d = 24: -1.51% (validation).
#include <cstdio>

#include <gtest/gtest.h>

#include "periodic_sphere.hpp"

namespace test_rotating_sphere {

using namespace settle::coupling::testing;

RotatingSphereResult run(double cells_per_diameter, int box_cells) {
  return run_rotating_sphere_printed(cells_per_diameter, box_cells);
}

TEST(RotatingSphere, StokesTorqueAt16CellsPerDiameter) {
  const RotatingSphereResult small_box = run(16.0, 32);
  const RotatingSphereResult large_box = run(16.0, 48);
  const BoxExtrapolation e = extrapolate_box(small_box, large_box);
  std::printf("extrapolated to an unbounded fluid: %.4f (%+.2f%%), c = %.2f\n", e.ratio_infinite,
              100.0 * (e.ratio_infinite - 1.0), e.coefficient);
  // Creeping flow: inertia changes the torque of a rotating sphere at O(Re^2) (Re ~ 5e-3 here).
  EXPECT_LT(small_box.reynolds, 0.01);
  // Steady: the ratio changed by less than 1e-5 over the last tenth of the box's slowest viscous
  // decay time, far below the tolerance.
  EXPECT_LT(small_box.last_relative_change, 1e-5);
  EXPECT_LT(large_box.last_relative_change, 1e-5);
  // The task's criterion, 3% of Stokes' torque once the box is removed. The measured error is
  // -1.8% at 12 and 16 cells per diameter and -1.5% at 24 (an effective radius about 0.6% small:
  // T ~ a^3; the retraction r_d = 0.4 was calibrated on the drag, docs/coupling.md), so this is
  // not a resolution-limited pass that a finer grid could break.
  EXPECT_NEAR(e.ratio_infinite, 1.0, 0.03);
}

// The same with the momentum exchange (interpolated bounce-back on the true surface): the control
// for the torque of that coupling, whose free sphere of Uhlmann and Dusek's case B spun up
// (docs/notes.md, 2026-11-26). Same criterion and reasons as above.
void expect_momentum_exchange_stokes_torque(settle::lbm::LatticeKind lattice) {
  using settle::coupling::CouplingKind;
  const RotatingSphereResult small_box =
      run_rotating_sphere_printed(16.0, 32, CouplingKind::momentum_exchange, lattice);
  const RotatingSphereResult large_box =
      run_rotating_sphere_printed(16.0, 48, CouplingKind::momentum_exchange, lattice);
  const BoxExtrapolation e = extrapolate_box(small_box, large_box);
  std::printf("extrapolated to an unbounded fluid: %.4f (%+.2f%%), c = %.2f\n", e.ratio_infinite,
              100.0 * (e.ratio_infinite - 1.0), e.coefficient);
  EXPECT_LT(small_box.last_relative_change, 1e-5);
  EXPECT_LT(large_box.last_relative_change, 1e-5);
  EXPECT_NEAR(e.ratio_infinite, 1.0, 0.03);
}

TEST(RotatingSphere, MomentumExchangeStokesTorqueAt16CellsPerDiameter) {
  expect_momentum_exchange_stokes_torque(settle::lbm::LatticeKind::D3Q19);
}

// The same on D3Q27, whose eight corner links change the set of wall links (about 1.6 times as
// many): the control for the free sphere whose spin ran away on D3Q27 (docs/notes.md,
// 2026-11-29). Same criterion and reasons as above.
TEST(RotatingSphere, MomentumExchangeStokesTorqueOnD3q27) {
  expect_momentum_exchange_stokes_torque(settle::lbm::LatticeKind::D3Q27);
}

}  // namespace test_rotating_sphere
