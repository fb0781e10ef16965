#include "body/carlson.hpp"

#include <algorithm>
#include <cmath>
#include <stdexcept>

namespace settle::body {
namespace {

// The duplication loop stops once 4^-m Q <= |A_m|; with this Q the truncated series has a
// relative error below 2^-53 (Carlson 1995, eqs. 2.2 and 2.13).
constexpr double kUnitRoundoff = 0x1p-53;

void require_non_negative(double x, double y, double z, const char* name) {
  if (!(x >= 0.0 && y >= 0.0 && z >= 0.0) || !std::isfinite(x + y + z)) {
    throw std::domain_error(std::string(name) + ": arguments must be finite and >= 0");
  }
}

}  // namespace

double carlson_rf(double x, double y, double z) {
  require_non_negative(x, y, z, "carlson_rf");
  if ((x == 0.0) + (y == 0.0) + (z == 0.0) > 1) throw std::domain_error("carlson_rf: two zero arguments");
  const double a0 = (x + y + z) / 3.0;
  double q =
      std::pow(3.0 * kUnitRoundoff, -1.0 / 6.0) * std::max({std::abs(a0 - x), std::abs(a0 - y), std::abs(a0 - z)});
  double a = a0;
  while (q > std::abs(a)) {
    const double sx = std::sqrt(x), sy = std::sqrt(y), sz = std::sqrt(z);
    const double lambda = sx * sy + sx * sz + sy * sz;
    x = 0.25 * (x + lambda);
    y = 0.25 * (y + lambda);
    z = 0.25 * (z + lambda);
    a = 0.25 * (a + lambda);
    q *= 0.25;
  }
  const double dx = 1.0 - x / a, dy = 1.0 - y / a, dz = -(dx + dy);
  const double e2 = dx * dy - dz * dz;
  const double e3 = dx * dy * dz;
  return (1.0 - e2 / 10.0 + e3 / 14.0 + e2 * e2 / 24.0 - 3.0 * e2 * e3 / 44.0) / std::sqrt(a);
}

double carlson_rd(double x, double y, double z) {
  require_non_negative(x, y, z, "carlson_rd");
  if (z == 0.0 || (x == 0.0 && y == 0.0)) throw std::domain_error("carlson_rd: z = 0 or x = y = 0");
  const double a0 = (x + y + 3.0 * z) / 5.0;
  double q =
      std::pow(0.25 * kUnitRoundoff, -1.0 / 6.0) * std::max({std::abs(a0 - x), std::abs(a0 - y), std::abs(a0 - z)});
  double a = a0;
  double tail_sum = 0.0;
  double weight = 1.0;  // 4^-m
  while (q > std::abs(a)) {
    const double sx = std::sqrt(x), sy = std::sqrt(y), sz = std::sqrt(z);
    const double lambda = sx * sy + sx * sz + sy * sz;
    tail_sum += weight / (sz * (z + lambda));
    weight *= 0.25;
    x = 0.25 * (x + lambda);
    y = 0.25 * (y + lambda);
    z = 0.25 * (z + lambda);
    a = 0.25 * (a + lambda);
    q *= 0.25;
  }
  const double dx = 1.0 - x / a, dy = 1.0 - y / a, dz = -(dx + dy) / 3.0;
  const double xy = dx * dy, z2 = dz * dz;
  const double e2 = xy - 6.0 * z2;
  const double e3 = (3.0 * xy - 8.0 * z2) * dz;
  const double e4 = 3.0 * (xy - z2) * z2;
  const double e5 = xy * z2 * dz;
  const double series = 1.0 - 3.0 * e2 / 14.0 + e3 / 6.0 + 9.0 * e2 * e2 / 88.0 - 3.0 * e4 / 22.0 -
                        9.0 * e2 * e3 / 52.0 + 3.0 * e5 / 26.0;
  return weight * series / (a * std::sqrt(a)) + 3.0 * tail_sum;
}

double carlson_rg(double x, double y, double z) {
  require_non_negative(x, y, z, "carlson_rg");
  double v[3] = {x, y, z};
  std::sort(v, v + 3);                            // v[0] <= v[1] <= v[2]
  if (v[1] == 0.0) return 0.5 * std::sqrt(v[2]);  // R_G(0, 0, z) = sqrt(z) / 2
  // DLMF 19.21.10 with the middle value as the distinguished argument: (x-z)(y-z) <= 0, so
  // all three terms are non-negative.
  const double lo = v[0], mid = v[1], hi = v[2];
  return 0.5 * (mid * carlson_rf(lo, hi, mid) - (lo - mid) * (hi - mid) * carlson_rd(lo, hi, mid) / 3.0 +
                std::sqrt(lo * hi / mid));
}

double complete_elliptic_e(double k) {
  if (!(k >= 0.0 && k <= 1.0)) throw std::domain_error("complete_elliptic_e: k must lie in [0, 1]");
  return 2.0 * carlson_rg(0.0, (1.0 - k) * (1.0 + k), 1.0);
}

}  // namespace settle::body
