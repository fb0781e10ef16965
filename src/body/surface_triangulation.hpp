#pragma once
// A closed triangulation of any shape's surface, for drawing it (the VTK surface files).
#include "body/shape.hpp"
#include "body/triangle_mesh.hpp"

namespace settle::body {

/// A closed, outward-oriented triangulation of the shape's surface in the body frame (same units
/// as the shape), built once and placed at each output's pose (io::write_surface_vtp).
///  - Meshes (MeshShape): the mesh's own triangles; max_edge is ignored.
///  - Analytic shapes: the cube-sphere grid of cube_sphere.hpp with grid lines cut into
///    edges of max_edge or less (each grid quad is split along its shorter diagonal, so triangle
///    edges reach about sqrt(2) max_edge), each grid point u on the cube [-1, 1]^3 sent to the surface along the ray
///    from the centroid in direction (h . u), h the half-extents of the bounding box, by bisection
///    on the inside test to 1e-13 of the bounding radius. Stretching the ray directions by h keeps
///    the triangles of elongated and flat bodies even, and puts the cube's edges and corners
///    exactly on a cuboid's, so a cuboid comes out exact. Valid for bodies that are star-shaped
///    about the centroid: every analytic shape is (all are convex). Sharp edges that the grid
///    does not follow (a cylinder's rims) are cut by up to one triangle.
/// Throws std::invalid_argument for max_edge not finite and > 0, or so small that the grid would
/// need more than about ten million triangles.
TriangleMesh surface_triangulation(const Shape& shape, double max_edge);

}  // namespace settle::body
