#pragma once
// The wall rules of an obstacle inside the grid as coefficients of one link (docs/lbm.md, "Walls
// inside the grid"): for a link from fluid cell x along c_i whose wall crosses it at the fraction q
// of its length, the population coming back from the wall is
//   f_opp(i)(x) = a f*_i(x) + b f*_i(x - c_i) + c f*_opp(i)(x) + b2 f*_i(x - 2 c_i)
//               + c2 f*_opp(i)(x - c_i) + (wall_scale / wall_divisor) W,
// f* the post-collision populations and W = -6 w_i c_i.u_w Ladd's moving-wall term at density 1
// (moving_wall_term). Pure functions of the rule, q and which of the cells behind x are fluid, so
// each rule is checked on q alone (tests/lbm/test_wall_rules.cpp); lbm/block_obstacle.hpp places
// the values in the population array.
#include <Eigen/Core>
#include <array>

#include "lbm/solver.hpp"

namespace settle::lbm {

struct WallCoefficients {
  double a = 1.0, b = 0.0, c = 0.0, b2 = 0.0, c2 = 0.0;
  /// The factor of W as the rule writes it, a quotient, so that the term is rounded as the
  /// formula reads (one division where the rule divides): wall_term.
  double wall_scale = 1.0, wall_divisor = 1.0;
  /// The quadratic rule's three-point form: it reads the third points x - 2 c_i (q < 1/2) or
  /// f*_opp(i)(x - c_i) (q >= 1/2), even where that coefficient vanishes (q = 1/2).
  bool reads_third = false;

  double wall_factor() const { return wall_scale / wall_divisor; }
  double wall_term(double moving) const { return moving * wall_scale / wall_divisor; }
};

/// The coefficients of `rule` at fraction q in (0, 1]. `has_second`: x - c_i is a fluid cell;
/// `has_third`: x - 2 c_i is one too (read by the quadratic rule alone). Where the rule's points
/// are not all fluid it falls back: the linear rules to half-way bounce-back (q < 1/2 for
/// Bouzidi's, every q for the central one), the quadratic rule to the linear one.
WallCoefficients wall_coefficients(WallRule rule, double q, bool has_second, bool has_third);

/// Ladd's moving-wall term -2 w_i rho_0 c_i.u_w / cs^2 at rho_0 = 1 (Ladd 1994, J. Fluid Mech.
/// 271, 285, doi:10.1017/S0022112094001771): what the wall adds to the population it returns.
inline double moving_wall_term(double weight, const std::array<int, 3>& c, const Eigen::Vector3d& wall_velocity) {
  return -6.0 * weight * (c[0] * wall_velocity[0] + c[1] * wall_velocity[1] + c[2] * wall_velocity[2]);
}

}  // namespace settle::lbm
