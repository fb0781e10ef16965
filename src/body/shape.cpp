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
    throw InputError(fmt::format("{}: {} is too coarse for a surface of area {} (fewer than 4 markers)", what,
                                 spacing, surface_area));
  }
  if (count > 1.0e6) {
    throw InputError(fmt::format("{}: {} is too fine for a surface of area {} (more than a million markers)",
                                 what, spacing, surface_area));
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
