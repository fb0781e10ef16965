#include "body/shape.hpp"

#include <cmath>
#include <numbers>
#include <numeric>

#include <fmt/core.h>

#include "common/error.hpp"

namespace settle::body {

double SurfaceMarkers::total_area() const { return std::accumulate(areas.begin(), areas.end(), 0.0); }

void SurfaceMarkers::append(const Eigen::Vector3d& position, const Eigen::Vector3d& normal, double area) {
  positions.push_back(position);
  normals.push_back(normal);
  areas.push_back(area);
}

MassProperties Shape::mass_properties(double density) const {
  return mass_properties_from_moments(volume_moments(), density);
}

double Shape::equivalent_diameter() const { return std::cbrt(6.0 * volume() / std::numbers::pi); }

// Regula falsi with the Illinois modification: superlinear, and it never leaves the bracket.
double Shape::surface_crossing(const Eigen::Vector3d& outside, const Eigen::Vector3d& inside) const {
  const Eigen::Vector3d along = inside - outside;
  const auto phi = [&](double t) { return signed_distance(outside + t * along); };
  double t0 = 0.0, t1 = 1.0, f0 = phi(0.0), f1 = phi(1.0);
  // The inside test and the signed distance may disagree by round-off at the surface itself.
  if (!(f0 > 0.0)) return 0.0;
  if (!(f1 < 0.0)) return 1.0;
  // A billionth of the segment: far below any effect on the interpolated bounce-back's weights.
  const double tolerance = 1e-9 * along.norm();
  int last_side = 0;
  for (int iteration = 0; iteration < 40; ++iteration) {
    const double t = t0 + f0 * (t1 - t0) / (f0 - f1);
    const double f = phi(t);
    if (std::abs(f) < tolerance || t1 - t0 < 1e-12) return t;
    if (f > 0.0) {
      t0 = t, f0 = f;
      if (last_side == 1) f1 *= 0.5;
      last_side = 1;
    } else {
      t1 = t, f1 = f;
      if (last_side == -1) f0 *= 0.5;
      last_side = -1;
    }
  }
  return 0.5 * (t0 + t1);
}

void Shape::surface_crossings(const Eigen::Vector3d& outside, std::span<const Eigen::Vector3d> insides,
                              std::span<double> t) const {
  for (std::size_t k = 0; k < insides.size(); ++k) t[k] = surface_crossing(outside, insides[k]);
}

double Shape::width(const Eigen::Vector3d& direction) const { return support(direction) + support(-direction); }

void validate_marker_spacing(double spacing, double surface_area, const char* what) {
  if (!std::isfinite(spacing) || spacing <= 0.0) {
    throw InputError(fmt::format("{}: must be finite and > 0, got {}", what, spacing));
  }
  // The marker count is about area / h^2. Below 4 the request is a unit mistake; above a
  // million the clustering's fine patches (~20 per marker, 56 bytes each) would need over a
  // gigabyte, far beyond any resolved simulation (40 cells per diameter need ~5000 markers).
  const double count = surface_area / (spacing * spacing);
  if (count < 4.0) {
    throw InputError(fmt::format("{}: {} is too coarse for a surface of area {} (fewer than 4 markers)", what, spacing,
                                 surface_area));
  }
  if (count > 1.0e6) {
    throw InputError(fmt::format("{}: {} is too fine for a surface of area {} (more than a million markers)", what,
                                 spacing, surface_area));
  }
}

Eigen::Vector3d unit_direction(const Eigen::Vector3d& direction, const char* what) {
  const double norm = direction.norm();
  if (!std::isfinite(norm) || norm == 0.0) {
    throw InputError(fmt::format("{}: must be a finite non-zero vector, got [{}, {}, {}]", what, direction.x(),
                                 direction.y(), direction.z()));
  }
  return direction / norm;
}

}  // namespace settle::body
