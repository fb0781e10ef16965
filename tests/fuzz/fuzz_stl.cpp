// libFuzzer target for the STL reader: arbitrary bytes go through body::parse_stl (the
// function body::read_stl calls on a file's bytes) and, when they parse, through the mesh shape's
// validation (body::MeshShape: closed, consistently oriented, non-zero volume), as for a case's
// particle.file.
//
// Expected outcome for bad input: settle::InputError, caught here. A finding is anything else:
// another exception type, a crash, a sanitizer report, a hang, or a broken oracle below (abort
// with a message):
//   - the read info matches the mesh (facet and welded vertex counts), every triangle index
//     points at a vertex, every coordinate is finite;
//   - an accepted shape has a finite, positive volume, a finite positive surface area, a finite
//     bounding radius, a finite centroid and finite, positive second moments (MeshShape reverses
//     inward meshes and refuses zero volume: these are the mass properties a run needs).
// Build and run: scripts/fuzz.sh (docs/fuzzing.md).
#include <cmath>
#include <cstddef>
#include <cstdint>
#include <cstdio>
#include <cstdlib>
#include <string>
#include <string_view>

#include "body/mesh_shape.hpp"
#include "body/stl_io.hpp"
#include "common/error.hpp"

namespace {

[[noreturn]] void finding(const char* what) {
  std::fprintf(stderr, "fuzz_stl finding: %s\n", what);
  std::abort();
}

void check_mesh(const settle::body::TriangleMesh& mesh, const settle::body::StlReadInfo& info) {
  if (info.facet_count != mesh.triangles.size()) finding("facet_count differs from the triangle count");
  if (info.welded_vertex_count != mesh.vertices.size()) finding("welded_vertex_count differs from the vertex count");
  const int vertex_count = static_cast<int>(mesh.vertices.size());
  for (const auto& tri : mesh.triangles)
    for (int v : tri)
      if (v < 0 || v >= vertex_count) finding("a triangle index is out of range");
  for (const auto& p : mesh.vertices)
    if (!p.allFinite()) finding("a vertex is not finite");
}

void check_shape(const settle::body::MeshShape& shape) {
  const double volume = shape.volume_moments().volume;
  if (!std::isfinite(volume) || volume <= 0.0) finding("an accepted mesh has a non-finite or non-positive volume");
  const double area = shape.surface_area();
  if (!std::isfinite(area) || area <= 0.0) finding("an accepted mesh has a non-finite or non-positive surface area");
  if (!std::isfinite(shape.bounding_radius())) finding("an accepted mesh has a non-finite bounding radius");
  const settle::body::VolumeMoments moments = shape.volume_moments();
  if (!moments.centroid.allFinite() || !moments.second_moment.allFinite())
    finding("an accepted mesh has non-finite moments");
  if (!(moments.second_moment.diagonal().minCoeff() > 0.0)) finding("an accepted mesh has a zero second moment");
}

}  // namespace

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  const std::string_view bytes(reinterpret_cast<const char*>(data), size);
  try {
    settle::body::StlReadInfo info;
    settle::body::TriangleMesh mesh = settle::body::parse_stl(bytes, "fuzz", &info);
    check_mesh(mesh, info);
    const settle::body::MeshShape shape(std::move(mesh), "fuzz");
    check_shape(shape);
  } catch (const settle::InputError&) {
    // The expected outcome for bad input.
  }
  return 0;
}
