#include "coupling/lattice_body.hpp"

namespace settle::coupling {
namespace {

bool periodic(const lbm::Solver& solver, int axis) {
  return solver.config().boundaries[static_cast<std::size_t>(axis)] == lbm::Boundary::periodic;
}

// The whole lattice's extent (a block of a split lattice answers for the whole).
int grid_extent(const lbm::Solver& solver, int axis) {
  if (solver.config().split) return solver.config().split->global[static_cast<std::size_t>(axis)];
  return axis == 0 ? solver.nx() : axis == 1 ? solver.ny() : solver.nz();
}

}  // namespace

bool box_fits(const CellBox& box, const lbm::Solver& solver) {
  for (int a = 0; a < 3; ++a) {
    const auto i = static_cast<std::size_t>(a);
    const int n = grid_extent(solver, a);
    if (periodic(solver, a)) {
      if (box.extent[i] > n) return false;
    } else if (box.origin[i] < 0 || box.origin[i] + box.extent[i] > n) {
      return false;
    }
  }
  return true;
}

}  // namespace settle::coupling
