// Stokes drag of spheroids in creeping flow (periodic_spheroid.hpp), CI-sized: a prolate spheroid
// broadside at 10 cells per volume-equivalent diameter in boxes of 3 and 4 d_v, extrapolated to an
// unbounded fluid. The finer check (16 cells per d_v, all four configurations) is
// validation_spheroid_drag.cpp.
#include <cmath>
#include <fstream>
#include <string>

#include <gtest/gtest.h>
#include <nlohmann/json.hpp>

#include "periodic_spheroid.hpp"

namespace test_spheroid_drag {

using namespace settle::coupling::testing;

nlohmann::json reference_table() {
  std::ifstream in(std::string(SETTLE_SOURCE_DIR) + "/validation/reference-data.json");
  return nlohmann::json::parse(in).at("spheroid_Stokes_drag").at("fields").at("K_table_D");
}

// The exact drag used as the reference is typed in the test support from the formulas of
// reference-data.json; the table beside them (computed independently from the same formulas)
// catches a transcription error. Tolerance: the table's 7 significant digits.
TEST(SpheroidStokesDrag, ClosedFormMatchesTheStoredTable) {
  int rows = 0;
  for (const auto& row : reference_table()) {
    const double gamma = row.at("gamma_L_over_d").get<double>();
    EXPECT_NEAR(spheroid_stokes_k(gamma, DragDirection::axial), row.at("K_axial_eqvol").get<double>(), 2e-6) << gamma;
    EXPECT_NEAR(spheroid_stokes_k(gamma, DragDirection::transverse), row.at("K_transverse_eqvol").get<double>(), 2e-6)
        << gamma;
    ++rows;
  }
  EXPECT_GE(rows, 10);
}

void check(double gamma, DragDirection direction) {
  const SpheroidDragCheck c = check_spheroid_drag(gamma, direction, 10.0, 30, 40);
  // Creeping flow: inertia changes K by O(Re), far below the budget at Re ~ 1e-2.
  EXPECT_LT(c.small_box.reynolds, 0.02);
  // Steady: the transient left in K (Aitken estimate, periodic_spheroid.hpp) is a thirtieth of
  // the budget or less.
  EXPECT_LT(c.small_box.last_relative_change, 1e-3);
  EXPECT_LT(c.large_box.last_relative_change, 1e-3);
  // A principal direction of the body and of the cubic array: no force across the drive, up to
  // the lattice's anisotropy and round-off.
  EXPECT_LT(c.large_box.lateral_force_ratio, 1e-3);
  // No-slip error at the markers after the default three forcing sweeps (the issue: reported and
  // bounded). Over the surface (rms) measured 0.56% of the flow speed; 1% catches a forcing that
  // stopped converging (one sweep leaves about half the slip of the step before it, docs/ibm.md).
  // The worst marker sits at a tip, where the radius of curvature b^2/a is 2 cells at this
  // resolution, less than the 3-cell support of the delta kernel, so neighbouring markers share
  // most of their stencil and the sweeps converge slowest there: measured 2.2% (L = 30) and 1.8%
  // (L = 40), against 0.4% for the axial drive at 16 cells per d_v (validation_spheroid_drag). 3% bounds it with the
  // small box's margin; the rms carries the convergence check.
  EXPECT_LT(c.large_box.slip_rms, 0.01);
  EXPECT_LT(c.large_box.slip_max, 0.03);
  // The criterion: 3% of the exact Stokes drag once the box is removed.
  EXPECT_NEAR(c.relative_error, 0.0, 0.03);
}

TEST(SpheroidStokesDrag, ProlateBroadsideAt10CellsPerDiameter) { check(2.0, DragDirection::transverse); }

}  // namespace test_spheroid_drag
