#include "study/grid_convergence.hpp"

#include <algorithm>
#include <cmath>
#include <stdexcept>

namespace settle::study {
namespace {

constexpr double kSafetyFactor = 1.25;  // Roache's, for three grids or more
// Where the grids do not confirm the scheme's order: Roache's safety factor for an unconfirmed
// order, with the observed order held within [0.5, 2]. 2 is the formal order of the lattice
// Boltzmann scheme, which no coupling of settle exceeds (the immersed boundary's diffuse interface
// is first order); an order observed far above it says the three grids are not yet governed by
// the leading error term, and an index computed with it would be too small.
constexpr double kUnconfirmedSafetyFactor = 3.0;
constexpr double kFormalOrder = 2.0;
constexpr double kLowestOrder = 0.5;
constexpr double kConfirmedWithin = 0.1;  // |p - 2| <= 0.2
constexpr int kMaxIterations = 200;

}  // namespace

GridConvergence grid_convergence(const ThreeGrids& g) {
  if (!(0.0 < g.h_fine && g.h_fine < g.h_medium && g.h_medium < g.h_coarse))
    throw std::invalid_argument("grid_convergence: needs 0 < h_fine < h_medium < h_coarse");
  GridConvergence result;
  const double r21 = g.h_medium / g.h_fine, r32 = g.h_coarse / g.h_medium;
  const double e21 = g.medium - g.fine, e32 = g.coarse - g.medium;
  if (e21 == 0.0 || e32 == 0.0) return result;
  const double s = e32 / e21 > 0.0 ? 1.0 : -1.0;
  result.oscillatory = s < 0.0;
  // Celik et al.'s equations (3)-(5): p = |ln|e32/e21| + q(p)| / ln r21 by fixed-point iteration,
  // q(p) = ln((r21^p - s) / (r32^p - s)), which vanishes for a constant ratio.
  const double log_ratio = std::log(std::abs(e32 / e21));
  double p = std::abs(log_ratio) / std::log(r21);
  for (int k = 0; k < kMaxIterations; ++k) {
    const double q = std::log((std::pow(r21, p) - s) / (std::pow(r32, p) - s));
    const double next = std::abs(log_ratio + q) / std::log(r21);
    if (!std::isfinite(next)) return result;
    const bool converged = std::abs(next - p) <= 1e-12 * std::max(1.0, p);
    p = next;
    if (converged) break;
  }
  const double rp = std::pow(r21, p);
  if (!(p > 0.0) || rp <= 1.0) return result;
  result.observed_order = p;
  result.extrapolated = (rp * g.fine - g.medium) / (rp - 1.0);
  result.order_confirmed = !result.oscillatory && std::abs(p - kFormalOrder) <= kConfirmedWithin * kFormalOrder;
  if (g.fine == 0.0) return result;
  if (result.order_confirmed) {
    result.gci_fine = kSafetyFactor * std::abs(e21 / g.fine) / (rp - 1.0);
  } else {
    const double held = std::clamp(p, kLowestOrder, kFormalOrder);
    result.gci_fine = kUnconfirmedSafetyFactor * std::abs(e21 / g.fine) / (std::pow(r21, held) - 1.0);
  }
  return result;
}

}  // namespace settle::study
