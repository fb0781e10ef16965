#include "body/surface_markers.hpp"

#include <algorithm>
#include <cmath>
#include <numbers>
#include <numeric>
#include <random>

#include "body/point_grid.hpp"

namespace settle::body {
namespace {

// Dart-throwing radius in units of h. Maximal Poisson-disk sets of radius r have about
// 0.7 A / r^2 points, so about 0.84 h would give A / h^2 seeds; darts are thrown at patch
// centres only, which packs them less tightly, and 0.80 h brings the mean marker area to
// h^2 (measured 0.99-1.02 h^2 across the shapes in tests/body).
constexpr double kDartRadius = 0.80;
// Patches join only seeds whose normal is within 120 degrees (cos > -0.5) of their own.
constexpr double kNormalCompatibility = -0.5;
// Lloyd's iteration stalls at moves of ~0.03 h, the jitter of single patches (~h/3 across,
// 1/20 of a cluster) changing cluster; the layout is settled long before this cap.
constexpr int kMaxLloydIterations = 20;
constexpr double kConvergedMove = 0.02;   // of h
constexpr double kSmallestCluster = 0.2;  // of h^2

// Fisher-Yates with raw 64-bit draws: std::shuffle's algorithm is implementation-defined, and
// the markers should not change with the standard library.
std::vector<int> shuffled_indices(std::size_t n, std::uint64_t seed) {
  std::vector<int> order(n);
  std::iota(order.begin(), order.end(), 0);
  std::mt19937_64 random(seed);
  for (std::size_t i = n; i > 1; --i) std::swap(order[i - 1], order[random() % i]);
  return order;
}

struct Seeds {
  std::vector<Eigen::Vector3d> positions;
  std::vector<Eigen::Vector3d> normals;
};

Seeds throw_darts(const SurfacePatches& patches, double radius, std::uint64_t seed) {
  Seeds seeds;
  // The grid is rebuilt lazily: accepted seeds go to a per-cell map keyed like PointGrid.
  std::unordered_map<std::uint64_t, std::vector<int>> cells;
  auto cell_of = [&](const Eigen::Vector3d& p) { return Eigen::Vector3i((p / radius).array().floor().cast<int>()); };
  auto key = [](const Eigen::Vector3i& c) {
    auto part = [](int v) { return static_cast<std::uint64_t>(static_cast<std::uint32_t>(v + (1 << 20)) & 0x1FFFFFu); };
    return part(c.x()) | (part(c.y()) << 21) | (part(c.z()) << 42);
  };
  for (int k : shuffled_indices(patches.centres.size(), seed)) {
    const Eigen::Vector3d& p = patches.centres[k];
    const Eigen::Vector3i c = cell_of(p);
    bool blocked = false;
    for (int dz = -1; dz <= 1 && !blocked; ++dz) {
      for (int dy = -1; dy <= 1 && !blocked; ++dy) {
        for (int dx = -1; dx <= 1 && !blocked; ++dx) {
          const auto it = cells.find(key(c + Eigen::Vector3i(dx, dy, dz)));
          if (it == cells.end()) continue;
          for (int s : it->second) {
            if ((seeds.positions[s] - p).squaredNorm() < radius * radius &&
                seeds.normals[s].dot(patches.normals[k]) > kNormalCompatibility) {
              blocked = true;
              break;
            }
          }
        }
      }
    }
    if (blocked) continue;
    cells[key(c)].push_back(static_cast<int>(seeds.positions.size()));
    seeds.positions.push_back(p);
    seeds.normals.push_back(patches.normals[k]);
  }
  return seeds;
}

struct Clusters {
  std::vector<double> area;
  std::vector<Eigen::Vector3d> weighted_centre;
  std::vector<Eigen::Vector3d> weighted_normal;
};

Clusters assign_patches(const SurfacePatches& patches, const Seeds& seeds, double spacing) {
  const PointGrid grid(seeds.positions, spacing);
  const std::ptrdiff_t patch_count = static_cast<std::ptrdiff_t>(patches.centres.size());
  // The searches run in parallel; the sums below run in patch order, so the result does not
  // depend on the number of threads.
  std::vector<int> owner(patches.centres.size());
#pragma omp parallel for schedule(static)
  for (std::ptrdiff_t k = 0; k < patch_count; ++k) {
    const Eigen::Vector3d& normal = patches.normals[k];
    int s =
        grid.nearest(patches.centres[k], [&](int i) { return seeds.normals[i].dot(normal) > kNormalCompatibility; });
    if (s < 0) s = grid.nearest(patches.centres[k]);  // no compatible seed anywhere: any seed
    owner[k] = s;
  }
  Clusters clusters;
  const std::size_t n = seeds.positions.size();
  clusters.area.assign(n, 0.0);
  clusters.weighted_centre.assign(n, Eigen::Vector3d::Zero());
  clusters.weighted_normal.assign(n, Eigen::Vector3d::Zero());
  for (std::size_t k = 0; k < patches.centres.size(); ++k) {
    const double a = patches.areas[k];
    clusters.area[owner[k]] += a;
    clusters.weighted_centre[owner[k]] += a * patches.centres[k];
    clusters.weighted_normal[owner[k]] += a * patches.normals[k];
  }
  return clusters;
}

}  // namespace

SurfaceMarkers fibonacci_sphere_markers(double radius, double spacing) {
  const double area = 4.0 * std::numbers::pi * radius * radius;
  const int count = std::max(4, static_cast<int>(std::lround(area / (spacing * spacing))));
  const double golden_angle = std::numbers::pi * (3.0 - std::sqrt(5.0));
  SurfaceMarkers markers;
  markers.spacing = spacing;
  for (int i = 0; i < count; ++i) {
    const double z = 1.0 - (2.0 * i + 1.0) / count;  // centre of the i-th equal-area band
    const double rho = std::sqrt(std::max(0.0, 1.0 - z * z));
    const double phi = golden_angle * i;
    const Eigen::Vector3d unit(rho * std::cos(phi), rho * std::sin(phi), z);
    markers.append(radius * unit, unit, area / count);
  }
  return markers;
}

double SurfacePatches::total_area() const { return std::accumulate(areas.begin(), areas.end(), 0.0); }

SurfacePatches patches_from_mesh(const TriangleMesh& mesh, double max_edge) {
  SurfacePatches patches;
  for (const auto& tri : mesh.triangles) {
    const Eigen::Vector3d& a = mesh.vertices[tri[0]];
    const Eigen::Vector3d& b = mesh.vertices[tri[1]];
    const Eigen::Vector3d& c = mesh.vertices[tri[2]];
    const double longest = std::sqrt(std::max({(b - a).squaredNorm(), (c - b).squaredNorm(), (a - c).squaredNorm()}));
    const int k = std::max(1, static_cast<int>(std::ceil(longest / max_edge)));
    const Eigen::Vector3d du = (b - a) / k, dv = (c - a) / k;
    const Eigen::Vector3d vector_area = 0.5 * du.cross(dv);
    const double area = vector_area.norm();
    const Eigen::Vector3d normal = vector_area / area;
    // Row i, column j: the upright triangle (i, j) and, except on the diagonal, the inverted one.
    for (int i = 0; i < k; ++i) {
      for (int j = 0; i + j < k; ++j) {
        const Eigen::Vector3d corner = a + i * du + j * dv;
        patches.centres.push_back(corner + (du + dv) / 3.0);
        patches.normals.push_back(normal);
        patches.areas.push_back(area);
        if (i + j + 1 < k) {
          patches.centres.push_back(corner + 2.0 * (du + dv) / 3.0);
          patches.normals.push_back(normal);
          patches.areas.push_back(area);
        }
      }
    }
  }
  return patches;
}

SurfaceMarkers cluster_patches_into_markers(const SurfacePatches& patches, double spacing,
                                            const SurfaceProjection& project, std::uint64_t seed) {
  Seeds seeds = throw_darts(patches, kDartRadius * spacing, seed);
  Clusters clusters;
  for (int iteration = 0; iteration < kMaxLloydIterations; ++iteration) {
    clusters = assign_patches(patches, seeds, spacing);
    Seeds moved;
    double largest_move = 0.0;
    for (std::size_t s = 0; s < seeds.positions.size(); ++s) {
      // A seed left with a sliver (typically squeezed against a sharp edge or vertex) is
      // dropped; its neighbours take its patches at the next assignment.
      if (clusters.area[s] < kSmallestCluster * spacing * spacing) continue;
      const Eigen::Vector3d target = project(clusters.weighted_centre[s] / clusters.area[s]);
      largest_move = std::max(largest_move, (target - seeds.positions[s]).norm());
      moved.positions.push_back(target);
      moved.normals.push_back(clusters.weighted_normal[s].normalized());
    }
    seeds = std::move(moved);
    if (largest_move < kConvergedMove * spacing) break;
  }
  // The final areas belong to the final positions.
  clusters = assign_patches(patches, seeds, spacing);
  SurfaceMarkers markers;
  markers.spacing = spacing;
  for (std::size_t s = 0; s < seeds.positions.size(); ++s) {
    if (clusters.area[s] <= 0.0) continue;
    markers.append(seeds.positions[s], clusters.weighted_normal[s].normalized(), clusters.area[s]);
  }
  return markers;
}

std::vector<double> nearest_marker_distances(const SurfaceMarkers& markers) {
  const double cell = markers.spacing > 0.0 ? markers.spacing : 1.0;
  const PointGrid grid(markers.positions, cell);
  std::vector<double> distances(markers.size(), std::numeric_limits<double>::infinity());
  for (std::size_t i = 0; i < markers.size(); ++i) {
    const int j = grid.nearest(markers.positions[i], static_cast<int>(i));
    if (j >= 0) distances[i] = (markers.positions[j] - markers.positions[i]).norm();
  }
  return distances;
}

std::vector<double> distances_to_nearest_marker(const SurfaceMarkers& markers,
                                                const std::vector<Eigen::Vector3d>& points) {
  const double cell = markers.spacing > 0.0 ? markers.spacing : 1.0;
  const PointGrid grid(markers.positions, cell);
  std::vector<double> distances(points.size(), std::numeric_limits<double>::infinity());
  for (std::size_t i = 0; i < points.size(); ++i) {
    const int j = grid.nearest(points[i]);
    if (j >= 0) distances[i] = (markers.positions[j] - points[i]).norm();
  }
  return distances;
}

}  // namespace settle::body
