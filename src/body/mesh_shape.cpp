#include "body/mesh_shape.hpp"

#include <algorithm>
#include <array>
#include <cmath>
#include <limits>
#include <numbers>
#include <numeric>
#include <optional>
#include <string_view>

#include <fmt/core.h>
#include <Eigen/Geometry>

#include "body/projected_area.hpp"
#include "body/stl_io.hpp"
#include "body/surface_markers.hpp"
#include "common/error.hpp"

namespace settle::body {
namespace {

// Labels each triangle with its connected component (shell) through the edge neighbours.
std::vector<int> shell_labels(const EdgeNeighbours& neighbours, int* shell_count) {
  std::vector<int> label(neighbours.size(), -1);
  int shells = 0;
  for (std::size_t start = 0; start < neighbours.size(); ++start) {
    if (label[start] >= 0) continue;
    std::vector<int> stack{static_cast<int>(start)};
    label[start] = shells;
    while (!stack.empty()) {
      const int t = stack.back();
      stack.pop_back();
      for (int u : neighbours[t]) {
        if (label[u] < 0) {
          label[u] = shells;
          stack.push_back(u);
        }
      }
    }
    ++shells;
  }
  *shell_count = shells;
  return label;
}

std::vector<double> shell_volumes(const TriangleMesh& mesh, const std::vector<int>& label, int shells) {
  std::vector<double> volume(shells, 0.0);
  const Eigen::Vector3d reference = mesh.vertices.front();
  for (std::size_t t = 0; t < mesh.triangles.size(); ++t) {
    const auto& tri = mesh.triangles[t];
    const Eigen::Vector3d a = mesh.vertices[tri[0]] - reference, b = mesh.vertices[tri[1]] - reference;
    const Eigen::Vector3d c = mesh.vertices[tri[2]] - reference;
    volume[label[t]] += a.dot(b.cross(c)) / 6.0;
  }
  return volume;
}

// The volume grows as the cube of the mesh's size and the second moments as its fifth power: a
// mesh beyond about 1e61 file units (or below about 1e-61) overflows (underflows) double precision,
// and its mass properties would come out inf, NaN or 0 (found by fuzz_stl, docs/fuzzing.md).
[[noreturn]] void refuse_size(const std::string& source, std::string_view too, double largest_coordinate,
                              std::string_view what) {
  throw InputError(
      fmt::format("{}: the mesh is too {} for double precision (largest coordinate {:.3g}): its {}; "
                  "rescale the mesh (its scale factor) or give its coordinates in other units",
                  source, too, largest_coordinate, what));
}

void check_size_representable(double diagonal, double largest_coordinate, const std::vector<double>& shell_volume,
                              const std::string& source) {
  const bool finite = std::isfinite(diagonal * diagonal * diagonal) &&
                      std::all_of(shell_volume.begin(), shell_volume.end(), [](double v) { return std::isfinite(v); });
  if (!finite) refuse_size(source, "large", largest_coordinate, "volume overflows");
}

void check_moments_representable(const VolumeMoments& moments, double area, double largest_coordinate,
                                 const std::string& source) {
  if (!std::isfinite(moments.volume) || !moments.centroid.allFinite() || !moments.second_moment.allFinite() ||
      !std::isfinite(area)) {
    refuse_size(source, "large", largest_coordinate, "moments of inertia overflow");
  }
  // A solid's second moments about its centroid are positive; below the smallest normal double
  // they have lost their precision (or are 0).
  if (moments.second_moment.diagonal().minCoeff() < std::numeric_limits<double>::min()) {
    refuse_size(source, "small", largest_coordinate, "moments of inertia underflow");
  }
}

// The solid angle triangle (a, b, c) subtends at the origin, signed by its winding (Van Oosterom and
// Strackee 1983, "The solid angle of a plane triangle", IEEE Trans. Biomed. Eng. 30(2), 125-126,
// doi:10.1109/TBME.1983.325207).
double solid_angle(const Eigen::Vector3d& a, const Eigen::Vector3d& b, const Eigen::Vector3d& c) {
  const double la = a.norm(), lb = b.norm(), lc = c.norm();
  const double denominator = la * lb * lc + a.dot(b) * lc + a.dot(c) * lb + b.dot(c) * la;
  return 2.0 * std::atan2(a.dot(b.cross(c)), denominator);
}

// The winding number of shell `shell` about p: the solid angle its triangles subtend over 4 pi, 1
// inside a closed outward shell and 0 outside (Gauss), exact up to rounding away from its surface.
double winding_number(const TriangleMesh& mesh, const std::vector<int>& label, int shell, const Eigen::Vector3d& p) {
  double total = 0.0;
  for (std::size_t t = 0; t < mesh.triangles.size(); ++t) {
    if (label[t] != shell) continue;
    const auto& tri = mesh.triangles[t];
    total += solid_angle(mesh.vertices[tri[0]] - p, mesh.vertices[tri[1]] - p, mesh.vertices[tri[2]] - p);
  }
  return total / (4.0 * std::numbers::pi);
}

// Outward shells one inside another would count the inner solid twice (the volumes add): refused.
// Only shells whose bounding box lies within another's are tested, with one of their vertices;
// shells that merely overlap are not detected (docs/shapes.md).
void check_shells_not_nested(const TriangleMesh& mesh, const std::vector<int>& label, int shells,
                             const std::string& source) {
  const auto n = static_cast<std::size_t>(shells);
  std::vector<Eigen::AlignedBox3d> box(n);
  std::vector<int> vertex(n, -1), triangles(n, 0);
  for (std::size_t t = 0; t < mesh.triangles.size(); ++t) {
    const auto s = static_cast<std::size_t>(label[t]);
    ++triangles[s];
    for (const int v : mesh.triangles[t]) box[s].extend(mesh.vertices[static_cast<std::size_t>(v)]);
    if (vertex[s] < 0) vertex[s] = mesh.triangles[t][0];
  }
  for (std::size_t outer = 0; outer < n; ++outer)
    for (std::size_t inner = 0; inner < n; ++inner) {
      if (inner == outer || !box[outer].contains(box[inner])) continue;
      const Eigen::Vector3d probe = mesh.vertices[static_cast<std::size_t>(vertex[inner])];
      if (winding_number(mesh, label, static_cast<int>(outer), probe) < 0.5) continue;
      throw InputError(
          fmt::format("{}: shell {} ({} triangles) lies inside shell {} ({} triangles), both oriented outward: "
                      "as one body their volumes would add and count the inner solid twice; remove the inner "
                      "shell, or merge the two into one surface",
                      source, inner + 1, triangles[inner], outer + 1, triangles[outer]));
    }
}

double corner_angle(const Eigen::Vector3d& at, const Eigen::Vector3d& p, const Eigen::Vector3d& q) {
  const Eigen::Vector3d u = p - at, v = q - at;
  return std::atan2(u.cross(v).norm(), u.dot(v));
}

}  // namespace

MeshShape::MeshShape(TriangleMesh mesh, std::string source) : mesh_(std::move(mesh)) {
  EdgeNeighbours neighbours = check_closed_and_oriented(mesh_, source);
  const auto [lo, hi] = vertex_bounds(mesh_);
  const double diagonal = (hi - lo).norm();
  const double largest_coordinate = std::max(lo.cwiseAbs().maxCoeff(), hi.cwiseAbs().maxCoeff());

  int shells = 0;
  const std::vector<int> label = shell_labels(neighbours, &shells);
  const std::vector<double> volumes = shell_volumes(mesh_, label, shells);
  check_size_representable(diagonal, largest_coordinate, volumes, source);
  const double total = std::accumulate(volumes.begin(), volumes.end(), 0.0);
  if (std::abs(total) <= 1e-10 * diagonal * diagonal * diagonal) {
    throw InputError(
        fmt::format("{}: the mesh encloses no volume (volume {:.3g} for a bounding-box diagonal of {:.3g})", source,
                    total, diagonal));
  }
  const int inward = static_cast<int>(std::count_if(volumes.begin(), volumes.end(), [](double v) { return v < 0.0; }));
  if (inward > 0 && inward < shells) {
    throw InputError(
        fmt::format("{}: the mesh has {} closed shells and {} of them are oriented inward (an inverted "
                    "shell or an internal cavity); every shell must enclose its own solid with outward "
                    "normals",
                    source, shells, inward));
  }
  if (inward == shells) {
    for (auto& tri : mesh_.triangles) std::swap(tri[1], tri[2]);
    for (auto& n : neighbours) n = {n[2], n[1], n[0]};  // edge k of the reversed triangle is old edge 2-k
    notes_.push_back(source + ": all faces were oriented inward (negative volume); the orientation was reversed");
  }
  if (shells > 1 && inward == 0) check_shells_not_nested(mesh_, label, shells, source);
  if (shells > 1)
    notes_.push_back(fmt::format("{}: the mesh has {} separate shells, treated as one rigid body", source, shells));

  moments_ = polyhedron_moments(mesh_);
  for (auto& v : mesh_.vertices) v -= moments_.centroid;  // body frame: origin at the centroid
  area_ = mesh_surface_area(mesh_);
  check_moments_representable(moments_, area_, largest_coordinate, source);
  convex_ = body::is_convex(mesh_, neighbours);
  const auto [body_lo, body_hi] = vertex_bounds(mesh_);
  box_ = {body_lo, body_hi};
  for (const auto& v : mesh_.vertices) bounding_radius_ = std::max(bounding_radius_, v.norm());
  bvh_ = TriangleBvh(mesh_);

  // Pseudonormals: faces' unit normals; an edge's is the sum of its two faces'; a vertex's the
  // sum of its faces' normals weighted by the face angle at the vertex.
  const std::size_t count = mesh_.triangles.size();
  face_normals_.resize(count);
  for (std::size_t t = 0; t < count; ++t)
    face_normals_[t] = triangle_vector_area(mesh_, static_cast<int>(t)).normalized();
  edge_normals_.resize(count);
  vertex_normals_.assign(mesh_.vertices.size(), Eigen::Vector3d::Zero());
  for (std::size_t t = 0; t < count; ++t) {
    const auto& tri = mesh_.triangles[t];
    for (int k = 0; k < 3; ++k) {
      edge_normals_[t][k] = face_normals_[t] + face_normals_[neighbours[t][k]];
      const auto& v = mesh_.vertices;
      vertex_normals_[tri[k]] += corner_angle(v[tri[k]], v[tri[(k + 1) % 3]], v[tri[(k + 2) % 3]]) * face_normals_[t];
    }
  }
}

Eigen::Vector3d MeshShape::feature_normal(const TriangleBvh::Hit& hit) const {
  switch (hit.feature.kind) {
    case TriangleFeature::Kind::face:
      return face_normals_[hit.triangle];
    case TriangleFeature::Kind::edge:
      return edge_normals_[hit.triangle][hit.feature.index];
    case TriangleFeature::Kind::vertex:
      return vertex_normals_[mesh_.triangles[hit.triangle][hit.feature.index]];
  }
  return face_normals_[hit.triangle];
}

double MeshShape::signed_distance(const Eigen::Vector3d& p) const {
  const TriangleBvh::Hit hit = bvh_.closest(p);
  const double distance = std::sqrt(hit.distance_squared);
  return (p - hit.point).dot(feature_normal(hit)) > 0.0 ? distance : -distance;
}

namespace {

// The first crossing of a segment from its hits (count of them, -1 for too many), when the hits at
// its first and at its last crossing all enter the solid (within the hit margin: an edge or a
// vertex is reported by each of its triangles); nothing otherwise.
std::optional<double> first_entering_crossing(std::span<TriangleBvh::SegmentHit> hits, int count) {
  if (count <= 0) return std::nullopt;
  const auto end = hits.begin() + count;
  std::sort(hits.begin(), end, [](const auto& a, const auto& b) { return a.t < b.t; });
  const double first = hits.front().t, last = (end - 1)->t;
  constexpr double kSame = 2.0 * TriangleBvh::kHitMargin;
  const bool ends_enter = std::all_of(hits.begin(), end, [&](const auto& hit) {
    return hit.entering || (hit.t > first + kSame && hit.t < last - kSame);
  });
  if (!ends_enter) return std::nullopt;
  return std::clamp(first, 0.0, 1.0);
}

constexpr std::size_t kMaxHits = 16;

// Whether the hits within the hit margin of hits[at] (sorted by t) all cross the same way.
bool crossing_is_clear(std::span<const TriangleBvh::SegmentHit> hits, std::size_t at) {
  constexpr double kSame = 2.0 * TriangleBvh::kHitMargin;
  return std::all_of(hits.begin(), hits.end(), [&](const auto& hit) {
    return std::abs(hit.t - hits[at].t) > kSame || hit.entering == hits[at].entering;
  });
}

}  // namespace

bool MeshShape::contains_from(const Eigen::Vector3d& p, const Eigen::Vector3d& reference, bool reference_inside) const {
  std::array<TriangleBvh::SegmentHit, kMaxHits> buffer;
  const int count = bvh_.segment_hits(reference, p, buffer);
  if (count == 0) return reference_inside;
  if (count < 0) return contains(p);
  const std::span<TriangleBvh::SegmentHit> hits(buffer.data(), static_cast<std::size_t>(count));
  std::sort(hits.begin(), hits.end(), [](const auto& a, const auto& b) { return a.t < b.t; });
  const std::size_t last = hits.size() - 1;
  const bool clear = hits[last].t < 1.0 - 2.0 * TriangleBvh::kHitMargin && crossing_is_clear(hits, 0) &&
                     crossing_is_clear(hits, last) && hits[0].entering != reference_inside;
  return clear ? hits[last].entering : contains(p);
}

double MeshShape::surface_crossing(const Eigen::Vector3d& outside, const Eigen::Vector3d& inside) const {
  std::array<TriangleBvh::SegmentHit, kMaxHits> hits;
  const std::optional<double> t = first_entering_crossing(hits, bvh_.segment_hits(outside, inside, hits));
  return t ? *t : Shape::surface_crossing(outside, inside);
}

void MeshShape::surface_crossings(const Eigen::Vector3d& outside, std::span<const Eigen::Vector3d> insides,
                                  std::span<double> t) const {
  double radius = 0.0;
  for (const Eigen::Vector3d& inside : insides) radius = std::max(radius, (inside - outside).norm());
  // Tens of leaves lie within a link of a cell when the triangles are about a cell wide; a mesh
  // much finer than the grid has more, and its segments walk the tree one by one.
  TriangleBvh::LeavesNear near;
  bvh_.leaves_near(outside, radius, near);
  for (std::size_t k = 0; k < insides.size(); ++k) {
    if (near.count < 0) {
      t[k] = surface_crossing(outside, insides[k]);
      continue;
    }
    std::array<TriangleBvh::SegmentHit, kMaxHits> hits;
    const int count = bvh_.segment_hits(near, insides[k], hits);
    const std::optional<double> crossing = first_entering_crossing(hits, count);
    t[k] = crossing ? *crossing : Shape::surface_crossing(outside, insides[k]);
  }
}

Eigen::Vector3d MeshShape::closest_surface_point(const Eigen::Vector3d& p) const { return bvh_.closest(p).point; }

Eigen::Vector3d MeshShape::outward_normal(const Eigen::Vector3d& surface_point) const {
  return feature_normal(bvh_.closest(surface_point)).normalized();
}

double MeshShape::support(const Eigen::Vector3d& n) const {
  double best = -std::numeric_limits<double>::infinity();
  for (const auto& v : mesh_.vertices) best = std::max(best, n.dot(v));
  return best;
}

double MeshShape::projected_area(const Eigen::Vector3d& direction) const {
  return convex_ ? convex_projected_area(mesh_, direction) : scanline_projected_area(mesh_, direction, 4096);
}

double MeshShape::mean_projected_area_perpendicular(const Eigen::Vector3d& axis) const {
  const Eigen::Vector3d unit = axis.normalized();
  return convex_ ? convex_mean_projected_area_perpendicular(mesh_, unit)
                 : scanline_mean_projected_area_perpendicular(mesh_, unit, 128, 1024);
}

SurfaceMarkers MeshShape::surface_markers(double spacing) const {
  validate_marker_spacing(spacing, surface_area());
  return cluster_patches_into_markers(patches_from_mesh(mesh_, kPatchEdgeFraction * spacing), spacing,
                                      [this](const Eigen::Vector3d& p) { return closest_surface_point(p); });
}

std::unique_ptr<MeshShape> load_mesh_shape(const std::filesystem::path& path, double scale) {
  if (!std::isfinite(scale) || scale <= 0.0) {
    throw InputError(fmt::format("{}: the scale factor must be finite and > 0, got {}", path.string(), scale));
  }
  TriangleMesh mesh = read_stl(path);
  for (auto& v : mesh.vertices) v *= scale;
  return std::make_unique<MeshShape>(std::move(mesh), path.string());
}

}  // namespace settle::body
