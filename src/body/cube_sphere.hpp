#pragma once
// Closed triangulations of star-shaped surfaces (ellipsoids, superellipsoids) from a gridded
// cube: the surface of [-1, 1]^3 is cut into an equiangular grid (u = tan(angle), angles evenly
// spaced in [-pi/4, pi/4], the "cubed sphere" of Ronchi, Iacono and Paolucci 1996, J. Comput.
// Phys. 124, 93-114, doi:10.1006/jcph.1996.0047) with cells[i] intervals along axis i, and each
// grid vertex is sent to the surface along its ray. Unlike latitude-longitude grids there are
// no poles, and the three counts let an elongated body get more cells along its long axis.
#include <array>
#include <functional>
#include <limits>

#include <Eigen/Dense>

#include "body/triangle_mesh.hpp"

namespace settle::body {

/// Maps a direction (a point on the cube surface) to the surface point on its ray.
using RadialMap = std::function<Eigen::Vector3d(const Eigen::Vector3d&)>;

/// The triangulation: vertices shared between faces (watertight), triangles outward
/// (counterclockwise seen from outside), each grid quad split along its shorter diagonal.
TriangleMesh cube_sphere_mesh(const std::array<int, 3>& cells, const RadialMap& to_surface);

/// A cube-sphere triangulation whose grid edges are all <= max_edge: starts from cells
/// proportional to the body's half-extents and refines each axis by its measured longest edge.
/// At most `max_triangles`: beyond it the cells of all three axes are scaled down by one factor
/// and the edges are longer than max_edge. The grid suits round bodies; a needle's tip face
/// spans a good part of its length, so the count grows as (length / max_edge)^2 whatever the
/// thickness (a 500:1 needle at d_eq/100 would need 2e8 triangles, 24 GB).
TriangleMesh cube_sphere_mesh_with_max_edge(const Eigen::Vector3d& half_extents, double max_edge,
                                            const RadialMap& to_surface,
                                            double max_triangles = std::numeric_limits<double>::infinity());

}  // namespace settle::body
