// The momentum exchange's force on a sphere oscillating in fluid at rest against Stokes' closed
// form (oscillating_sphere.hpp): the unsteady force of a body that moves across cells, the half of
// a free path oscillation that is not the wake's.
//
// Measured (native build, 2026-12-02; docs/validation.md, "A sphere oscillating in fluid at
// rest"): d = 12, a / delta = 2, X0 = 1 cell, tau 0.6, box 48 (4 d): dissipative -1.14%, inertial
// -1.17%. In a box of 72 (6 d) -0.10% and -0.67%: about 1% of the 48-cell figures is the periodic
// array's (solid fraction 0.8%: the fluid's back-flow and the images' dipoles). With X0 = 0.5 and
// 2 cells the dissipative part is -1.31% and -0.48%, the inertial -1.21% and -1.39%: the
// amplitude's O((X0 / a)^2) share is below half a percent. Three periods more before and
// during the measurement change the figures by 0.03%: the start has died out.
#include <gtest/gtest.h>

#include "oscillating_sphere.hpp"

namespace test_oscillating_sphere {

using namespace settle::coupling::testing;

TEST(OscillatingSphere, MomentumExchangeFollowsStokesAt12CellsPerDiameter) {
  OscillatingSphereOptions o;  // d 12, a / delta 2, X0 1 cell, tau 0.6, box 48, 2 + 3 periods
  const OscillatingSphereResult r = run_oscillating_sphere_printed(o);
  // 3%, as the Stokes drag and torque tests: the measured errors are about 1.2%, of which the box
  // holds about 1% (file comment), so a defect that moves either part of the unsteady force by
  // 2% more (a wrong wall velocity, momentum lost in covering or uncovering cells, a phase lag of
  // the force) fails.
  EXPECT_NEAR(r.dissipative_ratio, 1.0, 0.03);
  EXPECT_NEAR(r.inertial_ratio, 1.0, 0.03);
}

}  // namespace test_oscillating_sphere
