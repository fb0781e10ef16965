#pragma once
// Shared set-up of the periodic-sphere-array drag check (test_periodic_sphere.cpp, CI-sized,
// and validation_periodic_sphere.cpp): a fixed sphere in a periodic cubic box, Stokes flow
// driven by a uniform body force on the fluid, compared with Sangani and Acrivos 1982
// (Int. J. Multiphase Flow 8, 343, doi:10.1016/0301-9322(82)90047-7), eq. 60 and Table 1 for the
// simple cubic array, and with Zick and Homsy 1982 (J. Fluid Mech. 115, 13,
// doi:10.1017/S0022112082000627), as stored in the project's shared validation/reference-data.json.
// The same box also hosts the rotating-sphere torque check (run_rotating_sphere below;
// test_rotating_sphere.cpp and validation_rotating_sphere.cpp).
//
// Units: the SI case is written in lattice-like units (d = cells_per_diameter metres, rho = 1,
// nu = 1/6 m^2/s with tau = 1), so dx = dt = 1 and the numbers read directly in lattice units.
#include <algorithm>
#include <array>
#include <cmath>
#include <cstdint>
#include <cstdio>
#include <memory>
#include <numbers>

#include "body/shape_factory.hpp"
#include "coupling/simulation.hpp"
#include "support/default_setup.hpp"

namespace settle::coupling::testing {

/// Sangani and Acrivos 1982 series for the simple cubic array, K = sum_s q_s chi^s with
/// chi = d / L (reference-data.json, periodic_sphere_array_SC.SanganiAcrivos1982_SC_series).
inline double sangani_acrivos_k(double chi) {
  static constexpr std::array<double, 31> q{1.0,      1.418649, 2.012564,   2.331523,  2.564809,   2.584787,  2.873609,
                                            3.340163, 3.536763, 3.504092,   3.253622,  2.689757,   2.037769,  1.809341,
                                            1.877347, 1.534685, 0.9034708,  0.2857896, -0.5512626, -1.278724, 1.01335,
                                            5.492491, 4.615388, -0.5736023, -2.865924, -4.709215,  -6.870076, 0.1455304,
                                            12.51891, 9.742811, -5.566269};
  double k = 0.0, power = 1.0;
  for (double qs : q) {
    k += qs * power;
    power *= chi;
  }
  return k;
}

struct PeriodicSphereResult {
  double k = 0.0;            ///< F / (6 pi mu a U), U the superficial velocity
  double k_reference = 0.0;  ///< Sangani-Acrivos at chi = d / L
  double solid_fraction = 0.0;
  double reynolds = 0.0;              ///< U d / nu
  double last_relative_change = 0.0;  ///< of K over the last check interval (steady state)
  std::int64_t steps = 0;
  double slip_max = 0.0;  ///< largest marker slip after forcing / U
};

struct PeriodicSphereOptions {
  double cells_per_diameter = 16.0;
  int box_cells = 32;
  double tau = 1.0;
  double retraction = settle::test::default_setup().marker_retraction_cells;  ///< the default of settle run
  int forcing_iterations = 3;
  bool interior_markers = false;
  ibm::DeltaKernel kernel = ibm::DeltaKernel::Roma3;
  CouplingKind coupling = CouplingKind::immersed_boundary;
  lbm::WallRule wall_rule = lbm::WallRule::bouzidi;
  lbm::LatticeKind lattice = lbm::LatticeKind::D3Q19;
  std::int64_t max_steps = 20000;
  double steady_tolerance = 1e-6;  ///< relative change of K per check interval to stop
};

/// A sphere at the centre of a periodic cube in lattice-like units (file comment), no gravity,
/// no body force, motion fixed; callers set the driving.
inline SimulationSetup periodic_sphere_setup(const PeriodicSphereOptions& o) {
  const double d = o.cells_per_diameter;  // metres = cells (dx = 1)
  SimulationSetup s = settle::test::default_setup();
  body::ShapeSpec spec;
  spec.shape = "sphere";
  spec.diameter = d;
  s.shape = std::shared_ptr<const body::Shape>(body::make_shape(spec));
  s.motion = body::MotionKind::fixed;
  s.particle_density_si = 2.0;
  s.fluid_density_si = 1.0;
  s.dynamic_viscosity_si = (o.tau - 0.5) / 3.0;
  s.gravity_si = Eigen::Vector3d::Zero();
  const double box = o.box_cells;
  s.domain_size_si = Eigen::Vector3d::Constant(box);
  s.boundaries = {lbm::Boundary::periodic, lbm::Boundary::periodic, lbm::Boundary::periodic};
  s.initial.position_si = Eigen::Vector3d::Constant(0.5 * box);
  s.cells_per_diameter = o.cells_per_diameter;
  s.tau = o.tau;
  s.marker_retraction_cells = o.retraction;
  s.interior_markers = o.interior_markers;
  s.forcing_iterations = o.forcing_iterations;
  s.kernel = o.kernel;
  s.coupling = o.coupling;
  s.wall_rule = o.wall_rule;
  s.lattice = o.lattice;
  s.end_time_si = 1.0;
  return s;
}

/// The check interval of the steady-state tests: the slowest decaying Stokes mode of the box
/// relaxes as exp(-4 pi^2 nu t / L^2); a tenth of that time (at least 20 steps).
inline std::int64_t steady_check_interval(double box_cells, double nu) {
  return static_cast<std::int64_t>(
      std::max(20.0, 0.1 * box_cells * box_cells / (4.0 * std::numbers::pi * std::numbers::pi * nu)));
}

inline PeriodicSphereResult run_periodic_sphere(const PeriodicSphereOptions& o) {
  const double d = o.cells_per_diameter;  // metres = cells (dx = 1)
  const double nu = (o.tau - 0.5) / 3.0;
  SimulationSetup s = periodic_sphere_setup(o);
  const double box = o.box_cells;
  // Creeping flow: a force density giving U ~ 1e-4 (Re ~ 1e-2) with the Stokes drag of the
  // isolated sphere; the hindrance of the array only lowers U further.
  const double target_u = 1e-4;
  s.body_force_si = Eigen::Vector3d(3.0 * std::numbers::pi * nu * d * target_u / (box * box * box), 0.0, 0.0);

  Simulation sim(s);
  const double a = 0.5 * d;
  const auto measure_k = [&] {
    const double u = sim.superficial_velocity_si().x();
    return sim.last_step().hydrodynamic.force_si.x() / (6.0 * std::numbers::pi * nu * a * u);
  };
  PeriodicSphereResult r;
  const std::int64_t interval = steady_check_interval(box, nu);
  double k_previous = 0.0;
  while (sim.steps() < o.max_steps) {
    for (std::int64_t i = 0; i < interval; ++i) sim.step();
    const double k = measure_k();
    r.last_relative_change = std::abs(k - k_previous) / std::abs(k);
    k_previous = k;
    if (r.last_relative_change < o.steady_tolerance) break;
  }
  const double u = sim.superficial_velocity_si().x();
  r.k = k_previous;
  r.steps = sim.steps();
  r.solid_fraction = std::numbers::pi / 6.0 * std::pow(d / box, 3);
  r.k_reference = sangani_acrivos_k(d / box);
  r.reynolds = u * d / nu;
  r.slip_max = sim.last_step().slip_max_si / u;
  return r;
}

/// A sphere turning at a prescribed constant rate about z in a periodic cube (motion towed with
/// zero velocity: RigidBody keeps the initial body angular velocity and turns the attitude, the
/// markers carry omega x r), fluid initially at rest. Creeping flow: Omega a = 1e-4 in lattice
/// units (Re = Omega a^2 / nu ~ 5e-3 at d = 16).
struct RotatingSphereResult {
  double torque_ratio = 0.0;          ///< -T_z / (8 pi mu a^3 Omega): 1 for the unbounded Stokes sphere
  double volume_fraction = 0.0;       ///< pi d^3 / (6 L^3)
  double reynolds = 0.0;              ///< Omega a^2 / nu
  double last_relative_change = 0.0;  ///< of the ratio over the last check interval
  std::int64_t steps = 0;
};

inline RotatingSphereResult run_rotating_sphere(const PeriodicSphereOptions& o) {
  const double d = o.cells_per_diameter;
  const double a = 0.5 * d;
  const double nu = (o.tau - 0.5) / 3.0;
  SimulationSetup s = periodic_sphere_setup(o);
  const double omega = 1e-4 / a;  // rad per step (dt = 1): surface speed 1e-4
  s.motion = body::MotionKind::towed;
  s.initial.velocity_si = Eigen::Vector3d::Zero();
  s.initial.angular_velocity_b_si = Eigen::Vector3d(0.0, 0.0, omega);

  Simulation sim(s);
  // Lamb 1932 (Hydrodynamics, ch. XI): the torque of the fluid on a sphere turning at Omega in unbounded
  // fluid at rest is -8 pi mu a^3 Omega (mu = rho nu, rho = 1).
  const double stokes_torque = 8.0 * std::numbers::pi * nu * a * a * a * omega;
  const auto ratio = [&] { return -sim.last_step().hydrodynamic.torque_si.z() / stokes_torque; };
  const std::int64_t interval = steady_check_interval(o.box_cells, nu);
  RotatingSphereResult r;
  double previous = 0.0;
  while (sim.steps() < o.max_steps) {
    for (std::int64_t i = 0; i < interval; ++i) sim.step();
    const double now = ratio();
    r.last_relative_change = std::abs(now - previous) / std::abs(now);
    previous = now;
    if (r.last_relative_change < o.steady_tolerance) break;
  }
  r.torque_ratio = previous;
  r.steps = sim.steps();
  r.volume_fraction = std::numbers::pi / 6.0 * std::pow(d / o.box_cells, 3);
  r.reynolds = omega * a * a / nu;
  return r;
}

/// Removes the periodic-array correction from two boxes, assuming ratio(L) = ratio_inf (1 + c phi)
/// with phi = pi d^3 / (6 L^3) (the leading correction of a cubic array of rotlets decays like
/// (a / L)^3); returns ratio_inf and c.
struct BoxExtrapolation {
  double ratio_infinite = 0.0;
  double coefficient = 0.0;  ///< c of ratio = ratio_inf (1 + c phi)
};
inline BoxExtrapolation extrapolate_box(const RotatingSphereResult& small_box, const RotatingSphereResult& large_box) {
  const double p1 = small_box.volume_fraction, p2 = large_box.volume_fraction;
  const double r1 = small_box.torque_ratio, r2 = large_box.torque_ratio;
  BoxExtrapolation e;
  e.ratio_infinite = (r2 * p1 - r1 * p2) / (p1 - p2);
  e.coefficient = (r1 - r2) / (e.ratio_infinite * (p1 - p2));
  return e;
}

/// run_rotating_sphere at a resolution and box size, steady to 1e-5, with its figures printed.
inline RotatingSphereResult run_rotating_sphere_printed(double cells_per_diameter, int box_cells,
                                                        CouplingKind coupling = CouplingKind::immersed_boundary,
                                                        lbm::LatticeKind lattice = lbm::LatticeKind::D3Q19) {
  PeriodicSphereOptions o;
  o.coupling = coupling;
  o.lattice = lattice;
  o.cells_per_diameter = cells_per_diameter;
  o.box_cells = box_cells;
  o.steady_tolerance = 1e-5;
  const RotatingSphereResult r = run_rotating_sphere(o);
  std::printf("d = %g cells, L = %d: phi = %.5f, T / (8 pi mu a^3 Omega) = %.4f, Re = %.1e, change %.1e, %lld steps\n",
              cells_per_diameter, box_cells, r.volume_fraction, r.torque_ratio, r.reynolds, r.last_relative_change,
              static_cast<long long>(r.steps));
  return r;
}

}  // namespace settle::coupling::testing
