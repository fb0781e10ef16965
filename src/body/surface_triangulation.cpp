#include "body/surface_triangulation.hpp"

#include <cmath>
#include <stdexcept>

#include <fmt/core.h>

#include "body/cube_sphere.hpp"
#include "body/mesh_shape.hpp"
#include "common/bisection.hpp"

namespace settle::body {
namespace {

/// The point where the ray from the centroid along `direction` leaves the body, by bisection
/// on the exact inside test (assumes the body is star-shaped about the centroid).
Eigen::Vector3d ray_exit(const Shape& shape, const Eigen::Vector3d& direction) {
  const Eigen::Vector3d d = direction.normalized();
  const double radius = shape.bounding_radius();
  const double inside = 0.0;
  // A little beyond the bounding radius is outside by its definition.
  const double outside = radius * (1.0 + 1e-6);
  if (shape.contains(outside * d)) throw std::logic_error("surface_triangulation: bounding radius is too small");
  const auto side = [&](double distance) {
    return shape.contains(distance * d) ? BisectionSide::below : BisectionSide::above;
  };
  // 1e-13 of the radius: far below anything a grid resolves, and some 500 ulp above the
  // round-off of the inside tests of bodies of size ~1. Reached in about 43 halvings; the step
  // limit is only a guard.
  const auto converged = [&](double lo, double hi) { return !(hi - lo > 1e-13 * radius); };
  return bisect({inside, outside}, side, converged, 200).middle() * d;
}

// Cube-sphere grid sizes: 1.6 h / max_edge cells per axis to start with (cube_sphere.cpp), which
// refinement raises by at most about pi/2 (the equiangular grid's largest stretch).
constexpr double kMaxTriangles = 1.0e7;

void check_triangle_budget(const Eigen::Vector3d& half_extents, double max_edge) {
  const Eigen::Vector3d cells = 1.6 * 1.6 * half_extents / max_edge + Eigen::Vector3d::Constant(2.0);
  const double triangles = 4.0 * (cells(0) * cells(1) + cells(1) * cells(2) + cells(2) * cells(0));
  if (triangles > kMaxTriangles)
    throw std::invalid_argument(
        fmt::format("surface_triangulation: max_edge {} would need about {:.3g} triangles (limit {:.0g})", max_edge,
                    triangles, kMaxTriangles));
}

}  // namespace

TriangleMesh surface_triangulation(const Shape& shape, double max_edge) {
  if (const auto* mesh = dynamic_cast<const MeshShape*>(&shape)) return mesh->body_mesh();
  if (!std::isfinite(max_edge) || max_edge <= 0.0)
    throw std::invalid_argument(
        fmt::format("surface_triangulation: max_edge must be finite and > 0, got {}", max_edge));
  const Aabb box = shape.bounding_box();
  const Eigen::Vector3d half_extents = box.lower.cwiseAbs().cwiseMax(box.upper.cwiseAbs());
  check_triangle_budget(half_extents, max_edge);
  if (!shape.contains(Eigen::Vector3d::Zero()))
    throw std::logic_error("surface_triangulation: the centroid of a " + shape.kind() + " lies outside it");
  return cube_sphere_mesh_with_max_edge(
      half_extents, max_edge, [&](const Eigen::Vector3d& u) { return ray_exit(shape, half_extents.cwiseProduct(u)); });
}

}  // namespace settle::body
