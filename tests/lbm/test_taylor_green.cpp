// Decaying Taylor-Green vortex in a periodic box: a closed-form solution of the
// incompressible Navier-Stokes equations. In the plane of axes (a, b), with k = 2 pi / N,
//   u_a =  U sin(k x_a) cos(k x_b),  u_b = -U cos(k x_a) sin(k x_b),
//   p   = rho U^2 / 4 (cos 2k x_a + cos 2k x_b),
// uniform along the third axis. Velocity decays as exp(-nu (k_a^2 + k_b^2) t), the kinetic
// energy as exp(-2 nu K t) with K = k_a^2 + k_b^2 = 2 k^2 (the squared wavenumbers of the
// mode, summed).
#include <gtest/gtest.h>

#include <Eigen/Core>
#include <cmath>
#include <cstdio>
#include <numbers>

#include "lbm/lattice.hpp"
#include "lbm/solver.hpp"

namespace test_taylor_green {

using namespace settle::lbm;

/// Kinetic energy in the frame moving with the mean velocity (total momentum / total mass,
/// both conserved in a periodic box), i.e. the vortex's energy on a uniform background.
double kinetic_energy(const Solver& solver) {
  const auto rho = solver.density_field();
  const auto u = solver.velocity_field();
  double mass = 0.0;
  Eigen::Vector3d momentum = Eigen::Vector3d::Zero();
  for (std::size_t n = 0; n < rho.size(); ++n) {
    mass += rho[n];
    momentum += rho[n] * Eigen::Vector3d(u.x[n], u.y[n], u.z[n]);
  }
  const Eigen::Vector3d mean = momentum / mass;
  double energy = 0.0;
  for (std::size_t n = 0; n < rho.size(); ++n) {
    energy += 0.5 * rho[n] * (Eigen::Vector3d(u.x[n], u.y[n], u.z[n]) - mean).squaredNorm();
  }
  return energy;
}

struct DecayResult {
  double measured_rate;
  double exact_rate;
  double relative_error() const { return std::abs(measured_rate / exact_rate - 1.0); }
};

/// Energy decay rate of the vortex in the plane (axis_a, axis_b) of an N^3 box, fitted
/// between step t0 (after the initial equilibrium-start transient) and t1, carried by a uniform
/// `background` velocity.
DecayResult taylor_green(int n, LatticeKind lattice, CollisionKind collision, Precision precision, double tau,
                         int axis_a, int axis_b, int t0, int t1, double u0 = 0.02,
                         const Eigen::Vector3d& background = Eigen::Vector3d::Zero()) {
  SolverConfig cfg;
  cfg.lattice = lattice;
  cfg.collision = collision;
  cfg.precision = precision;
  cfg.nx = cfg.ny = cfg.nz = n;
  cfg.tau = tau;
  auto solver = make_solver(cfg);
  const double k = 2.0 * std::numbers::pi / n;
  solver->initialise([&](int x, int y, int z) {
    const double pos[3] = {x + 0.5, y + 0.5, z + 0.5};
    const double xa = k * pos[axis_a], xb = k * pos[axis_b];
    CellState state;
    state.velocity = background;
    state.velocity[axis_a] += u0 * std::sin(xa) * std::cos(xb);
    state.velocity[axis_b] -= u0 * std::cos(xa) * std::sin(xb);
    const double pressure = 0.25 * u0 * u0 * (std::cos(2 * xa) + std::cos(2 * xb));
    state.density = 1.0 + pressure / cs2;
    return state;
  });
  solver->run(t0);
  const double e0 = kinetic_energy(*solver);
  solver->run(t1 - t0);
  const double e1 = kinetic_energy(*solver);
  const double nu = viscosity_from_tau(tau);
  return {std::log(e0 / e1) / (t1 - t0), 2.0 * nu * 2.0 * k * k};
}

TEST(LbmTaylorGreen, TrtD3Q19EnergyDecayRateWithinOnePercentAt64Cubed) {
  // tau = 0.65 (nu = 0.05): the energy falls by exp(-1.2) over the fitted 300 steps.
  const auto r = taylor_green(64, LatticeKind::D3Q19, CollisionKind::trt, Precision::float64, 0.65, 0, 1, 50, 350);
  std::printf("TGV 64^3 D3Q19 TRT tau 0.65: rate %.6e, exact 2 nu K = %.6e, error %.3e\n", r.measured_rate,
              r.exact_rate, r.relative_error());
  // 1 %: LBM's viscosity is second-order accurate in k dx = 0.098 (error
  // ~1e-3) and the Mach-number error ~Ma^2 ~ 1e-3, so 1 % is a safe yet failing-capable bound
  // (a wrong tau-nu relation or forcing-free viscosity error shows up as several %).
  EXPECT_LT(r.relative_error(), 0.01);
}

struct Variant {
  LatticeKind lattice;
  CollisionKind collision;
  Precision precision;
  int axis_a, axis_b;
};

TEST(LbmTaylorGreen, EveryLatticeCollisionAndPlaneDecaysAtTheRightRateAt32Cubed) {
  // The mode is rotated into each coordinate plane so that every axis's streaming offsets
  // are exercised, and each lattice / collision / precision runs at least once.
  const Variant variants[] = {
      {LatticeKind::D3Q19, CollisionKind::bgk, Precision::float64, 1, 2},
      {LatticeKind::D3Q19, CollisionKind::recursive_regularized, Precision::float64, 2, 0},
      {LatticeKind::D3Q27, CollisionKind::trt, Precision::float64, 0, 1},
      {LatticeKind::D3Q27, CollisionKind::bgk, Precision::float32, 1, 2},
      {LatticeKind::D3Q27, CollisionKind::recursive_regularized, Precision::float32, 2, 0},
      {LatticeKind::D3Q19, CollisionKind::trt, Precision::float32, 0, 1},
      {LatticeKind::D3Q27, CollisionKind::cumulant, Precision::float64, 0, 1},
      {LatticeKind::D3Q27, CollisionKind::cumulant, Precision::float32, 1, 2},
  };
  for (const auto& v : variants) {
    const auto r = taylor_green(32, v.lattice, v.collision, v.precision, 0.65, v.axis_a, v.axis_b, 20, 170);
    std::printf("TGV 32^3 %s %s %s plane (%d,%d): rate %.6e, exact %.6e, error %.3e\n", to_string(v.lattice).c_str(),
                to_string(v.collision).c_str(), to_string(v.precision).c_str(), v.axis_a, v.axis_b, r.measured_rate,
                r.exact_rate, r.relative_error());
    // At 32 cells per wavelength the second-order dispersion error is 4x that at 64^3,
    // still a few 1e-3; 2 % bounds it with margin while a broken lattice, collision or
    // plane (wrong offsets) gives O(1) errors or blows up.
    EXPECT_LT(r.relative_error(), 0.02) << to_string(v.lattice) << " " << to_string(v.collision) << " "
                                        << to_string(v.precision);
  }
}

TEST(LbmTaylorGreen, CumulantDecayRateIsTheSameOnAUniformBackgroundFlow) {
  // The vortex of the test above carried through the box by a uniform velocity: a Galilean
  // invariant viscosity decays it at the same rate. D3Q27's third moments cannot carry the
  // Maxwellian's rho u_a^3, which adds 3 nu rho u_a^2 d_a u_a to the normal stresses; the cumulant
  // operator removes it (Geier et al. 2015, Appendix H).
  const auto r = taylor_green(32, LatticeKind::D3Q27, CollisionKind::cumulant, Precision::float64, 0.65, 0, 1, 20, 170,
                              0.02, Eigen::Vector3d(0.1, 0.06, 0.0));
  std::printf("TGV 32^3 D3Q27 cumulant on the background (0.1, 0.06, 0): rate %.6e, exact %.6e, error %.3e\n",
              r.measured_rate, r.exact_rate, r.relative_error());
  // 0.5 %, within the 2 % of the test above: at rest the error is 3.8e-4 (dispersion at 32 cells
  // per wavelength), and on this background the uncorrected defect costs 2-3 %: measured 3.1e-2
  // for the operator without its correction, 2.2e-2 for TRT and 3.1e-2 for the recursive
  // regularised operator on the same flow (docs/lbm.md, Tests).
  EXPECT_LT(r.relative_error(), 0.005);
}

}  // namespace test_taylor_green
