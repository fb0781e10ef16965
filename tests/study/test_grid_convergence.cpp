#include <gtest/gtest.h>

#include <cmath>
#include <stdexcept>

#include "study/grid_convergence.hpp"

namespace test_grid_convergence {

using settle::study::grid_convergence;
using settle::study::ThreeGrids;

// f(h) = f0 + C h^p exactly: the procedure must return p, f0 and the GCI of its definition. The
// tolerances are round-off of a few operations on numbers of order one (the iteration for unequal
// ratios is run to 1e-12).
ThreeGrids exact(double f0, double c, double p, double h1, double h2, double h3) {
  const auto f = [&](double h) { return f0 + c * std::pow(h, p); };
  return {h1, h2, h3, f(h1), f(h2), f(h3)};
}

TEST(GridConvergence, RecoversTheOrderAndTheLimitForAConstantRatio) {
  const auto g = grid_convergence(exact(0.7, 3.0, 2.0, 1.0 / 32, 1.0 / 16, 1.0 / 8));
  ASSERT_TRUE(g.observed_order && g.extrapolated && g.gci_fine);
  EXPECT_NEAR(*g.observed_order, 2.0, 1e-10);
  EXPECT_NEAR(*g.extrapolated, 0.7, 1e-12);
  EXPECT_FALSE(g.oscillatory);
  // Roache's index: 1.25 |(f2 - f1) / f1| / (r^p - 1) with r = 2, p = 2.
  const double f1 = 0.7 + 3.0 / (32.0 * 32.0), f2 = 0.7 + 3.0 / (16.0 * 16.0);
  EXPECT_NEAR(*g.gci_fine, 1.25 * std::abs((f2 - f1) / f1) / 3.0, 1e-12);
}

TEST(GridConvergence, RecoversTheOrderForUnequalRatios) {
  // 16, 20, 24, 32 cells per diameter give ratios 1.2 and 1.25: the fixed-point iteration's q(p).
  const auto g = grid_convergence(exact(1.1, -0.8, 1.5, 1.0 / 32, 1.0 / 24, 1.0 / 20));
  ASSERT_TRUE(g.observed_order && g.extrapolated);
  EXPECT_NEAR(*g.observed_order, 1.5, 1e-8);
  EXPECT_NEAR(*g.extrapolated, 1.1, 1e-9);
}

// Orders the grids do not confirm (not within 10% of the scheme's 2): Roache's safety factor 3
// with the order held within [0.5, 2]. A first-order figure keeps its order; one whose observed
// order is 7 (grids not yet governed by the leading term) is rated as if second order.
TEST(GridConvergence, AnOrderTheGridsDoNotConfirmGetsTheSafetyFactorThree) {
  const auto first = grid_convergence(exact(1.0, 0.5, 1.0, 1.0 / 32, 1.0 / 24, 1.0 / 20));
  ASSERT_TRUE(first.observed_order && first.gci_fine);
  EXPECT_FALSE(first.order_confirmed);
  const double f1 = 1.0 + 0.5 / 32.0, f2 = 1.0 + 0.5 / 24.0;
  EXPECT_NEAR(*first.gci_fine, 3.0 * std::abs((f2 - f1) / f1) / (32.0 / 24.0 - 1.0), 1e-9);

  // C = 1e8 puts the three values 0.003-0.08 above the limit, far from round-off.
  const auto steep = grid_convergence(exact(1.0, 1e8, 7.0, 1.0 / 32, 1.0 / 24, 1.0 / 20));
  ASSERT_TRUE(steep.observed_order && steep.gci_fine);
  EXPECT_NEAR(*steep.observed_order, 7.0, 1e-8);
  EXPECT_FALSE(steep.order_confirmed);
  const double g1 = 1.0 + 1e8 * std::pow(1.0 / 32.0, 7.0), g2 = 1.0 + 1e8 * std::pow(1.0 / 24.0, 7.0);
  EXPECT_NEAR(*steep.gci_fine, 3.0 * std::abs((g2 - g1) / g1) / (std::pow(32.0 / 24.0, 2.0) - 1.0), 1e-12);

  EXPECT_TRUE(grid_convergence(exact(0.7, 3.0, 2.0, 1.0 / 32, 1.0 / 16, 1.0 / 8)).order_confirmed);
}

TEST(GridConvergence, FlagsOscillatoryConvergenceAndSameValues) {
  EXPECT_TRUE(grid_convergence({0.25, 0.5, 1.0, 1.0, 1.1, 1.05}).oscillatory);
  EXPECT_FALSE(grid_convergence({0.25, 0.5, 1.0, 1.0, 1.0, 1.2}).observed_order.has_value());
  EXPECT_THROW(grid_convergence({0.5, 0.25, 1.0, 1.0, 1.1, 1.2}), std::invalid_argument);
}

}  // namespace test_grid_convergence
