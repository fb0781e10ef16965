// The momentum exchange's force bookkeeping (coupling/momentum_exchange.hpp): the wrench a step
// reports is the mean of that step's link sum and the previous one's, and the previous one comes
// back through carried_state, so that a restored coupling reports what the original does; with
// covered_cell_torque, the torque adds the angular momentum by which the covered cells' fluid
// lags the body's rigid motion.
// The sums are read from the fluid's per-link momenta, the quantity the coupling sums; a
// sphere crossing the grid obliquely changes its links at every step, so each step's sum differs.
#include <gtest/gtest.h>

#include <cmath>
#include <memory>

#include "body/shape_factory.hpp"
#include "coupling/body_coupling.hpp"
#include "coupling/case_plan.hpp"
#include "lbm/solver.hpp"
#include "support/default_setup.hpp"

namespace settle::coupling {
namespace {

struct Crossing {
  std::unique_ptr<lbm::Solver> fluid;
  std::unique_ptr<BodyCoupling> coupling;
  LatticePose pose;
};

// dx = 1 m, so lattice and SI lengths agree: a sphere of 8 cells in a periodic 24-cell box at
// tau = 0.6, coupled by the momentum exchange.
std::unique_ptr<lbm::Solver> box_fluid() {
  lbm::SolverConfig config;
  config.nx = config.ny = config.nz = 24;
  config.tau = 0.6;
  return lbm::make_solver(config);
}

std::unique_ptr<BodyCoupling> sphere_coupling(bool covered_cell_torque) {
  body::ShapeSpec spec;
  spec.shape = "sphere";
  spec.diameter = 8.0;
  CouplingOptions options = coupling_options(settle::test::default_setup());
  options.kind = CouplingKind::momentum_exchange;
  options.covered_cell_torque = covered_cell_torque;
  return make_coupling(std::shared_ptr<const body::Shape>(body::make_shape(spec)), 1.0, options);
}

// The sphere towed at (0.03, 0.02, -0.04) cells per step. The link sums alone: the covered cells'
// term is the impose's (its restart: RestartTest).
Crossing towed_sphere() {
  Crossing c{box_fluid(), sphere_coupling(false), {}};
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
  std::unique_ptr<BodyCoupling> b = sphere_coupling(false);
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

// The sphere, spinning and moving through fluid at rest, displaced between two imposes with
// no fluid step between: every cell it covers holds rho = 1, u = 0, and no link has exchanged
// momentum yet, so the reported torque is the covered cells' term alone.
LatticeWrench torque_after_a_displacement(bool covered_cell_torque, const LatticePose& from, const LatticePose& to) {
  auto fluid = box_fluid();
  auto coupling = sphere_coupling(covered_cell_torque);
  coupling->start(*fluid, from);
  coupling->impose(*fluid);
  EXPECT_EQ(coupling->measure(*fluid).total.torque, Eigen::Vector3d::Zero())
      << "the first impose makes the body's own cells solid: nothing is covered";
  coupling->place(*fluid, to);
  coupling->impose(*fluid);
  return coupling->measure(*fluid).total;
}

TEST(MomentumExchangeCoveredCells, TheBodyTakesTheSpinTheCoveredFluidLacks) {
  LatticePose from, to;
  from.centre = Eigen::Vector3d(12.2, 11.7, 12.4);
  to = from;
  to.centre += Eigen::Vector3d(0.6, -0.35, 0.45);
  to.velocity = from.velocity = Eigen::Vector3d(0.03, -0.02, 0.04);
  to.angular_velocity_n = from.angular_velocity_n = Eigen::Vector3d(0.004, -0.002, 0.01);
  // The covered cells, from the geometry: centres inside the sphere at `to` and not at `from`
  // (no centre lies within 1e-6 of either surface here). Their fluid is at rest at density 1:
  // each lags the body by its rigid velocity there.
  Eigen::Vector3d expected = Eigen::Vector3d::Zero();
  int covered = 0;
  for (int z = 0; z < 24; ++z)
    for (int y = 0; y < 24; ++y)
      for (int x = 0; x < 24; ++x) {
        const Eigen::Vector3d c(x, y, z);
        if ((c - to.centre).norm() >= 4.0 || (c - from.centre).norm() < 4.0) continue;
        expected += (c - to.centre).cross(-to.velocity_at(c));
        ++covered;
      }
  ASSERT_GT(covered, 20) << "the displacement must cover cells for the check to mean something";
  const LatticeWrench with = torque_after_a_displacement(true, from, to);
  // The same terms as the coupling's sum, maybe in another order: round-off of 1e-12.
  EXPECT_LT((with.torque - expected).norm(), 1e-12 * expected.norm());
  EXPECT_EQ(with.force, Eigen::Vector3d::Zero()) << "the force takes nothing of the covered cells";
  const LatticeWrench without = torque_after_a_displacement(false, from, to);
  EXPECT_EQ(without.torque, Eigen::Vector3d::Zero());
}

}  // namespace
}  // namespace settle::coupling
