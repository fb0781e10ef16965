#include "body/cuboid.hpp"

#include <algorithm>
#include <cmath>
#include <numbers>

#include <fmt/core.h>

#include "common/error.hpp"

namespace settle::body {

Cuboid::Cuboid(const Eigen::Vector3d& size) : size_(size) {
  for (int i = 0; i < 3; ++i) {
    if (!std::isfinite(size_(i)) || size_(i) <= 0.0) {
      throw InputError(fmt::format("cuboid: edge length {} must be finite and > 0, got {}", "abc"[i], size_(i)));
    }
  }
}

bool Cuboid::contains(const Eigen::Vector3d& p) const { return (p.cwiseAbs() - 0.5 * size_).maxCoeff() <= 0.0; }

double Cuboid::signed_distance(const Eigen::Vector3d& p) const {
  const Eigen::Vector3d q = p.cwiseAbs() - 0.5 * size_;
  return q.cwiseMax(0.0).norm() + std::min(q.maxCoeff(), 0.0);
}

Eigen::Vector3d Cuboid::closest_surface_point(const Eigen::Vector3d& p) const {
  const Eigen::Vector3d half = 0.5 * size_;
  if (!contains(p)) return p.cwiseMax(-half).cwiseMin(half);
  // Inside: move to the nearest face.
  Eigen::Index face = 0;
  (p.cwiseAbs() - half).maxCoeff(&face);
  Eigen::Vector3d q = p;
  q(face) = std::copysign(half(face), p(face));
  return q;
}

Eigen::Vector3d Cuboid::outward_normal(const Eigen::Vector3d& surface_point) const {
  Eigen::Index face = 0;
  (surface_point.cwiseAbs() - 0.5 * size_).maxCoeff(&face);
  Eigen::Vector3d n = Eigen::Vector3d::Zero();
  n(face) = std::copysign(1.0, surface_point(face));
  return n;
}

double Cuboid::support(const Eigen::Vector3d& n) const { return 0.5 * n.cwiseAbs().dot(size_); }

VolumeMoments Cuboid::volume_moments() const {
  VolumeMoments m;
  m.volume = size_.prod();
  m.second_moment = (m.volume / 12.0 * size_.cwiseProduct(size_)).asDiagonal();
  return m;
}

double Cuboid::surface_area() const {
  return 2.0 * (size_.x() * size_.y() + size_.y() * size_.z() + size_.z() * size_.x());
}

double Cuboid::projected_area(const Eigen::Vector3d& n) const {
  return std::abs(n.x()) * size_.y() * size_.z() + std::abs(n.y()) * size_.x() * size_.z() +
         std::abs(n.z()) * size_.x() * size_.y();
}

double Cuboid::mean_projected_area_perpendicular(const Eigen::Vector3d& axis) const {
  const Eigen::Vector3d f = axis.normalized();
  double sum = 0.0;
  for (int i = 0; i < 3; ++i) {
    const double face_area = size_.prod() / size_(i);
    sum += face_area * std::sqrt(std::max(0.0, 1.0 - f(i) * f(i)));
  }
  return 2.0 / std::numbers::pi * sum;
}

SurfaceMarkers Cuboid::surface_markers(double spacing) const {
  validate_marker_spacing(spacing, surface_area());
  SurfaceMarkers markers;
  markers.spacing = spacing;
  for (int k = 0; k < 3; ++k) {
    const int a = (k + 1) % 3, b = (k + 2) % 3;
    const int na = std::max(1, static_cast<int>(std::lround(size_(a) / spacing)));
    const int nb = std::max(1, static_cast<int>(std::lround(size_(b) / spacing)));
    const double da = size_(a) / na, db = size_(b) / nb;
    for (double side : {-1.0, 1.0}) {
      Eigen::Vector3d normal = Eigen::Vector3d::Zero();
      normal(k) = side;
      for (int i = 0; i < na; ++i) {
        for (int j = 0; j < nb; ++j) {
          Eigen::Vector3d p;
          p(k) = side * 0.5 * size_(k);
          p(a) = -0.5 * size_(a) + (i + 0.5) * da;
          p(b) = -0.5 * size_(b) + (j + 0.5) * db;
          markers.append(p, normal, da * db);
        }
      }
    }
  }
  return markers;
}

}  // namespace settle::body
