#pragma once
// Closed triangle meshes: topology checks, exact polyhedral mass properties and the projected
// areas of convex polyhedra.
#include <array>
#include <string>
#include <vector>

#include <Eigen/Dense>

#include "body/mass_properties.hpp"

namespace settle::body {

/// An indexed triangle mesh. Triangles list vertex indices counterclockwise when seen from
/// outside (the STL convention), so (v1 - v0) x (v2 - v0) points outward.
struct TriangleMesh {
  std::vector<Eigen::Vector3d> vertices;
  std::vector<std::array<int, 3>> triangles;
};

/// For each triangle t and each of its edges k (from vertex k to vertex k+1 mod 3), the
/// triangle on the other side of that edge.
using EdgeNeighbours = std::vector<std::array<int, 3>>;

/// Checks that the mesh bounds a solid without ambiguity and returns the edge neighbours.
/// Refused with settle::InputError (the message starts with `source`): no triangles, a vertex
/// index out of range, non-finite coordinates, a triangle with a repeated vertex or (near-)zero
/// area (area <= 1e-10 of its longest edge squared), an edge used by one triangle only (not
/// watertight), by more than two (non-manifold), or twice in the same direction (inconsistent
/// orientation).
EdgeNeighbours check_closed_and_oriented(const TriangleMesh& mesh, const std::string& source);

/// Exact volume moments of the polyhedron (signed: negative for an inward-oriented mesh) by
/// the divergence theorem, summed over the signed tetrahedra spanned by each face and a
/// reference point (Mirtich 1996, J. Graphics Tools 1(2) 31-50, doi:10.1080/10867651.1996.10487458;
/// the tetrahedron covariance form of Blow and Binstock 2004). The reference point is the mean
/// vertex, so meshes far from the origin lose no accuracy.
VolumeMoments polyhedron_moments(const TriangleMesh& mesh);

double mesh_surface_area(const TriangleMesh& mesh);

/// Area-weighted outward normal of triangle t (its length is the triangle's area).
Eigen::Vector3d triangle_vector_area(const TriangleMesh& mesh, int t);

/// True when the closed mesh is one connected component and every edge is convex (the vertex
/// across each edge lies on or behind the face's plane, to 1e-9 of the mesh size).
bool is_convex(const TriangleMesh& mesh, const EdgeNeighbours& neighbours);

/// Shadow area of a convex closed polyhedron along a unit direction, exact by Cauchy's
/// projection formula: A(n) = 1/2 sum_f |n . N_f| A_f.
double convex_projected_area(const TriangleMesh& mesh, const Eigen::Vector3d& direction);

/// Mean shadow area over the directions perpendicular to the unit `axis`, exact for a convex
/// polyhedron: averaging |m . N_f| over m on that circle gives (2/pi) |N_f perpendicular to the
/// axis|, so the mean is (1/pi) sum_f A_f |N_f - (N_f . axis) axis|.
double convex_mean_projected_area_perpendicular(const TriangleMesh& mesh, const Eigen::Vector3d& axis);

/// Axis-aligned bounds of the vertices.
std::array<Eigen::Vector3d, 2> vertex_bounds(const TriangleMesh& mesh);

}  // namespace settle::body
