#include "ibm/forcing.hpp"

#include <omp.h>

#include <algorithm>
#include <cmath>
#include <stdexcept>

namespace settle::ibm {
namespace {

Stencil local_stencil(const LocalGrid& grid, DeltaKernel kernel, const Eigen::Vector3d& x) {
  const auto& o = grid.origin();
  return stencil_at(kernel, x.x() - o[0], x.y() - o[1], x.z() - o[2]);
}

// Below this many markers the forcing runs on one thread: a few dozen markers take about as long
// as the parallel region's wake-up and its barriers, a few microseconds (docs/performance.md,
// "Small grids").
constexpr std::size_t kMarkersWorthThreads = 64;

// The box's planes k in [begin, end).
struct PlaneRange {
  int begin = 0, end = 0;
};

// This thread's share of the box's planes: contiguous, so that each cell is written by one thread.
PlaneRange planes_of_this_thread(int planes) {
  const int threads = omp_get_num_threads(), thread = omp_get_thread_num();
  return {planes * thread / threads, planes * (thread + 1) / threads};
}

// Applies `visit(cell_index, weight)` to the cells of a stencil that lie in `planes`, in a fixed
// order, so that the sums are the same on every run and thread count.
template <class Visit>
void for_each_cell_in(const LocalGrid& grid, const Stencil& s, PlaneRange planes, Visit&& visit) {
  const int k_begin = std::max(0, planes.begin - s.axis[2].first);
  const int k_end = std::min(s.axis[2].width, planes.end - s.axis[2].first);
  for (int k = k_begin; k < k_end; ++k)
    for (int j = 0; j < s.axis[1].width; ++j)
      for (int i = 0; i < s.axis[0].width; ++i) {
        const std::size_t c = grid.index(s.axis[0].first + i, s.axis[1].first + j, s.axis[2].first + k);
        visit(c, s.weight(i, j, k));
      }
}

template <class Visit>
void for_each_cell(const LocalGrid& grid, const Stencil& s, Visit&& visit) {
  for_each_cell_in(grid, s, {s.axis[2].first, s.axis[2].first + s.axis[2].width}, visit);
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

void spread_force_in(LocalGrid& grid, const Stencil& stencil, const Eigen::Vector3d& f, double volume,
                     PlaneRange planes) {
  for_each_cell_in(grid, stencil, planes, [&](std::size_t c, double w) {
    for (int a = 0; a < 3; ++a) grid.force[a][c] += w * volume * f[a];
  });
}

// What one forcing keeps between its sweeps. Shared by the threads of its parallel region; the
// functions below are called by every thread of it and share their loops among them.
struct ForcingWork {
  explicit ForcingWork(const LocalGrid& grid, const Markers& markers)
      : stencils(markers.size()), marker_rho(markers.size()), half_over_rho(grid.cell_count()), slip(markers.size()) {}
  std::vector<Stencil> stencils;
  std::vector<double> marker_rho;
  // 1 / (2 rho) of each cell, computed once per forcing rather than at every interpolation.
  std::vector<double> half_over_rho;
  std::vector<Eigen::Vector3d> slip;
};

// Sets `outside` (shared by the region's threads; read after the loop's closing barrier) when a
// marker's stencil leaves the box.
void place_stencils(const LocalGrid& grid, const Markers& markers, DeltaKernel kernel, ForcingWork& work,
                    bool& outside) {
  const auto cells = static_cast<std::ptrdiff_t>(work.half_over_rho.size());
#pragma omp for schedule(static) nowait
  for (std::ptrdiff_t c = 0; c < cells; ++c)
    work.half_over_rho[static_cast<std::size_t>(c)] = 0.5 / grid.rho[static_cast<std::size_t>(c)];
  const auto count = static_cast<std::ptrdiff_t>(markers.size());
#pragma omp for schedule(static)
  for (std::ptrdiff_t l = 0; l < count; ++l) {
    const auto m = static_cast<std::size_t>(l);
    work.stencils[m] = local_stencil(grid, kernel, markers.position[m]);
    if (!grid.contains(work.stencils[m])) {
#pragma omp atomic write
      outside = true;
      continue;
    }
    work.marker_rho[m] = interpolate_density(grid, work.stencils[m]);
  }
}

void measure_slips(const LocalGrid& grid, const Markers& markers, ForcingWork& work) {
  const auto count = static_cast<std::ptrdiff_t>(markers.size());
#pragma omp for schedule(static)
  for (std::ptrdiff_t l = 0; l < count; ++l) {
    const auto m = static_cast<std::size_t>(l);
    work.slip[m] =
        markers.target_velocity[m] - interpolate_current_velocity(grid, work.half_over_rho, work.stencils[m]);
  }
}

// Each thread adds every marker's share to its own slab of planes, in marker order: the same sums
// as on one thread, bit for bit.
void spread_slips(LocalGrid& grid, const Markers& markers, const ForcingWork& work, PlaneRange planes) {
  for (std::size_t m = 0; m < markers.size(); ++m)
    spread_force_in(grid, work.stencils[m], 2.0 * work.marker_rho[m] * work.slip[m], markers.volume[m], planes);
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
  spread_force_in(grid, stencil, f, volume, {0, grid.extent()[2]});
}

ForcingResult multi_direct_forcing(LocalGrid& grid, const Markers& markers, const ForcingOptions& options) {
  ForcingWork work(grid, markers);
  ForcingResult result;
  result.marker_force.assign(markers.size(), Eigen::Vector3d::Zero());
  SlipStats before;
  bool outside = false;
  // One parallel region for the whole forcing. Each sweep interpolates all markers first and
  // spreads afterwards (a Jacobi sweep), so the result does not depend on the order of the markers.
#pragma omp parallel if (markers.size() >= kMarkersWorthThreads)
  {
    place_stencils(grid, markers, options.kernel, work, outside);
    const PlaneRange planes = planes_of_this_thread(grid.extent()[2]);
    for (int sweep = 0; sweep < options.iterations && !outside; ++sweep) {
      measure_slips(grid, markers, work);
#pragma omp single nowait
      {
        // The first sweep's slips are the slips before any forcing. No thread overwrites the
        // slips before the barrier that closes this sweep.
        if (sweep == 0) before = slip_stats(work.slip);
        for (std::size_t m = 0; m < markers.size(); ++m)
          result.marker_force[m] += 2.0 * work.marker_rho[m] * work.slip[m];
      }
      spread_slips(grid, markers, work, planes);
#pragma omp barrier
    }
    if (!outside) measure_slips(grid, markers, work);
  }
  if (outside) throw std::logic_error("multi_direct_forcing: a marker's stencil leaves the cell box");

  const SlipStats after = slip_stats(work.slip);
  if (options.iterations == 0) before = after;
  result.slip_max_before = before.max;
  result.slip_rms_before = before.rms;
  result.slip_max_after = after.max;
  result.slip_rms_after = after.rms;
  return result;
}

}  // namespace settle::ibm
