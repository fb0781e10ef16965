// Validation (label `validation`, about a minute): the rotating sphere of test_rotating_sphere.cpp
// at 24 cells per diameter in boxes of 2 and 3 diameters, extrapolated to an unbounded fluid, and
// the box correction checked against a third box at 16 cells per diameter. Measured (Release):
// d = 24: ratio 1.0546 (L = 48), 1.0055 (L = 72), extrapolated 0.9849 (-1.51%), c = 1.08 (61 s);
// d = 16: L = 64 predicted 0.9906 from L = 32 and 48, measured 0.9913 (34 s).
#include <cstdio>

#include <gtest/gtest.h>

#include "periodic_sphere.hpp"

namespace {

using namespace settle::coupling::testing;

RotatingSphereResult run(double cells_per_diameter, int box_cells) {
  return run_rotating_sphere_printed(cells_per_diameter, box_cells);
}

TEST(RotatingSphereValidation, StokesTorqueAt24CellsPerDiameter) {
  const RotatingSphereResult small_box = run(24.0, 48);
  const RotatingSphereResult large_box = run(24.0, 72);
  const BoxExtrapolation e = extrapolate_box(small_box, large_box);
  std::printf("extrapolated to an unbounded fluid: %.4f (%+.2f%%), c = %.2f\n", e.ratio_infinite,
              100.0 * (e.ratio_infinite - 1.0), e.coefficient);
  EXPECT_LT(small_box.last_relative_change, 1e-5);  // steady (see test_rotating_sphere.cpp)
  EXPECT_LT(large_box.last_relative_change, 1e-5);
  // The task's criterion: 3% of Stokes' torque once the box is removed (the error shrinks from
  // -1.8% at d = 16 to -1.5% here).
  EXPECT_NEAR(e.ratio_infinite, 1.0, 0.03);
}

TEST(RotatingSphereValidation, BoxCorrectionAt16CellsPerDiameter) {
  const BoxExtrapolation e = extrapolate_box(run(16.0, 32), run(16.0, 48));
  const RotatingSphereResult third = run(16.0, 64);
  const double predicted = e.ratio_infinite * (1.0 + e.coefficient * third.volume_fraction);
  std::printf("L = 64 predicted from L = 32, 48: %.4f, measured %.4f\n", predicted, third.torque_ratio);
  // The extrapolation's own error must be small against the 3% budget: a wrong power of a / L
  // (e.g. (a / L)^1) would miss the third box by about 1%; 0.2% leaves the extrapolated torque
  // uncertain by far less than the discretisation error it is meant to expose.
  EXPECT_NEAR(third.torque_ratio, predicted, 0.002);
}

}  // namespace
