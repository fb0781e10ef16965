#include "ibm/forcing.hpp"

#include <cmath>
#include <stdexcept>

namespace settle::ibm {
namespace {

Stencil local_stencil(const LocalGrid& grid, DeltaKernel kernel, const Eigen::Vector3d& x) {
  const auto& o = grid.origin();
  return stencil_at(kernel, x.x() - o[0], x.y() - o[1], x.z() - o[2]);
}

// Applies `visit(cell_index, weight)` to every cell of a stencil, in a fixed order so that the
// sums are the same on every run and thread count.
template <class Visit>
void for_each_cell(const LocalGrid& grid, const Stencil& s, Visit&& visit) {
  for (int k = 0; k < s.axis[2].width; ++k)
    for (int j = 0; j < s.axis[1].width; ++j)
      for (int i = 0; i < s.axis[0].width; ++i) {
        const std::size_t c = grid.index(s.axis[0].first + i, s.axis[1].first + j, s.axis[2].first + k);
        visit(c, s.weight(i, j, k));
      }
}

double interpolate_density(const LocalGrid& grid, const Stencil& stencil) {
  double rho = 0.0;
  for_each_cell(grid, stencil, [&](std::size_t c, double w) { rho += w * grid.rho[c]; });
  return rho;
}

struct SlipStats {
  double max = 0.0, rms = 0.0;
};

// u = u_before + F / (2 rho) at a stencil's centre, with 1 / (2 rho) of each cell computed once per
// forcing rather than at every interpolation (the same values, so the same sums).
Eigen::Vector3d interpolate_current_velocity(const LocalGrid& grid, const std::vector<double>& half_over_rho,
                                             const Stencil& stencil) {
  Eigen::Vector3d u = Eigen::Vector3d::Zero();
  for_each_cell(grid, stencil, [&](std::size_t c, double w) {
    for (int a = 0; a < 3; ++a) u[a] += w * (grid.velocity[a][c] + half_over_rho[c] * grid.force[a][c]);
  });
  return u;
}

SlipStats slip_stats(const std::vector<Eigen::Vector3d>& slip) {
  SlipStats s;
  double sum_sq = 0.0;
  for (const Eigen::Vector3d& v : slip) {
    const double norm = v.norm();
    s.max = std::max(s.max, norm);
    sum_sq += norm * norm;
  }
  if (!slip.empty()) s.rms = std::sqrt(sum_sq / static_cast<double>(slip.size()));
  return s;
}

}  // namespace

LocalGrid::LocalGrid(std::array<int, 3> origin, std::array<int, 3> extent) : origin_(origin), extent_(extent) {
  const std::size_t n = static_cast<std::size_t>(extent[0]) * extent[1] * extent[2];
  rho.assign(n, 1.0);
  for (auto& v : velocity) v.assign(n, 0.0);
  for (auto& f : force) f.assign(n, 0.0);
}

bool LocalGrid::contains(const Stencil& stencil) const {
  for (int a = 0; a < 3; ++a) {
    const auto& s = stencil.axis[a];
    if (s.first < 0 || s.first + s.width > extent_[a]) return false;
  }
  return true;
}

Eigen::Vector3d interpolate_velocity(const LocalGrid& grid, const Stencil& stencil) {
  Eigen::Vector3d u = Eigen::Vector3d::Zero();
  for_each_cell(grid, stencil, [&](std::size_t c, double w) {
    const double half_force_factor = 0.5 / grid.rho[c];
    for (int a = 0; a < 3; ++a) u[a] += w * (grid.velocity[a][c] + half_force_factor * grid.force[a][c]);
  });
  return u;
}

void spread_force(LocalGrid& grid, const Stencil& stencil, const Eigen::Vector3d& f, double volume) {
  for_each_cell(grid, stencil, [&](std::size_t c, double w) {
    for (int a = 0; a < 3; ++a) grid.force[a][c] += w * volume * f[a];
  });
}

ForcingResult multi_direct_forcing(LocalGrid& grid, const Markers& markers, const ForcingOptions& options) {
  std::vector<Stencil> stencils(markers.size());
  std::vector<double> marker_rho(markers.size());
  for (std::size_t l = 0; l < markers.size(); ++l) {
    stencils[l] = local_stencil(grid, options.kernel, markers.position[l]);
    if (!grid.contains(stencils[l]))
      throw std::logic_error("multi_direct_forcing: a marker's stencil leaves the cell box");
    marker_rho[l] = interpolate_density(grid, stencils[l]);
  }
  std::vector<double> half_over_rho(grid.cell_count());
  for (std::size_t c = 0; c < half_over_rho.size(); ++c) half_over_rho[c] = 0.5 / grid.rho[c];
  const auto slip_at_markers = [&] {
    std::vector<Eigen::Vector3d> slip(markers.size());
    for (std::size_t l = 0; l < markers.size(); ++l)
      slip[l] = markers.target_velocity[l] - interpolate_current_velocity(grid, half_over_rho, stencils[l]);
    return slip;
  };

  // Each sweep interpolates all markers first and spreads afterwards (a Jacobi sweep), so the
  // result does not depend on the order of the markers. The first sweep's slips are the slips
  // before any forcing.
  ForcingResult result;
  result.marker_force.assign(markers.size(), Eigen::Vector3d::Zero());
  for (int sweep = 0; sweep < options.iterations; ++sweep) {
    const std::vector<Eigen::Vector3d> slip = slip_at_markers();
    if (sweep == 0) {
      const SlipStats before = slip_stats(slip);
      result.slip_max_before = before.max;
      result.slip_rms_before = before.rms;
    }
    for (std::size_t l = 0; l < markers.size(); ++l) {
      const Eigen::Vector3d increment = 2.0 * marker_rho[l] * slip[l];
      spread_force(grid, stencils[l], increment, markers.volume[l]);
      result.marker_force[l] += increment;
    }
  }

  const SlipStats after = slip_stats(slip_at_markers());
  if (options.iterations == 0) {
    result.slip_max_before = after.max;
    result.slip_rms_before = after.rms;
  }
  result.slip_max_after = after.max;
  result.slip_rms_after = after.rms;
  return result;
}

}  // namespace settle::ibm
