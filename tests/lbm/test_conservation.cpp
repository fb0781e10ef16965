// Conservation laws and walls: mass in a closed box, mixed boundaries at edges and
// corners, free-slip walls, and the exact Poiseuille profile in a duct whose side walls are
// free-slip (every edge and corner cell must carry the 1D parabola).
#include <gtest/gtest.h>

#include <cmath>
#include <cstdio>
#include <numbers>

#include "lbm/lattice.hpp"
#include "lbm/solver.hpp"
#include "steady.hpp"

namespace test_conservation {

using namespace settle::lbm;
using settle::lbm::testing::run_to_steady_state;

/// A smooth divergent-and-rotational flow with a density bump, no symmetry in the box.
CellState stirred(int x, int y, int z, int nx, int ny, int nz) {
  const double pi = std::numbers::pi;
  const double sx = (x + 0.5) / nx, sy = (y + 0.5) / ny, sz = (z + 0.5) / nz;
  CellState s;
  s.velocity = 0.05 * Eigen::Vector3d(std::sin(pi * sy) * std::cos(2 * pi * sz),
                                      std::sin(2 * pi * sx) * std::sin(pi * sz), std::cos(pi * sx) * std::sin(pi * sy));
  s.density = 1.0 + 0.01 * std::sin(2 * pi * sx + 1.0) * std::cos(pi * sy);
  return s;
}

double mass_drift(Precision precision, LatticeKind lattice, CollisionKind collision, std::array<Boundary, 3> walls,
                  int steps) {
  SolverConfig cfg;
  cfg.lattice = lattice;
  cfg.collision = collision;
  cfg.precision = precision;
  cfg.nx = 20;
  cfg.ny = 18;
  cfg.nz = 16;
  cfg.boundaries = walls;
  cfg.tau = 0.6;
  auto solver = make_solver(cfg);
  solver->initialise([&](int x, int y, int z) { return stirred(x, y, z, cfg.nx, cfg.ny, cfg.nz); });
  const double m0 = solver->total_mass();
  solver->run(steps);
  return std::abs(solver->total_mass() - m0) / m0;
}

TEST(LbmConservation, ClosedNoSlipBoxConservesMassToRoundOffDouble) {
  const std::array<Boundary, 3> box{Boundary::no_slip, Boundary::no_slip, Boundary::no_slip};
  const double drift = mass_drift(Precision::float64, LatticeKind::D3Q19, CollisionKind::trt, box, 1000);
  std::printf("closed box, double, 1000 steps: relative mass drift %.2e\n", drift);
  // Collision conserves mass per cell to a few ulps of f - w (~1e-3 here, so ~1e-19 per
  // cell and step) and bounce-back moves populations without arithmetic: a random walk
  // over 5760 cells x 1000 steps stays ~1e-17 relative to the mass 5760. 1e-13 leaves a
  // huge margin yet catches a single lost population (w / 5760 ~ 1e-5).
  EXPECT_LT(drift, 1e-13);
}

TEST(LbmConservation, ClosedNoSlipBoxConservesMassToRoundOffFloat) {
  const std::array<Boundary, 3> box{Boundary::no_slip, Boundary::no_slip, Boundary::no_slip};
  const double drift = mass_drift(Precision::float32, LatticeKind::D3Q19, CollisionKind::trt, box, 1000);
  std::printf("closed box, float, 1000 steps: relative mass drift %.2e\n", drift);
  // Each stored f - w (~5e-3) is rounded to 2^-24 relative, ~3e-10 absolute, per value
  // and step: a random walk over 19 x 5760 values x 1000 steps gives ~3e-10 x 1e4 = 3e-6
  // absolute, 5e-10 relative to the mass 5760. 1e-7 relative allows for systematic rounding
  // bias (200x) and still catches a lost population (~1e-5).
  EXPECT_LT(drift, 1e-7);
}

TEST(LbmConservation, MixedBoundariesConserveMassForEveryLatticeAndCollision) {
  // Channel no-slip in z, periodic x, free-slip y: edges and corners where different kinds
  // meet, then the same with the kinds permuted over the axes.
  const std::array<std::array<Boundary, 3>, 3> setups{{
      {Boundary::periodic, Boundary::free_slip, Boundary::no_slip},
      {Boundary::free_slip, Boundary::no_slip, Boundary::periodic},
      {Boundary::no_slip, Boundary::periodic, Boundary::free_slip},
  }};
  for (const auto& walls : setups) {
    for (const auto lattice : {LatticeKind::D3Q19, LatticeKind::D3Q27}) {
      for (const auto collision :
           {CollisionKind::bgk, CollisionKind::trt, CollisionKind::recursive_regularized, CollisionKind::cumulant}) {
        if (collision == CollisionKind::cumulant && lattice != LatticeKind::D3Q27) continue;  // D3Q27 only
        const double drift = mass_drift(Precision::float64, lattice, collision, walls, 200);
        // Same round-off argument as the closed box, fewer steps.
        EXPECT_LT(drift, 1e-13) << to_string(lattice) << " " << to_string(collision) << " " << to_string(walls[0])
                                << "/" << to_string(walls[1]) << "/" << to_string(walls[2]);
      }
    }
  }
}

TEST(LbmConservation, FluidAtRestUnderGravityInMixedChannelStaysAtRest) {
  // Gravity-like force towards a no-slip floor (z), periodic x, free-slip y: the discrete
  // hydrostatic state. Started at rest with uniform density, pressure waves form and are
  // damped; the fluid must come back to rest with the density gradient rho' = F / cs^2
  // balancing the force, at every cell including the edges where free-slip meets no-slip.
  SolverConfig cfg;
  cfg.nx = 4;
  cfg.ny = 6;
  cfg.nz = 12;
  cfg.boundaries = {Boundary::periodic, Boundary::free_slip, Boundary::no_slip};
  cfg.tau = 1.0;
  const double g = 1e-5;
  cfg.body_force = Eigen::Vector3d(0.0, 0.0, -g);
  auto solver = make_solver(cfg);
  solver->initialise([](int, int, int) { return CellState{}; });
  const double m0 = solver->total_mass();
  run_to_steady_state(*solver, 1e-18, 200000);
  double max_speed = 0.0;
  for (int z = 0; z < cfg.nz; ++z) {
    for (int y = 0; y < cfg.ny; ++y) {
      for (int x = 0; x < cfg.nx; ++x) max_speed = std::max(max_speed, solver->cell_velocity(x, y, z).norm());
    }
  }
  const double gradient = (solver->cell_density(0, 0, cfg.nz - 2) - solver->cell_density(0, 0, 1)) / (cfg.nz - 3);
  std::printf("hydrostatic channel: max |u| %.2e (force %.0e), density gradient %.6e (expected %.6e)\n", max_speed, g,
              gradient, -g / cs2);
  // At rest means no velocity beyond round-off of the O(1e-5) force terms: 1e-14 is 1e-9 of
  // the force; a wrong half-force correction or an unbalanced wall gives O(g) = 1e-5.
  EXPECT_LT(max_speed, 1e-14);
  // Hydrostatic balance d rho / dz = rho F / cs^2 (rho = 1 + O(1e-4)): 1e-3 relative.
  EXPECT_NEAR(gradient, -g / cs2, 1e-3 * g / cs2);
  EXPECT_NEAR(solver->total_mass(), m0, 1e-12 * m0);  // round-off, as in the closed box
}

TEST(LbmFreeSlip, UniformFlowParallelToFreeSlipWallsStaysUniform) {
  for (const auto lattice : {LatticeKind::D3Q19, LatticeKind::D3Q27}) {
    SolverConfig cfg;
    cfg.lattice = lattice;
    cfg.nx = 8;
    cfg.ny = 7;
    cfg.nz = 6;
    cfg.boundaries = {Boundary::periodic, Boundary::free_slip, Boundary::free_slip};
    cfg.tau = 0.7;
    auto solver = make_solver(cfg);
    const Eigen::Vector3d u0(0.05, 0.0, 0.0);  // along x, tangent to the y and z walls
    solver->initialise([&](int, int, int) { return CellState{1.0, u0}; });
    solver->run(301);  // odd: ends at the other AA parity
    double worst = 0.0, worst_rho = 0.0;
    for (int z = 0; z < cfg.nz; ++z) {
      for (int y = 0; y < cfg.ny; ++y) {
        for (int x = 0; x < cfg.nx; ++x) {
          const auto s = solver->cell_state(x, y, z);
          worst = std::max(worst, (s.velocity - u0).cwiseAbs().maxCoeff());
          worst_rho = std::max(worst_rho, std::abs(s.density - 1.0));
        }
      }
    }
    std::printf("free-slip %s: max |u - u0| %.2e, max |rho - 1| %.2e after 301 steps\n", to_string(lattice).c_str(),
                worst, worst_rho);
    // Specular reflection maps the uniform equilibrium onto itself, so only round-off of
    // O(0.05) values remains (ulp 7e-18); 1e-15 is ~100 ulps. A no-slip-like wall would slow
    // the wall cells by O(0.01) within these steps.
    EXPECT_LT(worst, 1e-15) << to_string(lattice);
    EXPECT_LT(worst_rho, 1e-15) << to_string(lattice);
  }
}

TEST(LbmFreeSlip, DuctWithFreeSlipSidesCarriesTheExactParabolaInEveryCell) {
  // Force along x, no-slip floor and ceiling (z), free-slip side walls (y): the free-slip
  // walls must not disturb the plane Poiseuille profile, which TRT with Lambda = 3/16
  // reproduces to round-off (see test_poiseuille), including the edge cells where a
  // free-slip wall meets a no-slip wall.
  SolverConfig cfg;
  cfg.nx = 2;
  cfg.ny = 5;
  cfg.nz = 8;
  cfg.boundaries = {Boundary::periodic, Boundary::free_slip, Boundary::no_slip};
  cfg.tau = 0.9;
  const double nu = viscosity_from_tau(cfg.tau);
  const double force = 1e-5;
  cfg.body_force = Eigen::Vector3d(force, 0.0, 0.0);
  auto solver = make_solver(cfg);
  solver->initialise([](int, int, int) { return CellState{}; });
  run_to_steady_state(*solver, 1e-17, 200000);
  double worst = 0.0, peak = 0.0;
  for (int z = 0; z < cfg.nz; ++z) {
    const double zc = z + 0.5;
    const double exact = force / (2.0 * nu) * zc * (cfg.nz - zc);
    peak = std::max(peak, exact);
    for (int y = 0; y < cfg.ny; ++y) {
      for (int x = 0; x < cfg.nx; ++x) {
        const Eigen::Vector3d u = solver->cell_velocity(x, y, z);
        worst = std::max({worst, std::abs(u.x() - exact), std::abs(u.y()), std::abs(u.z())});
      }
    }
  }
  std::printf("free-slip duct: max deviation from the parabola %.2e of u_max\n", worst / peak);
  // Round-off of the steady state (as in test_poiseuille): 1e-11 relative.
  EXPECT_LT(worst / peak, 1e-11);
}

}  // namespace test_conservation
