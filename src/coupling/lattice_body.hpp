#pragma once
// The lattice-unit geometry that both couplings (coupling/body_coupling.hpp) share: where the
// window's cells lie in SI, the box of cells a coupling works on, and the wrench a coupling
// measures. Lattice units: dx = dt = 1, fluid density 1.
//
// Lattice coordinates: cell (i, j, k) of the fluid grid has its centre at the INTEGER point
// (i, j, k), i.e. X = (x_si - window_origin_si) / dx_si - 1/2; the walls of a grid of n cells
// along an axis lie at -1/2 and n - 1/2 (half-way bounce-back).
#include <array>
#include <cstddef>

#include <Eigen/Core>

#include "lbm/solver.hpp"

namespace settle::coupling {

/// Maps SI positions to lattice coordinates of the (possibly moving) window.
struct LatticeFrame {
  Eigen::Vector3d window_origin_si = Eigen::Vector3d::Zero();  ///< SI position of the grid's corner
  double dx_si = 1.0;
  Eigen::Vector3d to_lattice(const Eigen::Vector3d& x_si) const {
    return (x_si - window_origin_si) / dx_si - Eigen::Vector3d::Constant(0.5);
  }
  Eigen::Vector3d to_si(const Eigen::Vector3d& x) const {
    return window_origin_si + (x + Eigen::Vector3d::Constant(0.5)) * dx_si;
  }
};

/// An axis-aligned box of cells (lattice units): first cell and extent per axis. Each coupling
/// says which box a body needs (BodyCoupling::box_at).
struct CellBox {
  std::array<int, 3> origin{};
  std::array<int, 3> extent{};
  std::size_t cell_count() const {
    return static_cast<std::size_t>(extent[0]) * static_cast<std::size_t>(extent[1]) *
           static_cast<std::size_t>(extent[2]);
  }
  /// Index of a cell of the box in x-fastest order.
  std::size_t index_of(const std::array<int, 3>& cell) const {
    const auto at = [&](std::size_t a) { return static_cast<std::size_t>(cell[a] - origin[a]); };
    return at(0) + static_cast<std::size_t>(extent[0]) * (at(1) + static_cast<std::size_t>(extent[1]) * at(2));
  }
};

/// True when the box can be exchanged with the solver: on a periodic axis its extent is at most
/// the grid's (no cell twice), on any other axis it lies inside the grid.
bool box_fits(const CellBox& box, const lbm::Solver& solver);

/// Force and torque (about the body's centre) that the fluid exerts on the body, lattice units.
struct LatticeWrench {
  Eigen::Vector3d force = Eigen::Vector3d::Zero();
  Eigen::Vector3d torque = Eigen::Vector3d::Zero();
};

}  // namespace settle::coupling
