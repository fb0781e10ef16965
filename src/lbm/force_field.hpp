#pragma once
// The per-cell force density of a block (lattice units), added to the uniform body force in the
// kernel: three arrays (x, y, z) in the storage precision over the interior cells, linear index
// x + nx (y + ny z). Only the cells written since the last clear() are non-zero, and clear()
// zeroes just those (a sparse list), so the coupling pays for the cells near the body alone.
#include <Eigen/Core>
#include <array>
#include <cstdint>
#include <span>
#include <vector>

#include "lbm/aligned_array.hpp"

namespace settle::lbm {

template <class Real>
class ForceField {
 public:
  ForceField(std::size_t cells, bool threaded) : flags_(cells, 0) {
    for (auto& component : components_) {
      component = AlignedArray<Real>(cells);
      Real* f = component.data();
      // Parallel first touch, as the populations (the kernel reads both by rows).
#pragma omp parallel for schedule(static) if (threaded)
      for (std::size_t k = 0; k < cells; ++k) f[k] = Real(0);
    }
  }

  const Real* component(int axis) const { return components_[static_cast<std::size_t>(axis)].data(); }
  double value(int axis, std::size_t n) const {
    return static_cast<double>(components_[static_cast<std::size_t>(axis)][n]);
  }
  Eigen::Vector3d at(std::size_t n) const { return {value(0, n), value(1, n), value(2, n)}; }

  void add(std::size_t n, const Eigen::Vector3d& force) {
    mark(n);
    for (int a = 0; a < 3; ++a) components_[a][n] = static_cast<Real>(components_[a][n] + force[a]);
  }
  void set(std::size_t n, const Eigen::Vector3d& force) {
    mark(n);
    for (int a = 0; a < 3; ++a) components_[a][n] = static_cast<Real>(force[a]);
  }
  void clear() {
    for (const std::size_t n : cells_) {
      for (auto& component : components_) component[n] = Real(0);
      flags_[n] = 0;
    }
    cells_.clear();
  }
  /// The cells written since the last clear(), in the order they were first written.
  const std::vector<std::size_t>& cells() const { return cells_; }

  /// Replaces the forces with a saved list: cells (distinct, in range: the caller checks) and three
  /// values per cell.
  void restore(std::span<const std::uint64_t> cells, std::span<const double> values) {
    clear();
    for (std::size_t k = 0; k < cells.size(); ++k) {
      const auto n = static_cast<std::size_t>(cells[k]);
      mark(n);
      for (std::size_t a = 0; a < 3; ++a) components_[a][n] = static_cast<Real>(values[3 * k + a]);
    }
  }

 private:
  void mark(std::size_t n) {
    if (!flags_[n]) {
      flags_[n] = 1;
      cells_.push_back(n);
    }
  }

  std::array<AlignedArray<Real>, 3> components_;
  std::vector<std::uint8_t> flags_;
  std::vector<std::size_t> cells_;
};

}  // namespace settle::lbm
