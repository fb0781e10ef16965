#pragma once
// Construction and measurement of surface markers (see SurfaceMarkers in shape.hpp).
//
// Two constructions serve the curved shapes:
//  - the sphere uses the spherical Fibonacci lattice: N = round(4 pi r^2 / h^2) points, each at
//    the centre of one of N equal-area latitude bands, with the golden angle between successive
//    points (Gonzalez 2010, Math. Geosci. 42, 49-64, doi:10.1007/s11004-009-9257-x). Every point
//    represents exactly 4 pi r^2 / N, so the areas sum to the exact area.
//  - every other curved surface (spheroids, ellipsoids, superellipsoids, meshes) is first cut
//    into small patches (a fine triangulation with edges <= h/4 whose vertices lie on the exact
//    surface), which are then grouped into clusters of about h^2 by Lloyd's algorithm for a
//    centroidal Voronoi tessellation on the surface (Du, Faber and Gunzburger 1999, SIAM Rev.
//    41, 637-676, doi:10.1137/S0036144599352836): seeds by dart throwing, then repeatedly each
//    patch joins its nearest seed and each seed moves to its cluster's area-weighted centroid,
//    projected back onto the surface. A marker sits at its cluster's seed and carries the
//    cluster's area, so the areas tile the triangulated surface exactly; the clusters converge
//    to near-regular hexagons (nearest-neighbour distance ~1.07 h). Patches only join seeds
//    whose normal is within 120 degrees of theirs, so the two sides of a thin plate never mix.
// Flat faces (cuboid faces, cylinder caps and mantle) use regular grids (see those shapes).
#include <cstdint>
#include <functional>
#include <vector>

#include <Eigen/Dense>

#include "body/shape.hpp"
#include "body/triangle_mesh.hpp"

namespace settle::body {

/// Longest edge of the fine triangulations that cluster_patches_into_markers groups, as a
/// fraction of the marker spacing: about 20 patches per marker, enough for the clusters to
/// settle into regular shapes (finer patches cost time and change the measured spacing little).
inline constexpr double kPatchEdgeFraction = 1.0 / 3.0;

/// Markers on the sphere of the given radius centred at the origin (Fibonacci lattice).
SurfaceMarkers fibonacci_sphere_markers(double radius, double spacing);

/// Small pieces of a surface: centre, unit outward normal and area of each.
struct SurfacePatches {
  std::vector<Eigen::Vector3d> centres;
  std::vector<Eigen::Vector3d> normals;
  std::vector<double> areas;
  double total_area() const;
};

/// Patches from a closed mesh, each triangle cut into k^2 congruent triangles with k the
/// smallest integer making every edge <= max_edge.
SurfacePatches patches_from_mesh(const TriangleMesh& mesh, double max_edge);

/// Maps a point near the surface onto the surface.
using SurfaceProjection = std::function<Eigen::Vector3d(const Eigen::Vector3d&)>;

/// Groups patches (much smaller than h) into markers of mean area about h^2 by Lloyd's
/// iteration (see the file comment). Normals are the clusters' mean normals; a shape with an
/// exact normal replaces them. Deterministic for a given seed.
SurfaceMarkers cluster_patches_into_markers(const SurfacePatches& patches, double spacing,
                                            const SurfaceProjection& project, std::uint64_t seed = 20240601);

/// For each marker, the distance to its nearest other marker.
std::vector<double> nearest_marker_distances(const SurfaceMarkers& markers);

/// For each query point, the distance to the nearest marker.
std::vector<double> distances_to_nearest_marker(const SurfaceMarkers& markers,
                                                const std::vector<Eigen::Vector3d>& points);

}  // namespace settle::body
