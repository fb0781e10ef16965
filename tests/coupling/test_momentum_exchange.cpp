// The momentum exchange's force bookkeeping (coupling/momentum_exchange.hpp): the wrench a step
// reports is the mean of that step's link sum and the previous one's, and the previous one comes
// back through carried_state, so that a restored coupling reports what the original does.
// The sums are read from the fluid's per-link momenta, the quantity the coupling sums; a
// sphere crossing the grid obliquely changes its links at every step, so each step's sum differs.
#include <gtest/gtest.h>

#include <cmath>
#include <memory>

#include "body/shape_factory.hpp"
#include "coupling/body_coupling.hpp"
#include "lbm/solver.hpp"

namespace settle::coupling {
namespace {

struct Crossing {
  std::unique_ptr<lbm::Solver> fluid;
  std::unique_ptr<BodyCoupling> coupling;
  LatticePose pose;
};

// dx = 1 m, so lattice and SI lengths agree; a sphere of 8 cells towed at (0.03, 0.02, -0.04)
// cells per step through a periodic 24-cell box at tau = 0.6.
Crossing towed_sphere() {
  body::ShapeSpec spec;
  spec.shape = "sphere";
  spec.diameter = 8.0;
  std::shared_ptr<const body::Shape> shape(body::make_shape(spec));
  lbm::SolverConfig config;
  config.nx = config.ny = config.nz = 24;
  config.tau = 0.6;
  CouplingOptions options;
  options.kind = CouplingKind::momentum_exchange;
  Crossing c{lbm::make_solver(config), make_coupling(shape, 1.0, options), {}};
  c.pose.centre = Eigen::Vector3d(12.2, 11.7, 12.4);
  c.pose.velocity = Eigen::Vector3d(0.03, 0.02, -0.04);
  c.coupling->start(*c.fluid, c.pose);
  return c;
}

LatticeWrench step(Crossing& c, Eigen::Vector3d* link_force_sum) {
  c.pose.centre += c.pose.velocity;
  c.coupling->place(*c.fluid, c.pose);
  c.coupling->impose(*c.fluid);
  c.fluid->step();
  *link_force_sum = Eigen::Vector3d::Zero();
  for (const Eigen::Vector3d& m : c.fluid->wall_momentum()) *link_force_sum += m;
  return c.coupling->measure(*c.fluid).total;
}

TEST(MomentumExchangeForce, IsTheMeanOfThisAndThePreviousStepsLinkSums) {
  Crossing c = towed_sphere();
  Eigen::Vector3d previous = Eigen::Vector3d::Zero(), sum;
  double largest_change = 0.0;
  for (int n = 0; n < 12; ++n) {
    const LatticeWrench reported = step(c, &sum);
    // Round-off only: the same additions in another order.
    EXPECT_LT((reported.force - 0.5 * (sum + previous)).norm(), 1e-12 * (1.0 + sum.norm())) << "step " << n;
    if (n > 0) largest_change = std::max(largest_change, (sum - previous).norm());
    previous = sum;
  }
  // Not a vacuous check: the sums change from step to step.
  EXPECT_GT(largest_change, 1e-6);
}

TEST(MomentumExchangeForce, ARestoredCouplingCarriesThePreviousStepsSum) {
  Crossing a = towed_sphere();
  Eigen::Vector3d sum;
  for (int n = 0; n < 5; ++n) step(a, &sum);
  // A second coupling on the same fluid, started at the same pose, given a's carried state.
  body::ShapeSpec spec;
  spec.shape = "sphere";
  spec.diameter = 8.0;
  CouplingOptions options;
  options.kind = CouplingKind::momentum_exchange;
  std::unique_ptr<BodyCoupling> b =
      make_coupling(std::shared_ptr<const body::Shape>(body::make_shape(spec)), 1.0, options);
  b->start(*a.fluid, a.pose);
  b->restore_carried_state(a.coupling->carried_state());
  a.pose.centre += a.pose.velocity;
  a.coupling->place(*a.fluid, a.pose);
  b->place(*a.fluid, a.pose);
  a.coupling->impose(*a.fluid);
  a.fluid->step();
  const LatticeWrench from_a = a.coupling->measure(*a.fluid).total;
  const LatticeWrench from_b = b->measure(*a.fluid).total;
  EXPECT_EQ(from_a.force, from_b.force);
  EXPECT_EQ(from_a.torque, from_b.torque);
}

}  // namespace
}  // namespace settle::coupling
