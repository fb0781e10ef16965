// Walls inside the grid (Solver::set_obstacle) on a curved-wall flow with a closed form:
// circular Couette flow between a turning inner cylinder and a fixed outer one, in a layer one
// cell thick with every axis periodic (the solid ring outside R2 closes the domain). Steady
// azimuthal velocity u(r) = A r + B / r, A = -Omega R1^2 / (R2^2 - R1^2),
// B = Omega R1^2 R2^2 / (R2^2 - R1^2); torque on the inner cylinder per unit length
// 4 pi mu Omega R1^2 R2^2 / (R2^2 - R1^2) (Landau and Lifshitz, Fluid Mechanics, section 18).
#include <gtest/gtest.h>

#include <array>
#include <cmath>
#include <vector>

#include "lbm/lattice.hpp"
#include "lbm/solver.hpp"

namespace test_curved_walls {

using namespace settle::lbm;

struct Couette {
  double r_inner = 0.0, r_outer = 0.0, omega = 0.0;
  Eigen::Vector2d centre;
  double speed(double r) const {
    const double d = r_outer * r_outer - r_inner * r_inner;
    return -omega * r_inner * r_inner / d * r + omega * r_inner * r_inner * r_outer * r_outer / d / r;
  }
  double torque_per_length(double mu) const {
    return 4.0 * M_PI * mu * omega * r_inner * r_inner * r_outer * r_outer / (r_outer * r_outer - r_inner * r_inner);
  }
  bool solid(const Eigen::Vector2d& p) const {
    const double r = (p - centre).norm();
    return r < r_inner || r > r_outer;
  }
  /// Fraction t in (0, 1] of the segment p + t d where it first meets either circle.
  double crossing(const Eigen::Vector2d& p, const Eigen::Vector2d& d) const {
    const Eigen::Vector2d o = p - centre;
    double best = 2.0;
    for (const double r : {r_inner, r_outer}) {
      const double a = d.squaredNorm(), b = 2.0 * o.dot(d), c = o.squaredNorm() - r * r;
      const double disc = b * b - 4.0 * a * c;
      if (disc < 0.0) continue;
      for (const double t : {(-b - std::sqrt(disc)) / (2.0 * a), (-b + std::sqrt(disc)) / (2.0 * a)}) {
        if (t > 0.0 && t <= 1.0) best = std::min(best, t);
      }
    }
    return best;
  }
};

struct CouetteResult {
  double velocity_error = 0.0;  ///< root mean square of |u - u_exact| over the fluid cells, of Omega R1
  double torque = 0.0;          ///< on the inner cylinder, from the momentum exchange, per unit length
};

/// Cell centres at integer points; the cylinders' axis at a point off every symmetry of the grid.
/// `collision` and `tau` default to the solver's default operator (TRT) at tau = 0.8.
CouetteResult run_couette(double r_outer, WallRule rule, CollisionKind collision = CollisionKind::trt,
                          double tau = 0.8) {
  Couette flow;
  flow.r_outer = r_outer;
  flow.r_inner = 0.5 * r_outer;
  // Diffusive scaling: the inner wall's speed 0.16 / R2 (0.02 at R2 = 8) falls with the cell
  // size, so that the compressibility error (of order Mach^2) falls at second order too and does
  // not mask the walls' order.
  flow.omega = 0.16 / r_outer / flow.r_inner;
  const int n = 2 * static_cast<int>(std::ceil(r_outer)) + 4;
  flow.centre = Eigen::Vector2d(0.5 * (n - 1) + 0.137, 0.5 * (n - 1) - 0.071);

  SolverConfig cfg;
  cfg.nx = n, cfg.ny = n, cfg.nz = 1;
  cfg.tau = tau;
  cfg.collision = collision;
  auto solver = make_solver(cfg);
  Obstacle obstacle;
  obstacle.rule = rule;
  for (int y = 0; y < n; ++y)
    for (int x = 0; x < n; ++x)
      if (flow.solid({x, y})) obstacle.solid_cells.push_back({x, y, 0});
  for (int y = 0; y < n; ++y) {
    for (int x = 0; x < n; ++x) {
      const Eigen::Vector2d p(x, y);
      if (flow.solid(p)) continue;
      for (int i = 1; i < D3Q19::Q; ++i) {
        const auto& c = D3Q19::set.c[i];
        const Eigen::Vector2d d(c[0], c[1]);
        if (d.isZero() || !flow.solid(p + d)) continue;
        // The layer is one cell thick: a link with a z component meets the walls where its
        // projection does.
        const double q = flow.crossing(p, d);
        const Eigen::Vector2d wall = p + q * d - flow.centre;
        const bool inner = wall.norm() < 0.5 * (flow.r_inner + flow.r_outer);
        const Eigen::Vector3d u_w =
            inner ? Eigen::Vector3d(-flow.omega * wall.y(), flow.omega * wall.x(), 0.0) : Eigen::Vector3d::Zero();
        obstacle.links.push_back({{x, y, 0}, i, q, u_w});
      }
    }
  }
  solver->set_obstacle(obstacle);
  solver->initialise([&](int x, int y, int) {
    const Eigen::Vector2d r = Eigen::Vector2d(x, y) - flow.centre;
    if (flow.solid({double(x), double(y)})) return CellState{};
    const Eigen::Vector2d t = Eigen::Vector2d(-r.y(), r.x()) / r.norm();
    return CellState{1.0, Eigen::Vector3d(t.x(), t.y(), 0.0) * flow.speed(r.norm())};
  });
  // Several viscous times of the gap: the start from the exact profile leaves only its
  // non-equilibrium transient and the discretisation's own steady error.
  const double gap = flow.r_outer - flow.r_inner;
  const int steps = 2 * static_cast<int>(4.0 * gap * gap / viscosity_from_tau(cfg.tau) / 2.0);
  solver->run(steps);

  CouetteResult result;
  double sum = 0.0;
  int count = 0;
  for (int y = 0; y < n; ++y) {
    for (int x = 0; x < n; ++x) {
      if (flow.solid({double(x), double(y)})) continue;
      const Eigen::Vector2d r = Eigen::Vector2d(x, y) - flow.centre;
      const Eigen::Vector2d t = Eigen::Vector2d(-r.y(), r.x()) / r.norm();
      const Eigen::Vector3d u = solver->cell_velocity(x, y, 0);
      const Eigen::Vector2d exact = t * flow.speed(r.norm());
      sum += (Eigen::Vector2d(u.x(), u.y()) - exact).squaredNorm();
      ++count;
    }
  }
  result.velocity_error = std::sqrt(sum / count) / (flow.omega * flow.r_inner);
  const auto& momentum = solver->wall_momentum();
  for (std::size_t k = 0; k < obstacle.links.size(); ++k) {
    const WallLink& link = obstacle.links[k];
    const auto& c = D3Q19::set.c[link.dir];
    const Eigen::Vector2d wall =
        Eigen::Vector2d(link.cell[0], link.cell[1]) + link.q * Eigen::Vector2d(c[0], c[1]) - flow.centre;
    if (wall.norm() > 0.5 * (flow.r_inner + flow.r_outer)) continue;
    result.torque += wall.x() * momentum[k].y() - wall.y() * momentum[k].x();
  }
  return result;
}

TEST(LbmCurvedWalls, InterpolatedBounceBackConvergesAtSecondOrderOnCouetteFlow) {
  const CouetteResult coarse = run_couette(8.0, WallRule::bouzidi);
  const CouetteResult medium = run_couette(16.0, WallRule::bouzidi);
  const CouetteResult fine = run_couette(32.0, WallRule::bouzidi);
  // Bouzidi's linear interpolation is second order in space (Bouzidi et al. 2001; Pan, Luo and
  // Miller 2006, doi:10.1016/j.compfluid.2005.03.008). The order of one grid pair scatters with how
  // the circles cut the lattice (measured 2.45 and 1.79 for 8/16 and 16/32; errors 7.9e-3, 1.4e-3,
  // 4.2e-4), so the test takes it over the factor 4 from the coarsest to the finest grid (2.12);
  // 1.7 separates it with margin from the staircase's first order (1.1, next test).
  const double order = std::log2(coarse.velocity_error / fine.velocity_error) / 2.0;
  EXPECT_GT(order, 1.7) << coarse.velocity_error << " " << medium.velocity_error << " " << fine.velocity_error;
  EXPECT_LT(order, 3.0);
  // The momentum exchange's torque: the fluid resists the turning cylinder, so its torque is
  // minus the closed form. Measured -1.1%, -0.12%, -0.05% at R2 = 8, 16, 32; 0.5% at R2 = 32
  // is ten times that and far below what a wrong sign or a missing wall term would give.
  const double mu = viscosity_from_tau(0.8);
  Couette exact;
  exact.r_outer = 32.0, exact.r_inner = 16.0, exact.omega = 0.16 / 32.0 / 16.0;
  EXPECT_NEAR(fine.torque, -exact.torque_per_length(mu), 0.005 * exact.torque_per_length(mu));
}

TEST(LbmCurvedWalls, HalfwayBounceBackOnTheSameFlowIsFirstOrderAndLessAccurate) {
  const CouetteResult medium = run_couette(16.0, WallRule::halfway);
  const CouetteResult fine = run_couette(32.0, WallRule::halfway);
  const CouetteResult interpolated = run_couette(32.0, WallRule::bouzidi);
  // The staircase moves each wall by up to half a cell: an O(dx) error in the velocity that the
  // interpolation removes. Measured: 1.5e-2 and 7.0e-3 at R2 = 16 and 32 (order 1.1), 17 times
  // the interpolation's error at R2 = 32; the bounds leave wide margins on both.
  EXPECT_GT(fine.velocity_error, 3.0 * interpolated.velocity_error);
  EXPECT_LT(std::log2(medium.velocity_error / fine.velocity_error), 1.6);
}

// The order over the factor 4 from R2 = 8 to 32 between 1.7 and 3 (the linear rule's test's bounds:
// they separate second order from the staircase's first), and the torque at R2 = 32 within 0.5%
// (a missing or wrongly scaled wall term, or a wrong weight, gives percents).
void expect_second_order_and_the_torque(WallRule rule) {
  const CouetteResult coarse = run_couette(8.0, rule);
  const CouetteResult fine = run_couette(32.0, rule);
  const double order = std::log2(coarse.velocity_error / fine.velocity_error) / 2.0;
  EXPECT_GT(order, 1.7) << coarse.velocity_error << " " << fine.velocity_error;
  EXPECT_LT(order, 3.0);
  Couette exact;
  exact.r_outer = 32.0, exact.r_inner = 16.0, exact.omega = 0.16 / 32.0 / 16.0;
  const double torque = exact.torque_per_length(viscosity_from_tau(0.8));
  EXPECT_NEAR(fine.torque, -torque, 0.005 * torque) << fine.torque << " " << -torque;
}

TEST(LbmCurvedWalls, QuadraticInterpolationConvergesAtSecondOrder) {
  // Bouzidi et al. 2001's quadratic rule is second order too. Measured under TRT at tau = 0.8:
  // 1.17e-2, 2.9e-3, 8.6e-4 at R2 = 8, 16, 32 (order 1.88 over the factor 4; the torque -1.9%,
  // -0.45%, -0.14%, the 0.5% over three times the last): under TRT it is less accurate than the
  // linear rule (docs/lbm.md).
  expect_second_order_and_the_torque(WallRule::quadratic);
}

TEST(LbmCurvedWalls, CentralLinearInterpolationConvergesAtSecondOrder) {
  // Ginzburg, Verhaeghe and d'Humieres 2008's central linear rule is second order (their section
  // 4). Measured under TRT at tau = 0.8: 5.2e-3, 1.2e-3, 2.8e-4 at R2 = 8, 16, 32 (order 2.12 over
  // the factor 4; the torque -0.22%, +0.13%, +0.02%).
  expect_second_order_and_the_torque(WallRule::central_linear);
}

TEST(LbmCurvedWalls, QuadraticInterpolationHalvesTheLinearRulesErrorAtLowTauUnderRecursiveRegularisation) {
  // The regime of the resolved sphere runs (tau 0.51-0.54, the recursive regularised operator,
  // BGK-like at the wall): there the linear rule's error grows as tau falls (its wall slip depends
  // on the viscosity), the quadratic rule's much less. Measured at tau = 0.53, R2 = 16: velocity
  // error 5.6e-3 (linear) and 1.9e-3 (quadratic), torque +1.34% and +0.65%. The factor 2 asserted
  // on the velocity error is below the measured 2.9; equal accuracy would fail it.
  const double tau = 0.53;
  const CouetteResult linear = run_couette(16.0, WallRule::bouzidi, CollisionKind::recursive_regularized, tau);
  const CouetteResult quadratic = run_couette(16.0, WallRule::quadratic, CollisionKind::recursive_regularized, tau);
  EXPECT_LT(2.0 * quadratic.velocity_error, linear.velocity_error)
      << quadratic.velocity_error << " " << linear.velocity_error;
  Couette exact;
  exact.r_outer = 16.0, exact.r_inner = 8.0, exact.omega = 0.16 / 16.0 / 8.0;
  const double torque = exact.torque_per_length(viscosity_from_tau(tau));
  EXPECT_LT(std::abs(quadratic.torque + torque), std::abs(linear.torque + torque));
}

}  // namespace test_curved_walls
