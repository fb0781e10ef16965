// The two-level refined lattice (lbm/refined_lattice.hpp): a uniform state stays uniform, mass is
// conserved to round-off, a force-driven channel reaches the parabola, and a shear wave decays at
// the rate of the one physical viscosity, with the fine box in the middle of each. docs/lbm.md,
// "Grid refinement (first step: two static levels, no body)", lists the figures.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <numbers>

#include "lbm/refined_lattice.hpp"
#include "lbm/solver.hpp"
#include "steady.hpp"

namespace test_refined_lattice {

using namespace settle::lbm::refinement;

/// Calls f(moments, x, y, z, volume) for every cell of both levels, positions and volumes in coarse
/// units.
template <class F>
void for_each_cell(const RefinedLattice& lattice, F&& f) {
  const auto& n = lattice.config().coarse_cells;
  for (int z = 0; z < n[2]; ++z)
    for (int y = 0; y < n[1]; ++y)
      for (int x = 0; x < n[0]; ++x)
        if (!lattice.covered(x, y, z)) f(lattice.coarse_moments(x, y, z), x + 0.5, y + 0.5, z + 0.5, 1.0);
  const auto m = lattice.fine_cells();
  const auto& lo = lattice.config().fine_box.lo;
  for (int c = 0; c < m[2]; ++c)
    for (int b = 0; b < m[1]; ++b)
      for (int a = 0; a < m[0]; ++a)
        f(lattice.fine_moments(a, b, c), lo[0] + 0.5 * (a + 0.5), lo[1] + 0.5 * (b + 0.5), lo[2] + 0.5 * (c + 0.5),
          0.125);
}

TEST(LbmRefinedLattice, UniformFlowStaysUniform) {
  // A uniform state is a fixed point of the scheme only if the explosion, the shares phi and the
  // coalescence fit together at every face, edge and corner of the box: any misplaced or missing
  // population shows up as an O(u) = O(1e-2) jump within one step.
  const std::array<double, 3> u0 = {0.05, -0.03, 0.02};
  for (const bool rescale : {true, false}) {
    RefinedLatticeConfig cfg;
    cfg.coarse_cells = {12, 12, 12};
    cfg.fine_box = {{4, 3, 5}, {8, 9, 10}};
    cfg.rescale_non_equilibrium = rescale;
    RefinedLattice lattice(cfg);
    lattice.initialise([&](double, double, double) { return CellMoments{1.0, u0}; });
    for (int s = 0; s < 1000; ++s) lattice.step();
    double worst = 0.0;
    for_each_cell(lattice, [&](const CellMoments& m, double, double, double, double) {
      worst = std::max(worst, std::abs(m.rho - 1.0));
      for (int d = 0; d < 3; ++d) worst = std::max(worst, std::abs(m.u[d] - u0[d]));
    });
    std::printf("uniform flow, rescale %d: max |rho - 1|, |u - u0| after 1000 coarse steps %.2e\n", rescale, worst);
    // Round-off: each step rounds populations of O(0.1) at ~1e-17, and 1000 steps accumulate
    // ~1e-14 at most; 1e-12 keeps a margin and is 10 orders below an interface defect.
    EXPECT_LT(worst, 1e-12) << "rescale " << rescale;
  }
}

TEST(LbmRefinedLattice, MassIsConservedToRoundOff) {
  // A non-uniform density and velocity field crossing every part of the box's boundary, over
  // 5000 coarse = 1e4 fine steps, with and without the non-equilibrium rescaling.
  for (const bool rescale : {true, false}) {
    RefinedLatticeConfig cfg;
    cfg.coarse_cells = {12, 12, 12};
    cfg.fine_box = {{3, 4, 3}, {9, 8, 10}};
    cfg.tau_coarse = 0.7;
    cfg.rescale_non_equilibrium = rescale;
    RefinedLattice lattice(cfg);
    const double k = 2.0 * std::numbers::pi / 12.0;
    lattice.initialise([&](double x, double y, double z) {
      return CellMoments{1.0 + 0.02 * std::sin(k * x) * std::cos(k * y) + 0.01 * std::sin(k * z),
                         {0.03 * std::sin(k * y), 0.02 * std::cos(k * z), 0.01 * std::sin(k * x)}};
    });
    const double initial = lattice.mass_deviation();
    double drift = 0.0;
    for (int s = 1; s <= 5000; ++s) {
      lattice.step();
      if (s % 50 == 0) drift = std::max(drift, std::abs(lattice.mass_deviation() - initial));
    }
    std::printf("mass, rescale %d: initial deviation %.6e, max drift over 1e4 fine steps %.2e (of %d cell volumes)\n",
                rescale, initial, drift, 12 * 12 * 12);
    // Each step rounds ~3500 cell sums of O(0.01) populations at ~1e-18 each; a random walk over
    // 5000 steps gives ~1e-13. 1e-11 of 1728 cell volumes (6e-15 relative) has margin, while a
    // population counted twice or lost at an edge or corner of the box drifts by ~1e-4 per step.
    EXPECT_LT(drift, 1e-11) << "rescale " << rescale;
  }
}

struct ChannelError {
  double max_relative = 0.0;       // max over all cells of |u - exact| / u_max
  double max_relative_near = 0.0;  // the same over the cells within one coarse cell of the box's x, y faces
  double max_relative_far = 0.0;   // the other cells
};

// The channel of both tests: H = `height` coarse cells, BGK with tau - 1/2 = sqrt(3/16) (Lambda =
// (tau - 1/2)^2 = 3/16 for BGK): on a uniform grid the half-way walls sit exactly at mid-link and
// Guo's forcing is exact for the quadratic profile, so the parabola comes out to round-off
// (Ginzburg, Verhaeghe and d'Humieres 2008, doi:10.4208/cicp.2008.v3.p427) and what is left with
// the fine box is the interface's error.
constexpr double kChannelTau = 0.5 + 0.4330127018922193;  // 1/2 + sqrt(3/16)
constexpr double kChannelUMax = 0.01;
double channel_force(int height) { return 8.0 * ((kChannelTau - 0.5) / 3.0) * kChannelUMax / (height * height); }
double channel_exact(int height, double y) {
  return channel_force(height) / (2.0 * (kChannelTau - 0.5) / 3.0) * y * (height - y);
}

/// Walls at y = 0 and H (half-way bounce-back, coarse level), periodic in x and z; the fine box in
/// the middle half of the channel, away from the walls: x in [H/8, 3H/8) of H/2, y in [H/4, 3H/4),
/// z in [1, 3) of 4. Started from the closed form, run until a block of 200 coarse steps changes
/// the volume-weighted sum of u_x by less than 1e-8 of it: the error left is that change times the
/// slowest mode's decay time over the block (H^2 / (pi^2 nu) / 200 < 4 at H = 32), < 1e-7 of u_max.
ChannelError run_refined_channel(int height) {
  RefinedLatticeConfig cfg;
  cfg.coarse_cells = {height / 2, height, 4};
  cfg.fine_box = {{height / 8, height / 4, 1}, {3 * height / 8, 3 * height / 4, 3}};
  cfg.walls_y = true;
  cfg.tau_coarse = kChannelTau;
  cfg.force_coarse = {channel_force(height), 0.0, 0.0};
  RefinedLattice lattice(cfg);
  lattice.initialise([&](double, double y, double) { return CellMoments{1.0, {channel_exact(height, y), 0.0, 0.0}}; });
  const auto flow_sum = [&] {
    double sum = 0.0;
    for_each_cell(lattice, [&](const CellMoments& m, double, double, double, double v) { sum += v * m.u[0]; });
    return sum;
  };
  double previous = flow_sum();
  for (int block = 0; block < 1000; ++block) {
    for (int s = 0; s < 200; ++s) lattice.step();
    const double now = flow_sum();
    if (std::abs(now - previous) < 1e-8 * std::abs(now)) break;
    previous = now;
  }
  ChannelError e;
  const auto& box = cfg.fine_box;
  // Near: within one coarse cell of the box's x or y faces. The z faces are left out of the
  // classification: the domain is 4 cells thick, so every cell is within one cell of them.
  for_each_cell(lattice, [&](const CellMoments& m, double x, double y, double, double) {
    const double err = std::abs(m.u[0] - channel_exact(height, y)) / kChannelUMax;
    const auto near_face = [](double p, int lo, int hi) { return std::abs(p - lo) < 1.0 || std::abs(p - hi) < 1.0; };
    const bool near = near_face(x, box.lo[0], box.hi[0]) || near_face(y, box.lo[1], box.hi[1]);
    e.max_relative = std::max(e.max_relative, err);
    double& part = near ? e.max_relative_near : e.max_relative_far;
    part = std::max(part, err);
  });
  return e;
}

/// The same channel on the uniform coarse grid (the AA solver, BGK), one cell thick in x and z.
double uniform_channel_error(int height) {
  using namespace settle::lbm;
  SolverConfig cfg;
  cfg.collision = CollisionKind::bgk;
  cfg.precision = Precision::float64;
  cfg.nx = 1;
  cfg.ny = height;
  cfg.nz = 1;
  cfg.boundaries = {Boundary::periodic, Boundary::no_slip, Boundary::periodic};
  cfg.tau = kChannelTau;
  cfg.body_force = Eigen::Vector3d(channel_force(height), 0.0, 0.0);
  auto solver = make_solver(cfg);
  solver->initialise([](int, int, int) { return CellState{}; });
  // Steady as in test_poiseuille.cpp: a 200-step block changes u by < 1e-16.
  settle::lbm::testing::run_to_steady_state(*solver, 1e-16, 400 * static_cast<std::int64_t>(height * height / 0.15));
  double worst = 0.0;
  for (int j = 0; j < height; ++j)
    worst = std::max(worst, std::abs(solver->cell_velocity(0, j, 0).x() - channel_exact(height, j + 0.5)));
  return worst / kChannelUMax;
}

TEST(LbmRefinedLattice, PoiseuilleChannelAcrossTheFineBox) {
  const double uniform = uniform_channel_error(16);
  const auto coarse = run_refined_channel(16);
  const auto fine = run_refined_channel(32);
  const double order_near = std::log2(coarse.max_relative_near / fine.max_relative_near);
  const double order_far = std::log2(coarse.max_relative_far / fine.max_relative_far);
  std::printf(
      "Poiseuille, max |u - exact| / u_max: uniform coarse grid H = 16: %.2e; with the fine box H = 16: %.3e "
      "(near the box %.3e, elsewhere %.3e), H = 32: %.3e (near %.3e, elsewhere %.3e); order near %.2f, "
      "elsewhere %.2f\n",
      uniform, coarse.max_relative, coarse.max_relative_near, coarse.max_relative_far, fine.max_relative,
      fine.max_relative_near, fine.max_relative_far, order_near, order_far);
  // Without the box the parabola is exact to round-off (Lambda = 3/16): all the error below is the
  // interface's.
  EXPECT_LT(uniform, 1e-10);
  // Every cell of both levels within 1% of u_max at H = 16 (measured 0.38%): the homogeneous
  // (zeroth-order) explosion gives 1.8% and the rescaled non-equilibrium 9% (docs/lbm.md).
  EXPECT_LT(coarse.max_relative, 1e-2);
  // The interface is first order (the fine level's ghost values are the coarse state of the start
  // of the coarse step for both fine steps, and its non-equilibrium part is the coarse level's):
  // away from the box the error halves from H = 16 to 32 (measured order 1.03; 0.8 allows for the
  // two-point estimate). Next to the box it converges more slowly (measured 0.74); the bound
  // asserts convergence there, not first order (docs/lbm.md, "Grid refinement").
  EXPECT_GT(order_far, 0.8);
  EXPECT_GT(order_near, 0.5);
}

TEST(LbmRefinedLattice, ShearWaveDecaysAtTheOneViscosity) {
  // u_x = U sin(k y), k = 2 pi / L, in a periodic box; the fine box spans y in [L/4, 3L/4), the
  // wave's two extrema and the zero crossing between them, and part of x and z. The amplitude (the
  // volume-weighted projection on sin(k y) over both levels) decays as exp(-nu k^2 t) if both
  // levels carry the viscosity nu = cs^2 (tau_c - 1/2).
  const int length = 32;
  RefinedLatticeConfig cfg;
  cfg.coarse_cells = {16, length, 8};
  cfg.fine_box = {{4, length / 4, 2}, {12, 3 * length / 4, 6}};
  cfg.tau_coarse = 0.8;
  const double k = 2.0 * std::numbers::pi / length, amplitude = 0.01;
  const double nu = (cfg.tau_coarse - 0.5) / 3.0;
  RefinedLattice lattice(cfg);
  lattice.initialise([&](double, double y, double) {
    return CellMoments{1.0, {amplitude * std::sin(k * y), 0.0, 0.0}};
  });
  const auto projection = [&] {
    double along = 0.0, norm = 0.0;
    for_each_cell(lattice, [&](const CellMoments& m, double, double y, double, double volume) {
      along += volume * m.u[0] * std::sin(k * y);
      norm += volume * std::sin(k * y) * std::sin(k * y);
    });
    return along / norm;
  };
  // From t = 100 (after the initial layer of the equilibrium start, a few tau) to t = 600, two
  // e-foldings: the rate is measured to ~1e-6 by the projection's round-off.
  const int start = 100, end = 600;
  for (int s = 0; s < start; ++s) lattice.step();
  const double first = projection();
  for (int s = start; s < end; ++s) lattice.step();
  const double last = projection();
  const double rate = std::log(first / last) / (end - start);
  const double expected = nu * k * k;
  std::printf("shear wave L = %d, tau_c = %.2f: decay rate %.6e per coarse step, nu k^2 = %.6e, ratio - 1 = %.2e\n",
              length, cfg.tau_coarse, rate, expected, rate / expected - 1.0);
  // 1% (issue 71): the lattice's own O((k dx)^2) dispersion at k dx = 0.2 is ~1e-3 (BGK), a level
  // with twice or half the viscosity would be off by tens of per cent.
  EXPECT_NEAR(rate / expected, 1.0, 0.01);
}

}  // namespace test_refined_lattice
