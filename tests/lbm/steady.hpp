#pragma once
// Shared helper of the lbm tests: advance a solver to its discrete steady state.
#include <algorithm>
#include <cmath>
#include <cstdint>

#include "lbm/solver.hpp"

namespace settle::lbm::testing {

/// Steps in blocks of `block` until the largest change of any velocity component over a
/// block is below `tolerance` (absolute, lattice units), or `max_steps` is reached.
/// Returns the number of steps taken.
inline std::int64_t run_to_steady_state(Solver& solver, double tolerance, std::int64_t max_steps, int block = 200) {
  VectorField previous = solver.velocity_field();
  std::int64_t steps = 0;
  while (steps < max_steps) {
    solver.run(block);
    steps += block;
    const VectorField now = solver.velocity_field();
    double change = 0.0;
    for (std::size_t n = 0; n < now.x.size(); ++n) {
      change = std::max({change, std::abs(now.x[n] - previous.x[n]), std::abs(now.y[n] - previous.y[n]),
                         std::abs(now.z[n] - previous.z[n])});
    }
    if (change < tolerance) break;
    previous = now;
  }
  return steps;
}

}  // namespace settle::lbm::testing
