#pragma once
// A sphere oscillating along x in fluid at rest, u(t) = U0 sin(omega t), against Stokes' exact
// force on an oscillating sphere (G. G. Stokes 1851, Trans. Camb. Phil. Soc. 9, 8; Landau and
// Lifshitz, Fluid Mechanics, 2nd ed. 1987, section 24, problem 5):
//     F = -6 pi mu a (1 + a / delta) u - 3 pi a^2 rho delta (1 + 2 a / (9 delta)) du/dt,
// delta = sqrt(2 nu / omega) the Stokes layer. The first term is the dissipative part (in phase
// with u), the second the inertial part: added mass (half the displaced fluid's, the limit
// delta -> 0) plus the quadrature of the history force. Valid to first order in X0 / a, the
// amplitude of the motion over the radius (the convective term's share).
//
// The control this gives (docs/validation.md, "A sphere oscillating in fluid at rest"): a body
// that moves through the lattice, covering and uncovering cells, feels the force of a moving body
// in an unsteady flow, apart from any wake. A free sphere's path oscillation (Uhlmann and Dusek's
// case C) is this force's response to the sideways motion plus the wake's; the wake alone is
// checked by the fixed sphere (Johnson and Patel).
//
// Set-up: periodic_sphere_setup's lattice-like units (dx = dt = 1 m, s; rho = 1), a periodic
// cube, the body towed (SimulationSetup::towed_velocity_si) in a window that stays put. The
// velocity starts from zero, so the start is not impulsive; the first periods are left out.
#include <cmath>
#include <cstdint>
#include <cstdio>
#include <numbers>

#include "periodic_sphere.hpp"

namespace settle::coupling::testing {

struct OscillatingSphereOptions {
  double cells_per_diameter = 12.0;
  double radius_over_stokes_layer = 2.0;  ///< a / delta; fixes omega for the given tau
  double amplitude_cells = 1.0;           ///< X0
  double tau = 0.6;
  int box_cells = 48;
  int skipped_periods = 2;
  int measured_periods = 3;
  CouplingKind coupling = CouplingKind::momentum_exchange;
  lbm::WallRule wall_rule = lbm::WallRule::bouzidi;
  lbm::CollisionKind collision = lbm::CollisionKind::trt;
};

struct OscillatingSphereResult {
  double dissipative_ratio = 0.0;  ///< measured in-phase coefficient / Stokes' 6 pi mu a (1 + a/delta)
  double inertial_ratio = 0.0;     ///< measured quadrature coefficient / Stokes' 3 pi a^2 rho delta (1 + 2a/(9 delta))
  double period_steps = 0.0;
  double solid_fraction = 0.0;
  std::int64_t steps = 0;
};

inline OscillatingSphereResult run_oscillating_sphere(const OscillatingSphereOptions& o) {
  PeriodicSphereOptions p;
  p.cells_per_diameter = o.cells_per_diameter;
  p.box_cells = o.box_cells;
  p.tau = o.tau;
  p.coupling = o.coupling;
  p.wall_rule = o.wall_rule;
  SimulationSetup s = periodic_sphere_setup(p);
  s.collision = o.collision;
  const double a = 0.5 * o.cells_per_diameter;
  const double nu = (o.tau - 0.5) / 3.0;
  const double delta = a / o.radius_over_stokes_layer;
  const double omega = 2.0 * nu / (delta * delta);
  const double u0 = o.amplitude_cells * omega;
  s.motion = body::MotionKind::towed;
  s.towed_velocity_si = [u0, omega](double t) { return Eigen::Vector3d(u0 * std::sin(omega * t), 0.0, 0.0); };
  s.max_lattice_velocity = 2.0 * u0;
  const double period = 2.0 * std::numbers::pi / omega;
  const auto skipped = static_cast<std::int64_t>(std::llround(o.skipped_periods * period));
  const auto measured = static_cast<std::int64_t>(std::llround(o.measured_periods * period));
  s.end_time_si = static_cast<double>(skipped + measured + 1);

  Simulation sim(s);
  // Project the force on u and du/dt over whole periods: the two are orthogonal there, and a
  // constant (the mean streaming's) or the second harmonic (the convective term's) drops out.
  double force_u = 0.0, u_u = 0.0, force_du = 0.0, du_du = 0.0;
  for (std::int64_t n = 0; n < skipped + measured; ++n) {
    // The step moves the body with its velocity at the step's start, the wall velocity the
    // bounce-back sees: the force belongs to that time.
    const double t = static_cast<double>(n);
    sim.step();
    if (n < skipped) continue;
    const double u = u0 * std::sin(omega * t);
    const double du = u0 * omega * std::cos(omega * t);
    const double f = sim.last_step().hydrodynamic.force_si.x();
    force_u += f * u, u_u += u * u;
    force_du += f * du, du_du += du * du;
  }
  const double mu = nu;  // rho = 1
  const double dissipative_stokes = 6.0 * std::numbers::pi * mu * a * (1.0 + a / delta);
  const double inertial_stokes = 3.0 * std::numbers::pi * a * a * delta * (1.0 + 2.0 * a / (9.0 * delta));
  OscillatingSphereResult r;
  r.dissipative_ratio = -force_u / u_u / dissipative_stokes;
  r.inertial_ratio = -force_du / du_du / inertial_stokes;
  r.period_steps = period;
  r.solid_fraction = std::numbers::pi / 6.0 * std::pow(o.cells_per_diameter / o.box_cells, 3);
  r.steps = sim.steps();
  return r;
}

inline OscillatingSphereResult run_oscillating_sphere_printed(const OscillatingSphereOptions& o) {
  const OscillatingSphereResult r = run_oscillating_sphere(o);
  std::printf(
      "%s, d = %g cells, a/delta = %g, X0 = %g cells, tau %.3f, box %d (phi %.4f), period %.0f steps: "
      "dissipative %.4f (%+.2f%%), inertial %.4f (%+.2f%%) of Stokes\n",
      to_string(o.coupling).c_str(), o.cells_per_diameter, o.radius_over_stokes_layer, o.amplitude_cells, o.tau,
      o.box_cells, r.solid_fraction, r.period_steps, r.dissipative_ratio, 100.0 * (r.dissipative_ratio - 1.0),
      r.inertial_ratio, 100.0 * (r.inertial_ratio - 1.0));
  std::fflush(stdout);
  return r;
}

}  // namespace settle::coupling::testing
