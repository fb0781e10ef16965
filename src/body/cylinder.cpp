#include "body/cylinder.hpp"

#include <algorithm>
#include <cmath>
#include <numbers>

#include <fmt/core.h>

#include "body/carlson.hpp"
#include "common/error.hpp"
#include "common/require.hpp"

namespace settle::body {
namespace {

// Unit radial direction of p, or x when p is on the axis.
Eigen::Vector3d radial_unit(const Eigen::Vector3d& p) {
  const double rho = std::hypot(p.x(), p.y());
  return rho > 0.0 ? Eigen::Vector3d(p.x() / rho, p.y() / rho, 0.0) : Eigen::Vector3d::UnitX();
}

void add_cap(SurfaceMarkers& markers, double radius, double z, double normal_z, double spacing) {
  const int rings = std::max(0, static_cast<int>(std::lround(radius / spacing - 0.5)));
  const double width = radius / (rings + 0.5);
  const double golden_angle = std::numbers::pi * (3.0 - std::sqrt(5.0));
  const Eigen::Vector3d normal(0.0, 0.0, normal_z);
  markers.append({0.0, 0.0, z}, normal, std::numbers::pi * 0.25 * width * width);
  for (int k = 1; k <= rings; ++k) {
    const double inner = (k - 0.5) * width, outer = (k + 0.5) * width;
    const int count = std::max(1, static_cast<int>(std::lround(2.0 * std::numbers::pi * k)));
    const double area = std::numbers::pi * (outer * outer - inner * inner) / count;
    const double r = std::sqrt(0.5 * (inner * inner + outer * outer));  // halves the ring's area
    for (int j = 0; j < count; ++j) {
      const double phi = 2.0 * std::numbers::pi * j / count + golden_angle * k;
      markers.append({r * std::cos(phi), r * std::sin(phi), z}, normal, area);
    }
  }
}

}  // namespace

Cylinder::Cylinder(double diameter, double length) : radius_(0.5 * diameter), length_(length) {
  require_positive(diameter, "cylinder diameter");
  require_positive(length, "cylinder length");
}

bool Cylinder::contains(const Eigen::Vector3d& p) const {
  return p.x() * p.x() + p.y() * p.y() <= radius_ * radius_ && std::abs(p.z()) <= 0.5 * length_;
}

double Cylinder::signed_distance(const Eigen::Vector3d& p) const {
  const double qr = std::hypot(p.x(), p.y()) - radius_;
  const double qz = std::abs(p.z()) - 0.5 * length_;
  const double outside = std::hypot(std::max(qr, 0.0), std::max(qz, 0.0));
  return outside + std::min(std::max(qr, qz), 0.0);
}

Eigen::Vector3d Cylinder::closest_surface_point(const Eigen::Vector3d& p) const {
  const double rho = std::hypot(p.x(), p.y());
  const double half = 0.5 * length_;
  const Eigen::Vector3d radial = radial_unit(p);
  const double qr = rho - radius_, qz = std::abs(p.z()) - half;
  const double cap_z = std::copysign(half, p.z());
  if (qr <= 0.0 && qz <= 0.0) {  // inside: the nearer of mantle and cap
    if (qr >= qz) return radius_ * radial + Eigen::Vector3d(0.0, 0.0, p.z());
    return {p.x(), p.y(), cap_z};
  }
  const double r = std::min(rho, radius_);
  const double z = std::clamp(p.z(), -half, half);
  return r * radial + Eigen::Vector3d(0.0, 0.0, z);
}

Eigen::Vector3d Cylinder::outward_normal(const Eigen::Vector3d& surface_point) const {
  const double qr = std::hypot(surface_point.x(), surface_point.y()) - radius_;
  const double qz = std::abs(surface_point.z()) - 0.5 * length_;
  if (qr >= qz) return radial_unit(surface_point);
  return {0.0, 0.0, std::copysign(1.0, surface_point.z())};
}

double Cylinder::bounding_radius() const { return std::hypot(radius_, 0.5 * length_); }

Aabb Cylinder::bounding_box() const {
  const Eigen::Vector3d half(radius_, radius_, 0.5 * length_);
  return {-half, half};
}

double Cylinder::support(const Eigen::Vector3d& n) const {
  return radius_ * std::hypot(n.x(), n.y()) + 0.5 * length_ * std::abs(n.z());
}

VolumeMoments Cylinder::volume_moments() const {
  VolumeMoments m;
  m.volume = std::numbers::pi * radius_ * radius_ * length_;
  const double r2 = radius_ * radius_;
  m.second_moment = (m.volume * Eigen::Vector3d(r2 / 4.0, r2 / 4.0, length_ * length_ / 12.0)).asDiagonal();
  return m;
}

double Cylinder::surface_area() const {
  return 2.0 * std::numbers::pi * radius_ * radius_ + 2.0 * std::numbers::pi * radius_ * length_;
}

double Cylinder::projected_area(const Eigen::Vector3d& n) const {
  const double nz = std::min(1.0, std::abs(n.z()));
  return std::numbers::pi * radius_ * radius_ * nz + 2.0 * radius_ * length_ * std::sqrt(1.0 - nz * nz);
}

double Cylinder::mean_projected_area_perpendicular(const Eigen::Vector3d& axis) const {
  // On the circle perpendicular to the axis, m . e_z = s cos(phi) with s = |e_z - (e_z . f) f|.
  const double fz = std::min(1.0, std::abs(axis.normalized().z()));
  const double s = std::sqrt(1.0 - fz * fz);
  return 2.0 * radius_ * radius_ * s + 4.0 * radius_ * length_ / std::numbers::pi * complete_elliptic_e(s);
}

SurfaceMarkers Cylinder::surface_markers(double spacing) const {
  validate_marker_spacing(spacing, surface_area());
  SurfaceMarkers markers;
  markers.spacing = spacing;
  const double half = 0.5 * length_;
  add_cap(markers, radius_, half, 1.0, spacing);
  add_cap(markers, radius_, -half, -1.0, spacing);
  const int around = std::max(3, static_cast<int>(std::lround(2.0 * std::numbers::pi * radius_ / spacing)));
  const int along = std::max(1, static_cast<int>(std::lround(length_ / spacing)));
  const double area = 2.0 * std::numbers::pi * radius_ * length_ / (around * along);
  for (int i = 0; i < along; ++i) {
    const double z = -half + (i + 0.5) * length_ / along;
    for (int j = 0; j < around; ++j) {
      // Alternate rows are offset by half a cell, a staggered (near-hexagonal) pattern.
      const double phi = 2.0 * std::numbers::pi * (j + 0.5 * (i % 2)) / around;
      const Eigen::Vector3d radial(std::cos(phi), std::sin(phi), 0.0);
      markers.append(radius_ * radial + Eigen::Vector3d(0.0, 0.0, z), radial, area);
    }
  }
  return markers;
}

}  // namespace settle::body
