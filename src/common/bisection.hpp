#pragma once
// Bisection on a bracket [low, high] of a monotone problem: the one root finder of settle's
// force balances (terminal speeds), closest-point multipliers and ray-surface intersections.
// Callers choose the midpoint rule (arithmetic, or geometric for brackets spanning decades), the
// stopping rule and a step limit, so each keeps the tolerance its problem needs.
#include <cmath>

namespace settle {

/// Where a trial point lies relative to the root sought.
enum class BisectionSide {
  below,      ///< the root lies above the point: the bracket's low end moves up to it
  above,      ///< the root lies below the point: the high end moves down to it
  at_root,    ///< the point is the root: both ends move to it
  undefined,  ///< the problem is not defined there (e.g. NaN): bisection stops
};

struct BisectionBracket {
  double low = 0.0;
  double high = 0.0;
  bool undefined = false;  ///< bisection stopped at a point where the side was undefined
  [[nodiscard]] double middle() const { return 0.5 * (low + high); }
};

inline double arithmetic_midpoint(double low, double high) { return 0.5 * (low + high); }
/// For brackets of positive numbers spanning many decades: halves the bracket in log scale.
inline double geometric_midpoint(double low, double high) { return std::sqrt(low * high); }

/// Halves `bracket` until converged(low, high) holds or max_steps trial points were taken. Each
/// step takes the trial point midpoint(low, high) and moves an end of the bracket to it as
/// side_of(point) says. Returns the final bracket.
template <class SideOf, class Converged>
BisectionBracket bisect(BisectionBracket bracket, SideOf side_of, Converged converged, int max_steps,
                        double (*midpoint)(double, double) = arithmetic_midpoint) {
  for (int step = 0; step < max_steps && !converged(bracket.low, bracket.high); ++step) {
    const double point = midpoint(bracket.low, bracket.high);
    switch (side_of(point)) {
      case BisectionSide::below:
        bracket.low = point;
        break;
      case BisectionSide::above:
        bracket.high = point;
        break;
      case BisectionSide::at_root:
        bracket.low = bracket.high = point;
        break;
      case BisectionSide::undefined:
        bracket.undefined = true;
        return bracket;
    }
  }
  return bracket;
}

}  // namespace settle
