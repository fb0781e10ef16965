#pragma once
// Stokes drag of a fixed spheroid in a periodic cubic box (flow driven by a uniform body force
// on the fluid), moving along its symmetry axis ("axial": prolate end-on, oblate face-on) or
// across it ("transverse": prolate broadside, oblate edgewise), compared with the exact drag of
// a spheroid in unbounded fluid (Oberbeck 1876; Happel and Brenner 1965, Low Reynolds Number
// Hydrodynamics, section 5-11; formulas as stored in validation/reference-data.json,
// spheroid_Stokes_drag).
//
// Removing the box. A periodic array of bodies drags more than one body alone. For a point
// force in a cubic lattice the leading correction is shape independent (Hasimoto 1959,
// J. Fluid Mech. 5, 317, doi:10.1017/S0022112059000222): with U the superficial velocity and F the
// drag per body,
//     6 pi mu r_v U / F = 1 / K(L) = 1 / K_inf - 1.418649 (d_v / L) + b (d_v / L)^3 + ...
// (1.418649 = 2.837297 / 2, the Hasimoto constant for d_v = 2 r_v). The (d_v / L)^3 term depends
// on the body's size and shape, so it is fitted from two boxes; K_inf is what remains. Applied to
// Sangani and Acrivos' exact series for spheres, this procedure recovers K_inf = 1 to 0.11% from
// L = 2 d and 3 d, and to 0.02% from L = 3 d and 4 d.
#include <cmath>
#include <cstdint>
#include <cstdio>
#include <numbers>
#include <string>

#include "periodic_sphere.hpp"

namespace settle::coupling::testing {

enum class DragDirection { axial, transverse };

/// K = F / (6 pi mu r_v U) of a spheroid of aspect ratio gamma = polar / equatorial in unbounded
/// Stokes flow, r_v the volume-equivalent radius (exact: Oberbeck 1876, Happel and Brenner 1965).
inline double spheroid_stokes_k(double gamma, DragDirection direction) {
  const double pi = std::numbers::pi;
  if (std::abs(gamma - 1.0) < 1e-12) return 1.0;
  const double r_v_over_a_eq = std::cbrt(gamma);  // r_v in units of the equatorial radius
  double force_over_mu_u = 0.0;                   // F / (mu U) with the equatorial radius = 1
  if (gamma > 1.0) {
    const double a = gamma;  // polar semi-axis
    const double e = std::sqrt(1.0 - 1.0 / (gamma * gamma));
    const double l = std::log((1.0 + e) / (1.0 - e));
    force_over_mu_u = direction == DragDirection::axial
                          ? 16.0 * pi * a * e * e * e / ((1.0 + e * e) * l - 2.0 * e)
                          : 32.0 * pi * a * e * e * e / (2.0 * e + (3.0 * e * e - 1.0) * l);
  } else {
    const double a = 1.0;  // equatorial semi-axis
    const double e = std::sqrt(1.0 - gamma * gamma);
    const double s = std::sqrt(1.0 - e * e);
    force_over_mu_u = direction == DragDirection::axial
                          ? 8.0 * pi * a * e * e * e / (e * s - (1.0 - 2.0 * e * e) * std::asin(e))
                          : 16.0 * pi * a * e * e * e / ((1.0 + 2.0 * e * e) * std::asin(e) - e * s);
  }
  return force_over_mu_u / (6.0 * pi * r_v_over_a_eq);
}

struct PeriodicSpheroidResult {
  double k = 0.0;                     ///< F / (6 pi mu r_v U) in the periodic box
  double chi = 0.0;                   ///< d_v / L
  double reynolds = 0.0;              ///< U d_v / nu
  double lateral_force_ratio = 0.0;   ///< |F normal to the drive| / |F along it|
  double slip_max = 0.0;              ///< largest marker slip after forcing / U
  double slip_rms = 0.0;              ///< rms marker slip after forcing / U
  double last_relative_change = 0.0;  ///< estimated relative error of K left by the transient
  std::int64_t steps = 0;
};

/// A spheroid with its symmetry axis along z at the centre of a periodic cube of `box_cells`,
/// `cells_per_diameter` cells per volume-equivalent diameter, driven along z (axial) or x
/// (transverse) until the transient left in K is below `steady_tolerance` (relative).
inline PeriodicSpheroidResult run_periodic_spheroid(double gamma, DragDirection direction, double cells_per_diameter,
                                                    int box_cells, double steady_tolerance = 3e-4) {
  PeriodicSphereOptions o;
  o.cells_per_diameter = cells_per_diameter;
  o.box_cells = box_cells;
  o.max_steps = 200000;
  SimulationSetup s = periodic_sphere_setup(o);
  const double d_v = cells_per_diameter;
  body::ShapeSpec spec;
  spec.shape = "spheroid";
  spec.diameter = d_v / std::cbrt(gamma);  // equatorial diameter with the volume of a d_v sphere
  spec.aspect_ratio = gamma;
  s.shape = std::shared_ptr<const body::Shape>(body::make_shape(spec));

  const double nu = (o.tau - 0.5) / 3.0;
  const Eigen::Vector3d drive = direction == DragDirection::axial ? Eigen::Vector3d::UnitZ() : Eigen::Vector3d::UnitX();
  // Creeping flow: the force density that would give U ~ 1e-4 past the isolated body (Stokes
  // drag of the equivalent sphere; Re = U d_v / nu ~ 1e-2).
  const double target_u = 1e-4;
  const double box = box_cells;
  s.body_force_si = drive * (3.0 * std::numbers::pi * nu * d_v * target_u / (box * box * box));

  Simulation sim(s);
  const double r_v = 0.5 * d_v;
  const auto measure_k = [&] {
    const double u = sim.superficial_velocity_si().dot(drive);
    return sim.last_step().hydrodynamic.force_si.dot(drive) / (6.0 * std::numbers::pi * nu * r_v * u);
  };
  PeriodicSpheroidResult r;
  // The slowest transient is the mean flow of the whole box accelerating against the drag of one
  // body (time scale rho L^3 / zeta, several times the viscous time L^2 / nu of the box). K
  // approaches its steady value geometrically, so the error left after the last interval is
  // |dK| q / (1 - q) with q the ratio of successive changes (Aitken); stop once that is below
  // steady_tolerance.
  // Check interval: a tenth of the slower of the viscous time of the box and the mean-flow time
  // rho L^3 / zeta (zeta bounded below by the Stokes drag of the volume-equivalent sphere).
  const double mean_flow_time = box * box * box / (6.0 * std::numbers::pi * nu * 0.5 * d_v);
  const std::int64_t interval =
      std::max(steady_check_interval(box, nu), static_cast<std::int64_t>(0.1 * mean_flow_time));
  double k_previous = 0.0, change_previous = 0.0;
  r.last_relative_change = 1.0;
  while (sim.steps() < o.max_steps) {
    for (std::int64_t i = 0; i < interval; ++i) sim.step();
    const double k = measure_k();
    const double change = k - k_previous;
    k_previous = k;
    const double q = change_previous != 0.0 ? change / change_previous : 1.0;
    change_previous = change;
    if (q <= 0.0 || q >= 0.95) continue;  // not yet in the geometric tail
    r.last_relative_change = std::abs(change) * q / (1.0 - q) / std::abs(k);
    if (r.last_relative_change < steady_tolerance) break;
  }
  const double u = sim.superficial_velocity_si().dot(drive);
  const Eigen::Vector3d force = sim.last_step().hydrodynamic.force_si;
  r.k = k_previous;
  r.chi = d_v / box;
  r.reynolds = u * d_v / nu;
  r.lateral_force_ratio = (force - force.dot(drive) * drive).norm() / std::abs(force.dot(drive));
  r.slip_max = sim.last_step().slip_max_si / u;
  r.slip_rms = sim.last_step().slip_rms_si / u;
  r.steps = sim.steps();
  return r;
}

/// Hasimoto's point-force coefficient of 1 / K in d_v / L (file comment).
inline constexpr double hasimoto_coefficient = 1.418649;

/// K in unbounded fluid from two boxes (file comment): 1 / K + 1.418649 chi = 1 / K_inf + b chi^3.
struct DragExtrapolation {
  double k_infinite = 0.0;
  double b = 0.0;
};
inline DragExtrapolation extrapolate_drag(const PeriodicSpheroidResult& small_box,
                                          const PeriodicSpheroidResult& large_box) {
  const double y1 = 1.0 / small_box.k + hasimoto_coefficient * small_box.chi;
  const double y2 = 1.0 / large_box.k + hasimoto_coefficient * large_box.chi;
  const double c1 = std::pow(small_box.chi, 3), c2 = std::pow(large_box.chi, 3);
  DragExtrapolation e;
  e.b = (y1 - y2) / (c1 - c2);
  e.k_infinite = 1.0 / (y1 - e.b * c1);
  return e;
}

inline const char* direction_name(DragDirection d) { return d == DragDirection::axial ? "axial" : "transverse"; }

/// run_periodic_spheroid with its figures printed.
inline PeriodicSpheroidResult run_periodic_spheroid_printed(double gamma, DragDirection direction,
                                                            double cells_per_diameter, int box_cells) {
  const PeriodicSpheroidResult r = run_periodic_spheroid(gamma, direction, cells_per_diameter, box_cells);
  std::printf(
      "gamma = %g %s, d_v = %g cells, L = %d: K = %.4f, Re = %.1e, lateral %.1e, slip max %.4f U rms %.4f U, "
      "transient left %.1e, %lld steps\n",
      gamma, direction_name(direction), cells_per_diameter, box_cells, r.k, r.reynolds, r.lateral_force_ratio,
      r.slip_max, r.slip_rms, r.last_relative_change, static_cast<long long>(r.steps));
  std::fflush(stdout);
  return r;
}

/// Both boxes, the extrapolation and the comparison with the exact value, printed; returns the
/// relative error of K_inf.
struct SpheroidDragCheck {
  PeriodicSpheroidResult small_box, large_box;
  DragExtrapolation extrapolation;
  double k_exact = 0.0;
  double relative_error = 0.0;
};
inline SpheroidDragCheck check_spheroid_drag(double gamma, DragDirection direction, double cells_per_diameter,
                                             int small_box_cells, int large_box_cells) {
  SpheroidDragCheck c;
  c.small_box = run_periodic_spheroid_printed(gamma, direction, cells_per_diameter, small_box_cells);
  c.large_box = run_periodic_spheroid_printed(gamma, direction, cells_per_diameter, large_box_cells);
  c.extrapolation = extrapolate_drag(c.small_box, c.large_box);
  c.k_exact = spheroid_stokes_k(gamma, direction);
  c.relative_error = c.extrapolation.k_infinite / c.k_exact - 1.0;
  std::printf("  -> K_inf = %.4f (b = %.2f), exact %.4f: %+.2f%%\n", c.extrapolation.k_infinite, c.extrapolation.b,
              c.k_exact, 100.0 * c.relative_error);
  std::fflush(stdout);
  return c;
}

}  // namespace settle::coupling::testing
