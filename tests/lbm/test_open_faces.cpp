// Inlets and outlets (SolverConfig::open_faces): a uniform stream entering through a velocity
// face and leaving through an outflow face is an exact steady state of the scheme (the inlet's
// moving-wall bounce-back returns the equilibrium of the inflow velocity, the outlet's
// equilibrium at density 1 and the neighbouring velocity is that equilibrium, the free-slip
// sides reflect no normal velocity), and a channel started at rest fills with the inflow. The population-level rules are checked against the pull-form reference
// in test_aa_reference.cpp.
#include <gtest/gtest.h>

#include <cmath>
#include <numbers>

#include "common/error.hpp"
#include "lbm/solver.hpp"

namespace test_open_faces {

using namespace settle::lbm;

SolverConfig channel(LatticeKind lattice, Precision precision) {
  SolverConfig cfg;
  cfg.lattice = lattice;
  cfg.precision = precision;
  cfg.nx = 6, cfg.ny = 5, cfg.nz = 24;
  cfg.boundaries = {Boundary::free_slip, Boundary::periodic, Boundary::no_slip};
  cfg.open_faces = {{{2, 0}, Boundary::velocity}, {{2, 1}, Boundary::outflow}};
  cfg.inflow_velocity = Eigen::Vector3d(0.0, 0.0, 0.05);
  cfg.tau = 0.6;
  return cfg;
}

double largest_deviation(const Solver& solver, const Eigen::Vector3d& u, double rho) {
  double worst = 0.0;
  for (int z = 0; z < solver.nz(); ++z)
    for (int y = 0; y < solver.ny(); ++y)
      for (int x = 0; x < solver.nx(); ++x) {
        const CellState s = solver.cell_state(x, y, z);
        worst = std::max({worst, (s.velocity - u).cwiseAbs().maxCoeff(), std::abs(s.density - rho)});
      }
  return worst;
}

TEST(LbmOpenFaces, UniformStreamIsAnExactSteadyState) {
  for (const auto lattice : {LatticeKind::D3Q19, LatticeKind::D3Q27}) {
    auto solver = make_solver(channel(lattice, Precision::float64));
    const Eigen::Vector3d u = solver->config().inflow_velocity;
    solver->initialise([&](int, int, int) { return CellState{1.0, u}; });
    solver->run(101);  // both parities
    // Round-off only: each step reproduces the equilibrium to a few ulps of its O(0.1) values.
    EXPECT_LT(largest_deviation(*solver, u, 1.0), 1e-13) << to_string(lattice);
  }
}

TEST(LbmOpenFaces, ChannelStartedAtRestFillsWithTheInflow) {
  auto solver = make_solver(channel(LatticeKind::D3Q19, Precision::float64));
  const Eigen::Vector3d u = solver->config().inflow_velocity;
  solver->initialise([](int, int, int) { return CellState{}; });
  // The inflow ramps up as sin^2 over 1000 steps, as the cases do. What the start-up leaves
  // rings as the channel's quarter-wave acoustic mode between the reflecting inlet and the
  // pressure outlet (period 4 nz / c_s = 166 steps), which viscosity damps with an e-folding
  // time of about 4000 steps here: 19000 more steps leave about 1e-5 of it.
  constexpr int kRampSteps = 1000;
  for (int step = 0; step < kRampSteps; ++step) {
    const double phase = std::sin(0.5 * std::numbers::pi * step / kRampSteps);
    solver->set_inflow_velocity(phase * phase * u);
    solver->run(1);
  }
  solver->set_inflow_velocity(u);
  solver->run(19000);
  // The outlet lets the unknowns enter at the reference density, so the stream settles at density
  // 1 and the inflow's velocity. 1e-4 is ten times the acoustic residual and far below what an
  // outlet that lets the density float (1 / (1 - U) = 1.053 here, measured with a zero-gradient
  // copy) or an inlet at density 1 (a velocity error of U (rho - 1)) would leave.
  EXPECT_LT(largest_deviation(*solver, u, 1.0), 1e-4);
}

TEST(LbmOpenFaces, RefusedOnPeriodicAxesAndTwiceOnOneFace) {
  SolverConfig cfg = channel(LatticeKind::D3Q19, Precision::float64);
  cfg.open_faces.push_back({{1, 0}, Boundary::outflow});  // y is periodic
  EXPECT_THROW(make_solver(cfg), settle::InputError);
  cfg = channel(LatticeKind::D3Q19, Precision::float64);
  cfg.open_faces.push_back({{2, 1}, Boundary::velocity});
  EXPECT_THROW(make_solver(cfg), settle::InputError);
  cfg = channel(LatticeKind::D3Q19, Precision::float64);
  cfg.inflow_velocity = Eigen::Vector3d(0.0, 0.0, 0.4);
  EXPECT_THROW(make_solver(cfg), settle::InputError);
  EXPECT_EQ(to_string(parse_face("z-", "domain.inflow")), "z-");
  EXPECT_THROW(parse_face("z", "domain.inflow"), settle::InputError);
}

}  // namespace test_open_faces
