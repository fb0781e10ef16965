// Inputs found with the STL fuzz target (tests/fuzz/fuzz_stl.cpp, docs/fuzzing.md), kept as
// regression tests: each must now be refused with settle::InputError naming the problem, and the
// neighbouring sizes that double precision does represent must still read with exact mass
// properties.
#include <gtest/gtest.h>

#include <cmath>
#include <filesystem>
#include <numbers>
#include <string>

#include "body/cube_sphere.hpp"
#include "body/mesh_shape.hpp"
#include "body/superellipsoid.hpp"
#include "body/triangle_mesh.hpp"
#include "common/error.hpp"

namespace settle::body {
namespace test_fuzz_regressions {

std::filesystem::path fuzz_input(const std::string& name) {
  return std::filesystem::path(SETTLE_SOURCE_DIR) / "tests/fuzz/corpus_stl" / name;
}

std::string refusal(const std::filesystem::path& path, double scale = 1.0) {
  try {
    load_mesh_shape(path, scale);
  } catch (const InputError& e) {
    return e.what();
  }
  return "";
}

bool contains(const std::string& text, const std::string& part) { return text.find(part) != std::string::npos; }

// Finding 2: the unit cube of tests/data/cube_ascii.stl with every coordinate times 1e103 (ASCII
// STL reads any finite double). Its volume, 1e309, overflows: the mesh was accepted with an
// infinite volume, and `settle shape --mesh` printed null for every mass property, exit status 0.
TEST(FuzzRegression, MeshWhoseVolumeOverflowsIsRefused) {
  EXPECT_TRUE(contains(refusal(fuzz_input("finding_cube_1e103.stl")), "too large for double precision"));
}

// The same cube times 1e62: the volume (1e186) is finite but the second moments (L^5 / 12 =
// 8e309) overflow; the inertia came out inf.
TEST(FuzzRegression, MeshWhoseMomentsOverflowAreRefused) {
  EXPECT_TRUE(contains(refusal(fuzz_input("finding_cube_1e62.stl")), "moments of inertia overflow"));
}

// The same cube times 1e-70: the second moments (1e-350 / 12) underflow to 0, a body without
// inertia.
TEST(FuzzRegression, MeshWhoseMomentsUnderflowAreRefused) {
  EXPECT_TRUE(contains(refusal(fuzz_input("finding_cube_1e-70.stl")), "moments of inertia underflow"));
}

// The scale factor of a case (particle.scale) reaches the same checks.
TEST(FuzzRegression, ScaleFactorThatOverflowsTheMomentsIsRefused) {
  const std::filesystem::path cube = std::filesystem::path(SETTLE_SOURCE_DIR) / "tests/data/cube_ascii.stl";
  EXPECT_TRUE(contains(refusal(cube, 1e62), "too large for double precision"));
  EXPECT_TRUE(contains(refusal(cube, 1e-70), "too small for double precision"));
}

// Positive controls just inside the representable range: a cube of side L has volume L^3 and
// second moment about its centroid int x^2 dV = L^5 / 12 along each axis (off-diagonals 0).
// Relative tolerance 1e-12: the moments are sums of a dozen tetrahedra in double precision.
TEST(FuzzRegression, LargeAndSmallCubesStillHaveExactMassProperties) {
  const std::filesystem::path cube = std::filesystem::path(SETTLE_SOURCE_DIR) / "tests/data/cube_ascii.stl";
  for (const double side : {1e60, 1e-60}) {
    const auto shape = load_mesh_shape(cube, side);
    const VolumeMoments m = shape->volume_moments();
    EXPECT_NEAR(m.volume / std::pow(side, 3), 1.0, 1e-12) << side;
    for (int i = 0; i < 3; ++i) EXPECT_NEAR(m.second_moment(i, i) / std::pow(side, 5), 1.0 / 12.0, 1e-12) << side;
  }
}

// Finding 3 (case parser): particle.shape = "superellipsoid" with semi_axes [1e-3, 2e-6, 2e-6]
// (within the schema's 1000:1) built a distance triangulation of 2e8 triangles: 24 GB and 400 s
// before preflight could refuse anything. The triangulation is now capped; the cap is exact.
TEST(FuzzRegression, CubeSphereTriangulationKeepsToItsTriangleCap) {
  const Eigen::Vector3d axes(1.0, 0.002, 0.002);
  const auto on_ellipsoid = [&](const Eigen::Vector3d& u) {
    return Eigen::Vector3d(axes.cwiseProduct(u.normalized()));  // a ray's exit of the ellipsoid
  };
  const double cap = 2.0e4;
  const TriangleMesh mesh = cube_sphere_mesh_with_max_edge(axes, 1e-4, on_ellipsoid, cap);
  EXPECT_LE(static_cast<double>(mesh.triangles.size()), cap);
  // Still a closed, consistently oriented surface (throws otherwise).
  EXPECT_NO_THROW(check_closed_and_oriented(mesh, "capped cube sphere"));
}

// The 500:1 needle of the finding itself (in units of its half-length; e1 = e2 = 1 is the
// ellipsoid): it is now built with at most 1e6 triangles, and what does not depend on the
// triangulation is unchanged: the volume 4/3 pi abc (Beta functions) to round-off, and the
// distance of points on the normal through a surface point, which is exactly their offset for a
// convex body. Tolerance 1e-8 of the thickness b: the polishing converges on the exact surface
// (the header's 1e-8 d_eq near the surface), whatever the starting triangle.
TEST(FuzzRegression, NeedleSuperellipsoidIsBuiltWithExactVolumeAndNearSurfaceDistance) {
  const Eigen::Vector3d axes(1.0, 0.002, 0.002);
  const Superellipsoid needle(axes, 1.0, 1.0);
  EXPECT_NEAR(needle.volume() / (4.0 / 3.0 * std::numbers::pi * axes.prod()), 1.0, 1e-12);
  const double offset = 0.01 * axes.y();
  for (const Eigen::Vector3d& direction :
       {Eigen::Vector3d(0.3, 1.0, 0.0), Eigen::Vector3d(-0.9, 0.2, 0.4), Eigen::Vector3d(1.0, 0.0, 0.0)}) {
    const Eigen::Vector3d scaled = axes.cwiseProduct(direction);
    const Eigen::Vector3d surface = scaled / needle.gauge(scaled);
    const Eigen::Vector3d normal = needle.outward_normal(surface);
    EXPECT_NEAR(needle.signed_distance(surface + offset * normal), offset, 1e-8 * axes.y()) << direction.transpose();
  }
}

}  // namespace test_fuzz_regressions
}  // namespace settle::body
