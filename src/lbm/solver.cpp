#include "lbm/solver.hpp"

#include <fmt/format.h>

#include <stdexcept>

#include "common/error.hpp"
#include "lbm/aa_solver.hpp"
#include "lbm/cumulant.hpp"

namespace settle::lbm {

namespace {

template <Lattice L, class Collision>
std::unique_ptr<Solver> make_with_precision(const SolverConfig& config) {
  if (config.precision == Precision::float32) {
    return std::make_unique<AaSolver<L, Collision, float>>(config);
  }
  return std::make_unique<AaSolver<L, Collision, double>>(config);
}

// The subgrid model is a distinct collision type, so that the plain operators' kernels carry none
// of it (no branch per cell).
template <Lattice L, class Operator>
std::unique_ptr<Solver> make_with_subgrid(const SolverConfig& config) {
  if (config.subgrid == SubgridModel::smagorinsky) return make_with_precision<L, Smagorinsky<Operator>>(config);
  return make_with_precision<L, Operator>(config);
}

template <Lattice L>
std::unique_ptr<Solver> make_with_collision(const SolverConfig& config) {
  switch (config.collision) {
    case CollisionKind::bgk:
      return make_with_subgrid<L, Bgk>(config);
    case CollisionKind::trt:
      return make_with_subgrid<L, Trt>(config);
    case CollisionKind::recursive_regularized:
      return make_with_subgrid<L, RecursiveRegularized>(config);
    case CollisionKind::cumulant:
      // validate (check_collision_lattice) has refused any other lattice.
      if constexpr (L::Q == 27) return make_with_precision<L, Cumulant>(config);
      throw std::logic_error("make_solver: the cumulant operator needs D3Q27");
  }
  return nullptr;
}

/// d/d(axis) of `field` (a lattice of extent n) at cell (x, y, z) by second-order differences.
double derivative(const std::vector<double>& field, const std::array<int, 3>& extent,
                  const std::array<Boundary, 3>& boundaries, int axis, int x, int y, int z) {
  const int n = extent[axis];
  if (n == 1) return 0.0;
  std::array<int, 3> c{x, y, z};
  const auto at = [&](int k) {
    std::array<int, 3> p = c;
    p[axis] = k;
    return field[static_cast<std::size_t>(p[0]) +
                 static_cast<std::size_t>(extent[0]) *
                     (static_cast<std::size_t>(p[1]) + static_cast<std::size_t>(extent[1]) * p[2])];
  };
  const int k = c[axis];
  if (boundaries[axis] == Boundary::periodic) {
    return 0.5 * (at((k + 1) % n) - at((k - 1 + n) % n));
  }
  if (n == 2) return at(1) - at(0);
  if (k == 0) return 0.5 * (-3.0 * at(0) + 4.0 * at(1) - at(2));
  if (k == n - 1) return 0.5 * (3.0 * at(n - 1) - 4.0 * at(n - 2) + at(n - 3));
  return 0.5 * (at(k + 1) - at(k - 1));
}

}  // namespace

void Solver::refill_cell(const std::array<int, 3>& cell, double rho, const Eigen::Vector3d& u,
                         const std::optional<std::array<int, 3>>& donor) {
  std::vector<double> f_neq(static_cast<std::size_t>(velocity_count()), 0.0);
  if (donor) non_equilibrium((*donor)[0], (*donor)[1], (*donor)[2], f_neq);
  refill_cell_with(cell, rho, u, f_neq);
}

std::span<const std::array<int, 3>> velocity_set(LatticeKind kind) {
  if (kind == LatticeKind::D3Q27) return D3Q27::set.c;
  return D3Q19::set.c;
}

std::unique_ptr<Solver> make_solver(const SolverConfig& config) {
  validate(config);
  if (config.lattice == LatticeKind::D3Q27) return make_with_collision<D3Q27>(config);
  return make_with_collision<D3Q19>(config);
}

std::vector<double> Solver::pressure_field() const {
  std::vector<double> p = density_field();
  for (double& value : p) value = cs2 * (value - 1.0);
  return p;
}

VectorField Solver::vorticity_field() const {
  return vorticity_of(velocity_field(), {nx(), ny(), nz()}, config().boundaries);
}

VectorField vorticity_of(const VectorField& u, const std::array<int, 3>& extent,
                         const std::array<Boundary, 3>& boundaries) {
  const std::size_t cells =
      static_cast<std::size_t>(extent[0]) * static_cast<std::size_t>(extent[1]) * static_cast<std::size_t>(extent[2]);
  VectorField w{std::vector<double>(cells), std::vector<double>(cells), std::vector<double>(cells)};
  const int nx = extent[0], ny = extent[1], nz = extent[2];
#pragma omp parallel for collapse(2) schedule(static)
  for (int z = 0; z < nz; ++z) {
    for (int y = 0; y < ny; ++y) {
      for (int x = 0; x < nx; ++x) {
        const std::size_t n =
            static_cast<std::size_t>(x) +
            static_cast<std::size_t>(nx) * (static_cast<std::size_t>(y) + static_cast<std::size_t>(ny) * z);
        const auto d = [&](const std::vector<double>& f, int axis) {
          return derivative(f, extent, boundaries, axis, x, y, z);
        };
        w.x[n] = d(u.z, 1) - d(u.y, 2);
        w.y[n] = d(u.x, 2) - d(u.z, 0);
        w.z[n] = d(u.y, 0) - d(u.x, 1);
      }
    }
  }
  return w;
}

std::string to_string(WallRule rule) {
  switch (rule) {
    case WallRule::halfway:
      return "halfway";
    case WallRule::bouzidi:
      return "bouzidi";
    case WallRule::quadratic:
      return "quadratic";
    case WallRule::central_linear:
      return "central_linear";
  }
  return "?";
}

WallRule parse_wall_rule(const std::string& name, const std::string& what) {
  for (const WallRule rule : {WallRule::bouzidi, WallRule::quadratic, WallRule::central_linear, WallRule::halfway})
    if (name == to_string(rule)) return rule;
  throw InputError(fmt::format("{}: must be bouzidi, quadratic, central_linear or halfway, got '{}'", what, name));
}

}  // namespace settle::lbm
