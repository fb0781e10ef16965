#pragma once
// A sphere towed at constant velocity through fluid at rest, the moving window following it: the
// Galilean equivalent of a uniform stream past a fixed sphere, built only from parts settle needs
// for free settling. Compared with the standard drag curve of Clift, Grace and Weber 1978
// (Bubbles, Drops and Particles, Table 5.2; as stored in validation/reference-data.json,
// drag_sphere.Clift_standard_curve).
//
// Set-up (lattice-like SI units, as periodic_sphere.hpp: d = cells_per_diameter metres, so
// dx = 1 m; rho = 1): the sphere moves along -z at U = 0.04 lattice units (Mach 0.07) with
// nu = U d / Re. Free-slip side walls 7 d apart: the sphere's frontal area is pi/4/49 = 1.6% of
// the cross-section (the issue asks for lateral blockage below 2%); a free-slip wall is a mirror,
// so this is one sphere of a square array of period 7 d. No-slip walls at the ends of the window,
// 5 d ahead of the sphere and 11 d behind it; the window holds the sphere at its starting place,
// so fluid at rest enters ahead and the far wake leaves behind.
#include <algorithm>
#include <cmath>
#include <cstdint>
#include <cstdio>
#include <memory>
#include <numbers>
#include <vector>

#include "body/shape_factory.hpp"
#include "coupling/simulation.hpp"
#include "support/default_setup.hpp"

namespace settle::coupling::testing {

/// Clift, Grace and Weber 1978 standard drag curve, 0.01 < Re <= 1500 (the range used here).
inline double clift_sphere_drag(double re) {
  if (re <= 20.0) return 24.0 / re * (1.0 + 0.1315 * std::pow(re, 0.82 - 0.05 * std::log10(re)));
  if (re <= 260.0) return 24.0 / re * (1.0 + 0.1935 * std::pow(re, 0.6305));
  const double w = std::log10(re);
  return std::pow(10.0, 1.6435 - 1.1242 * w + 0.1558 * w * w);
}

struct TowedSphereOptions {
  double reynolds = 20.0;
  double cells_per_diameter = 12.0;
  double lattice_speed = 0.04;
  /// Side of the square cross-section: sides 4 d from the axis keep the drag within 1% of an
  /// unbounded fluid's at Re = 20-300 (docs/validation.md, "How large a window").
  double width_diameters = 8.0;
  double ahead_diameters = 5.0;    ///< fluid ahead of the sphere's centre
  double behind_diameters = 11.0;  ///< wake room behind it
  double travel_diameters = 30.0;  ///< run length
  /// The towing speed rises linearly from rest over the time it takes to travel this many
  /// diameters at full speed (SimulationSetup::hold_ramp_time_si); 0: an impulsive start.
  double ramp_diameters = 0.0;
  /// Start off the window's axis by this many cells along x and y: the symmetry breaking of the
  /// wakes above Re of about 210 needs a seed (zero: mirror-symmetric to round-off).
  Eigen::Vector2d offset_cells = Eigen::Vector2d::Zero();
  CouplingKind coupling = CouplingKind::immersed_boundary;
  lbm::CollisionKind collision = lbm::CollisionKind::trt;
  lbm::WallRule wall_rule = lbm::WallRule::bouzidi;  ///< momentum exchange only
};

struct TowedSphereResult {
  double drag_coefficient = 0.0;  ///< mean over the last fifth of the travel
  double previous_fifth = 0.0;    ///< mean over the fifth before: the drift measures the transient
  double reference = 0.0;         ///< Clift et al. at this Re
  double lateral_ratio = 0.0;     ///< |lateral force| / drag, last fifth
  double slip_max = 0.0;          ///< largest marker slip after forcing / U, last step
  double slip_rms = 0.0;
  std::int64_t steps = 0;
  std::array<int, 3> cells{};
  double tau = 0.0;
};

inline TowedSphereResult run_towed_sphere(const TowedSphereOptions& o) {
  const double d = o.cells_per_diameter;  // metres = cells
  const double nu = o.lattice_speed * d / o.reynolds;
  SimulationSetup s = settle::test::default_setup();
  body::ShapeSpec spec;
  spec.shape = "sphere";
  spec.diameter = d;
  s.shape = std::shared_ptr<const body::Shape>(body::make_shape(spec));
  s.motion = body::MotionKind::towed;
  s.particle_density_si = 2.0;
  s.fluid_density_si = 1.0;
  s.dynamic_viscosity_si = nu;
  s.gravity_si = Eigen::Vector3d::Zero();
  const double width = std::round(o.width_diameters * d);
  const double length = std::round((o.ahead_diameters + o.behind_diameters) * d);
  s.domain_size_si = Eigen::Vector3d(width, width, length);
  s.boundaries = {lbm::Boundary::free_slip, lbm::Boundary::free_slip, lbm::Boundary::no_slip};
  s.follow_particle = true;
  s.coupling = o.coupling;
  s.collision = o.collision;
  s.wall_rule = o.wall_rule;
  s.initial.position_si = Eigen::Vector3d(0.5 * width + o.offset_cells.x(), 0.5 * width + o.offset_cells.y(),
                                          std::round(o.ahead_diameters * d));
  s.initial.velocity_si = Eigen::Vector3d(0.0, 0.0, -o.lattice_speed);
  s.cells_per_diameter = d;
  s.tau = 0.5 + 3.0 * nu;  // dx = dt = 1
  s.max_lattice_velocity = o.lattice_speed * 1.01;
  s.end_time_si = o.travel_diameters * d / o.lattice_speed;
  s.hold_ramp_time_si = o.ramp_diameters * d / o.lattice_speed;

  Simulation sim(s);
  const double dynamic_pressure_area = 0.5 * o.lattice_speed * o.lattice_speed * std::numbers::pi * d * d / 4.0;
  const auto total_steps = static_cast<std::int64_t>(s.end_time_si);
  const std::int64_t fifth = total_steps / 5;
  double drag_last = 0.0, drag_before = 0.0, lateral_last = 0.0;
  for (std::int64_t n = 0; n < total_steps; ++n) {
    sim.step();
    const Eigen::Vector3d f = sim.last_step().hydrodynamic.force_si;
    // Drag opposes the motion (-z): the fluid pushes the sphere along +z.
    if (n >= total_steps - fifth) {
      drag_last += f.z();
      lateral_last += std::hypot(f.x(), f.y());
    } else if (n >= total_steps - 2 * fifth) {
      drag_before += f.z();
    }
  }
  TowedSphereResult r;
  r.drag_coefficient = drag_last / static_cast<double>(fifth) / dynamic_pressure_area;
  r.previous_fifth = drag_before / static_cast<double>(fifth) / dynamic_pressure_area;
  r.lateral_ratio = lateral_last / drag_last;
  r.reference = clift_sphere_drag(o.reynolds);
  r.slip_max = sim.last_step().slip_max_si / o.lattice_speed;
  r.slip_rms = sim.last_step().slip_rms_si / o.lattice_speed;
  r.steps = sim.steps();
  r.cells = sim.derived().cells;
  r.tau = sim.units().tau();
  return r;
}

inline TowedSphereResult run_towed_sphere_printed(const TowedSphereOptions& o) {
  const TowedSphereResult r = run_towed_sphere(o);
  std::printf(
      "%s, Re = %g, d = %g cells (%dx%dx%d, tau %.4f, %lld steps): C_D = %.4f (fifth before %.4f), "
      "Clift %.4f (%+.2f%%), lateral %.1e, slip max %.3f rms %.4f U\n",
      to_string(o.coupling).c_str(), o.reynolds, o.cells_per_diameter, r.cells[0], r.cells[1], r.cells[2], r.tau,
      static_cast<long long>(r.steps), r.drag_coefficient, r.previous_fifth, r.reference,
      100.0 * (r.drag_coefficient / r.reference - 1.0), r.lateral_ratio, r.slip_max, r.slip_rms);
  std::fflush(stdout);
  return r;
}

}  // namespace settle::coupling::testing
