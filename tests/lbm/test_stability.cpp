// Stability gain of the recursive regularised collision (Malaspinas 2015; Coreixas et al.
// 2017) close to tau = 1/2, on the doubly periodic shear layer of Minion & Brown 1997
// (doi:10.1006/jcph.1997.5810), the standard stress test of these papers:
//   u_x = U tanh(kappa (y/L - 1/4)) for y <= L/2, U tanh(kappa (3/4 - y/L)) above,
//   u_y = delta U sin(2 pi (x/L + 1/4)),  kappa = 80, delta = 0.05,
// under-resolved on purpose (L = 64 cells, the shear layer ~1 cell thick) at a very small
// viscosity. BGK and TRT blow up; the regularised model and the cumulant operator (Geier et al.
// 2015, doi:10.1016/j.camwa.2015.05.001) stay bounded, and so do BGK and TRT with the Smagorinsky
// subgrid model. They must also still be accurate at that tau: a resolved Taylor-Green vortex
// decays at 2 nu K.
#include <gtest/gtest.h>

#include <cmath>
#include <cstdio>
#include <numbers>

#include "lbm/lattice.hpp"
#include "lbm/solver.hpp"

namespace test_stability {

using namespace settle::lbm;

constexpr double kTau = 0.5 + 1.5e-4;  // nu = 5e-5: Re = U L / nu = 0.1 * 64 / 5e-5 = 128000
constexpr double kU = 0.1;             // Mach number U / cs = 0.17
constexpr int kL = 64;
constexpr int kSteps = 4000;  // ~6 convective times L/U

double kinetic_energy(const Solver& solver) {
  const auto rho = solver.density_field();
  const auto u = solver.velocity_field();
  double energy = 0.0;
  for (std::size_t n = 0; n < rho.size(); ++n) {
    energy += 0.5 * rho[n] * (u.x[n] * u.x[n] + u.y[n] * u.y[n] + u.z[n] * u.z[n]);
  }
  return energy;
}

struct RunSummary {
  double max_speed;     // largest |u| seen at the block ends (+inf once NaN)
  double energy_ratio;  // kinetic energy at the end / at the start
};

RunSummary shear_layer(CollisionKind collision, LatticeKind lattice, SubgridModel subgrid = SubgridModel::none) {
  SolverConfig cfg;
  cfg.lattice = lattice;
  cfg.collision = collision;
  cfg.subgrid = subgrid;
  cfg.nx = kL;
  cfg.ny = kL;
  cfg.nz = 1;  // quasi-2D: one periodic cell along z
  cfg.tau = kTau;
  auto solver = make_solver(cfg);
  solver->initialise([](int x, int y, int) {
    const double xs = (x + 0.5) / kL, ys = (y + 0.5) / kL;
    CellState s;
    s.velocity.x() = ys <= 0.5 ? kU * std::tanh(80.0 * (ys - 0.25)) : kU * std::tanh(80.0 * (0.75 - ys));
    s.velocity.y() = 0.05 * kU * std::sin(2.0 * std::numbers::pi * (xs + 0.25));
    return s;
  });
  const double e0 = kinetic_energy(*solver);
  RunSummary summary{0.0, 0.0};
  for (int done = 0; done < kSteps; done += 100) {
    solver->run(100);
    const auto u = solver->velocity_field();
    for (std::size_t n = 0; n < u.x.size(); ++n) {
      const double speed = std::sqrt(u.x[n] * u.x[n] + u.y[n] * u.y[n] + u.z[n] * u.z[n]);
      summary.max_speed = std::isfinite(speed) ? std::max(summary.max_speed, speed) : INFINITY;
    }
    if (summary.max_speed > 1.0) break;  // NaN or beyond the speed of sound: blown up
  }
  summary.energy_ratio = kinetic_energy(*solver) / e0;
  return summary;
}

TEST(LbmStability, ShearLayerNearHalfTauBlowsUpBgkAndTrtButNotRecursiveRegularizedOrCumulant) {
  const auto bgk = shear_layer(CollisionKind::bgk, LatticeKind::D3Q19);
  const auto trt = shear_layer(CollisionKind::trt, LatticeKind::D3Q19);
  const auto rr = shear_layer(CollisionKind::recursive_regularized, LatticeKind::D3Q19);
  const auto rr27 = shear_layer(CollisionKind::recursive_regularized, LatticeKind::D3Q27);
  const auto cumulant = shear_layer(CollisionKind::cumulant, LatticeKind::D3Q27);
  std::printf(
      "shear layer tau = 0.5 + 1.5e-4, U = %.2f, %d steps: max |u| / U: bgk %.3g, "
      "trt %.3g, rr D3Q19 %.3g (E/E0 %.4f), rr D3Q27 %.3g (E/E0 %.4f), cumulant D3Q27 %.3g (E/E0 %.4f)\n",
      kU, kSteps, bgk.max_speed / kU, trt.max_speed / kU, rr.max_speed / kU, rr.energy_ratio, rr27.max_speed / kU,
      rr27.energy_ratio, cumulant.max_speed / kU, cumulant.energy_ratio);
  // Blown up: NaN or |u| beyond the lattice speed of sound (0.58), i.e. > 5 U.
  EXPECT_GT(bgk.max_speed, 0.5);
  EXPECT_GT(trt.max_speed, 0.5);
  for (const auto& stable : {rr, rr27, cumulant}) {
    // Bounded: without forcing in a periodic box the kinetic energy can only decay (the
    // 1 % allows for the exchange with acoustic potential energy at Ma = 0.17), and no speed
    // may run away. The under-resolved roll-up overshoots U locally (~1.7 U measured, the
    // ~1-cell-thick shear layer rings); 2 U separates that from blow-up (> 5 U).
    EXPECT_LT(stable.energy_ratio, 1.01);
    EXPECT_LT(stable.max_speed, 2.0 * kU);
  }
}

TEST(LbmStability, ShearLayerNearHalfTauStaysBoundedUnderBgkAndTrtWithSmagorinsky) {
  // The same layer that blows up plain BGK and TRT above, with the Smagorinsky eddy viscosity at the
  // default C_S = 0.1: in the ~1-cell-thick layer |S| ~ U / dx makes nu_t ~ C_S^2 U ~ 1e-3, twenty
  // times nu0, and both stay bounded by the bounds of the regularised operator above (measured:
  // BGK 1.71 U, E/E0 0.905; TRT 1.57 U, E/E0 0.832: the eddy viscosity also dissipates more).
  for (const auto collision : {CollisionKind::bgk, CollisionKind::trt}) {
    const auto run = shear_layer(collision, LatticeKind::D3Q19, SubgridModel::smagorinsky);
    std::printf("shear layer + Smagorinsky C_S = %.2f: %s max |u| / U %.3g, E/E0 %.4f\n", kDefaultSmagorinskyConstant,
                to_string(collision).c_str(), run.max_speed / kU, run.energy_ratio);
    EXPECT_LT(run.energy_ratio, 1.01) << to_string(collision);
    EXPECT_LT(run.max_speed, 2.0 * kU) << to_string(collision);
  }
}

/// Relative error of the energy decay rate of a resolved Taylor-Green vortex (32 x 32 cells,
/// uniform along z) at the shear layer's tau: energy decays as exp(-2 nu K t), K = 2 (2 pi / 32)^2
/// (the mode's squared wavenumbers summed).
double decay_rate_error_at_the_same_tau(CollisionKind collision, LatticeKind lattice) {
  constexpr int n = 32;
  constexpr double u0 = 0.01;
  SolverConfig cfg;
  cfg.lattice = lattice;
  cfg.collision = collision;
  cfg.nx = n;
  cfg.ny = n;
  cfg.nz = 1;
  cfg.tau = kTau;
  auto solver = make_solver(cfg);
  const double k = 2.0 * std::numbers::pi / n;
  solver->initialise([&](int x, int y, int) {
    const double xa = k * (x + 0.5), xb = k * (y + 0.5);
    CellState s;
    s.velocity = Eigen::Vector3d(u0 * std::sin(xa) * std::cos(xb), -u0 * std::cos(xa) * std::sin(xb), 0.0);
    s.density = 1.0 + 0.25 * u0 * u0 * (std::cos(2 * xa) + std::cos(2 * xb)) / cs2;
    return s;
  });
  solver->run(1000);
  const double e0 = kinetic_energy(*solver);
  constexpr int span = 20000;
  solver->run(span);
  const double rate = std::log(e0 / kinetic_energy(*solver)) / span;
  const double exact = 2.0 * viscosity_from_tau(kTau) * 2.0 * k * k;
  std::printf("TGV 32^2 %s %s tau = 0.5 + 1.5e-4: rate %.4e, exact %.4e, error %.3e\n", to_string(collision).c_str(),
              to_string(lattice).c_str(), rate, exact, std::abs(rate / exact - 1.0));
  return rate / exact - 1.0;
}

// Tolerance 1 % (the bound of the 64^3 Taylor-Green test): the viscosity is second-order accurate in
// k dx = 0.2 (error a few 1e-3 at most) and the energy still falls 15 % over the fit, so
// the rate is well determined; a model that buys stability with extra shear dissipation
// (e.g. the bulk rate leaking into the shear part) would be off by O(1) at this tiny nu.
TEST(LbmStability, RecursiveRegularizedStillDecaysAtTheRightRateAtTheSameTau) {
  EXPECT_NEAR(decay_rate_error_at_the_same_tau(CollisionKind::recursive_regularized, LatticeKind::D3Q19), 0.0, 0.01);
}

TEST(LbmStability, CumulantStillDecaysAtTheRightRateAtTheSameTau) {
  EXPECT_NEAR(decay_rate_error_at_the_same_tau(CollisionKind::cumulant, LatticeKind::D3Q27), 0.0, 0.01);
}

}  // namespace test_stability
