#include "lbm/wall_rules.hpp"

namespace settle::lbm {

namespace {

// Notation: along the link, s = 0 at the fluid cell x, s = -1 at x - c_i, the wall at s = q.

// Half-way bounce-back: the wall at s = 1/2 whatever q, f_opp(i)(x) = f*_i(x) + W (Ladd 1994).
WallCoefficients halfway() { return {}; }

// Bouzidi, Firdaouss and Lallemand 2001 (Phys. Fluids 13, 3452, doi:10.1063/1.1399290), the
// linear interpolation along the link. q < 1/2: the population that reaches x after its bounce left
// from s = 2q - 1 before the streaming, interpolated between s = 0 and s = -1:
//   f_opp(i)(x) = 2q f*_i(x) + (1 - 2q) f*_i(x - c_i) + W.
// q >= 1/2: the bounced f*_i(x) + W lands at s = 2q - 1, and the value at s = 0 is interpolated
// between it and f*_opp(i)(x), streamed to s = -1:
//   f_opp(i)(x) = (f*_i(x) + W) / 2q + (2q - 1) / 2q f*_opp(i)(x).
WallCoefficients bouzidi_linear(double q) {
  WallCoefficients k;
  if (q < 0.5) {
    k.a = 2.0 * q, k.b = 1.0 - 2.0 * q;
  } else {
    k.a = 0.5 / q, k.c = (2.0 * q - 1.0) / (2.0 * q), k.wall_divisor = 2.0 * q;
  }
  return k;
}

// The same paper's quadratic interpolation, Lagrange's through three points of the link.
// q < 1/2, from s = 0, -1, -2 to s = 2q - 1:
//   f_opp(i)(x) = q (1 + 2q) f*_i(x) + (1 - 2q)(1 + 2q) f*_i(x - c_i) - q (1 - 2q) f*_i(x - 2 c_i) + W.
// q >= 1/2, from s = 2q - 1, -1, -2 (f*_i(x) + W, f*_opp(i)(x), f*_opp(i)(x - c_i)) to s = 0:
//   f_opp(i)(x) = (f*_i(x) + W) / (q (2q + 1)) + (2q - 1) / q f*_opp(i)(x)
//               - (2q - 1) / (2q + 1) f*_opp(i)(x - c_i).
WallCoefficients bouzidi_quadratic(double q) {
  WallCoefficients k;
  k.reads_third = true;
  if (q < 0.5) {
    k.a = q * (1.0 + 2.0 * q), k.b = (1.0 - 2.0 * q) * (1.0 + 2.0 * q), k.b2 = -q * (1.0 - 2.0 * q);
  } else {
    k.a = 1.0 / (q * (2.0 * q + 1.0)), k.c = (2.0 * q - 1.0) / q, k.c2 = -(2.0 * q - 1.0) / (2.0 * q + 1.0);
    k.wall_scale = k.a;
  }
  return k;
}

// Ginzburg, Verhaeghe and d'Humieres 2008 (Commun. Comput. Phys. 3, 427), the central linear
// interpolation (CLI): their Eq. (4.1) with the coefficients of their Table 3 (kappa_1 = 1,
// kappa_0 = k on f*_i(x - c_i), -k on f*_opp(i)(x)),
//   f_opp(i)(x) = f*_i(x) + k (f*_i(x - c_i) - f*_opp(i)(x)) + 2 W / (1 + 2q),  k = (1 - 2q) / (1 + 2q),
// the wall term from their Table 4: alpha = 4 / (1 + 2q) times 3 w_i c_i.u_w = -W / 2, which
// half-way bounce-back takes with alpha = 2. One formula for every q, half-way bounce-back at
// q = 1/2; it reads x - c_i for every q (waLBerla's CurvedLinear.h implements the same).
WallCoefficients central_linear(double q) {
  const double k = (1.0 - 2.0 * q) / (1.0 + 2.0 * q);
  WallCoefficients coefficients;
  coefficients.b = k, coefficients.c = -k;
  coefficients.wall_scale = 2.0, coefficients.wall_divisor = 1.0 + 2.0 * q;
  return coefficients;
}

}  // namespace

WallCoefficients wall_coefficients(WallRule rule, double q, bool has_second, bool has_third) {
  // Without the second node the interpolation has nothing to lean on: half-way bounce-back there
  // (first order at that link only). Bouzidi's q >= 1/2 branch reads no node behind x.
  if (rule == WallRule::halfway || (!has_second && (q < 0.5 || rule == WallRule::central_linear))) return halfway();
  if (rule == WallRule::central_linear) return central_linear(q);
  if (rule == WallRule::quadratic && has_second && has_third) return bouzidi_quadratic(q);
  return bouzidi_linear(q);
}

}  // namespace settle::lbm
