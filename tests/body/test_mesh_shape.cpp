// Mesh shapes against closed forms: boxes (axis-aligned, off the origin, rotated), a
// tetrahedron, a non-convex L-shaped prism, and icospheres converging to the sphere.
#include <cmath>
#include <filesystem>
#include <numbers>
#include <random>

#include <gtest/gtest.h>

#include "body/cuboid.hpp"
#include "body/mesh_shape.hpp"
#include "body/projected_area.hpp"
#include "body/shape_factors.hpp"
#include "common/error.hpp"
#include "shape_test_support.hpp"

namespace settle::body {
namespace test_mesh_shape {

using std::numbers::pi;
using testing::box_mesh;

// Polyhedral moments are sums of a few terms per face: round-off ~1e-15 relative.
constexpr double kExact = 1e-13;

Eigen::Matrix3d test_rotation() {
  return (Eigen::AngleAxisd(0.9, Eigen::Vector3d(1, -2, 0.5).normalized()) *
          Eigen::AngleAxisd(0.3, Eigen::Vector3d::UnitZ()))
      .toRotationMatrix();
}

TEST(MeshShape, AxisAlignedBoxMatchesCuboid) {
  const Eigen::Vector3d size(3.0, 2.0, 1.0);
  const MeshShape mesh(box_mesh(size), "box");
  const Cuboid box(size);
  EXPECT_TRUE(mesh.is_convex());
  EXPECT_NEAR(mesh.volume(), box.volume(), kExact * 6);
  EXPECT_NEAR(mesh.surface_area(), box.surface_area(), kExact * 22);
  EXPECT_TRUE(mesh.mass_properties(2.0).inertia.isApprox(box.mass_properties(2.0).inertia, kExact));
  EXPECT_NEAR(mesh.bounding_radius(), box.bounding_radius(), kExact);
  std::mt19937_64 rng(40);
  for (int i = 0; i < 20; ++i) {
    const Eigen::Vector3d n = testing::random_unit(rng);
    EXPECT_NEAR(mesh.projected_area(n), box.projected_area(n), kExact * 10);
    EXPECT_NEAR(mesh.mean_projected_area_perpendicular(n), box.mean_projected_area_perpendicular(n), kExact * 10);
    EXPECT_NEAR(mesh.support(n), box.support(n), kExact);
  }
}

TEST(MeshShape, BoxDistanceIsExactIncludingEdgesAndCorners) {
  // The box mesh is the box: the distance must equal the cuboid's closed form everywhere,
  // which exercises the pseudonormal sign at faces, edges and corners (points near those are
  // included on purpose).
  const Eigen::Vector3d size(3.0, 2.0, 1.0), centre(10.0, -4.0, 2.5);
  const Eigen::Matrix3d rotation = test_rotation();
  const MeshShape mesh(box_mesh(size, centre, rotation), "rotated box");
  const Cuboid box(size);
  std::mt19937_64 rng(41);
  std::vector<Eigen::Vector3d> local;
  for (int i = 0; i < 2000; ++i) local.push_back(testing::random_in_box(rng, 0.75 * size));
  for (int corner = 0; corner < 8; ++corner) {  // just outside and inside each corner
    const Eigen::Vector3d c =
        0.5 * size.cwiseProduct(Eigen::Vector3d(corner & 1 ? 1 : -1, corner & 2 ? 1 : -1, corner & 4 ? 1 : -1));
    local.push_back(1.01 * c);
    local.push_back(0.99 * c);
    local.push_back(c + 0.01 * Eigen::Vector3d(1, -1, 1));
  }
  for (const auto& q : local) {
    // Body frame of the mesh: origin at the centroid (the box centre), axes of the file.
    const Eigen::Vector3d p = rotation * q;
    EXPECT_NEAR(mesh.signed_distance(p), box.signed_distance(q), 1e-12) << q.transpose();
    EXPECT_EQ(mesh.contains(p), box.contains(q));
  }
}

TEST(MeshShape, OffOriginRotatedBoxHasCentroidAndPrincipalFrame) {
  const Eigen::Vector3d size(3.0, 2.0, 1.0), centre(10.0, -4.0, 2.5);
  const Eigen::Matrix3d rotation = test_rotation();
  const MeshShape mesh(box_mesh(size, centre, rotation), "rotated box");
  const MassProperties p = mesh.mass_properties(1.5);
  const MassProperties reference = Cuboid(size).mass_properties(1.5);
  // The centroid is the box centre; the mesh is stored about it. Far from the origin the
  // vertices carry absolute errors of ~1e-15 x 10, hence 1e-13.
  EXPECT_TRUE(p.centroid.isApprox(centre, 1e-13));
  EXPECT_TRUE(p.inertia.isApprox(rotation * reference.inertia * rotation.transpose(), 1e-12));
  // Principal moments ascending and the axes: the rotated x, y, z (up to sign).
  EXPECT_TRUE(p.principal.moments.isApprox(reference.principal.moments, 1e-12));
  for (int i = 0; i < 3; ++i) EXPECT_NEAR(std::abs(p.principal.axes.col(i).dot(rotation.col(i))), 1.0, 1e-12);
  EXPECT_NEAR(p.principal.axes.determinant(), 1.0, 1e-12);
  // The rotation to the principal frame diagonalises the tensor.
  const Eigen::Matrix3d r = p.rotation_body_from_principal().toRotationMatrix();
  const Eigen::Matrix3d diagonal = r.transpose() * p.inertia * r;
  EXPECT_LT((diagonal - Eigen::Matrix3d(p.principal.moments.asDiagonal())).norm(), 1e-12 * p.inertia.norm());
  const ShapeFactors f = compute_shape_factors(mesh, Eigen::Vector3d::UnitZ());
  EXPECT_TRUE(f.principal_extents.isApprox(Eigen::Vector3d(3.0, 2.0, 1.0), 1e-12));
}

TEST(MeshShape, TetrahedronClosedForms) {
  // Legs a = 2, b = 3, c = 4 from the origin: int x^2 dV = a^3 b c / 60, int x y dV =
  // a^2 b^2 c / 120 (simplex integrals), V = 4 and centroid (a, b, c)/4; about the centroid
  // S = int x x^T dV - V c c^T.
  TriangleMesh mesh;
  mesh.vertices = {{0, 0, 0}, {2, 0, 0}, {0, 3, 0}, {0, 0, 4}};
  mesh.triangles = {{0, 2, 1}, {0, 1, 3}, {0, 3, 2}, {1, 2, 3}};
  const VolumeMoments m = MeshShape(mesh, "tetrahedron").volume_moments();
  EXPECT_NEAR(m.volume, 4.0, kExact);
  EXPECT_TRUE(m.centroid.isApprox(Eigen::Vector3d(0.5, 0.75, 1.0), kExact));
  Eigen::Matrix3d expected;
  expected << 0.6, -0.3, -0.4, -0.3, 1.35, -0.6, -0.4, -0.6, 2.4;
  EXPECT_TRUE(m.second_moment.isApprox(expected, kExact));
}

TEST(MeshShape, RegularTetrahedronHasIsotropicInertia) {
  // Edge s: I = m s^2 / 20 about every axis through the centroid.
  TriangleMesh mesh;
  mesh.vertices = {{1, 1, 1}, {1, -1, -1}, {-1, 1, -1}, {-1, -1, 1}};  // edge 2 sqrt 2
  mesh.triangles = {{0, 1, 2}, {0, 3, 1}, {0, 2, 3}, {1, 3, 2}};
  const MeshShape tet(mesh, "regular tetrahedron");
  const MassProperties p = tet.mass_properties(1.0);
  EXPECT_NEAR(p.volume, 8.0 / 3.0, kExact);
  EXPECT_TRUE(p.inertia.isApprox(Eigen::Matrix3d::Identity() * p.mass * 8.0 / 20.0, kExact));
  EXPECT_NEAR(compute_shape_factors(tet, Eigen::Vector3d::UnitZ()).sphericity, std::cbrt(pi / (6.0 * std::sqrt(3.0))),
              1e-12);  // (pi / 6 sqrt 3)^(1/3) = 0.671
}

TEST(MeshShape, IcosphereConvergesToTheSphere) {
  // An icosphere's volume, area and inertia approach the sphere's at second order in the edge
  // length: each subdivision halves the edge, so the error must fall by ~4.
  const double r = 0.5;
  double previous[3] = {0, 0, 0};
  for (int level = 2; level <= 6; ++level) {
    const MeshShape mesh(testing::icosphere(level, r), "icosphere");
    const double errors[3] = {
        std::abs(mesh.volume() / (4.0 / 3.0 * pi * r * r * r) - 1.0),
        std::abs(mesh.surface_area() / (4.0 * pi * r * r) - 1.0),
        std::abs(mesh.mass_properties(1.0).inertia(2, 2) / (8.0 / 15.0 * pi * std::pow(r, 5)) - 1.0)};
    for (int k = 0; k < 3; ++k) {
      if (level > 2) {
        EXPECT_NEAR(previous[k] / errors[k], 4.0, 0.25) << "level " << level << " quantity " << k;
      }
      previous[k] = errors[k];
    }
    if (level == 6) {
      std::printf("icosphere level 6 (%zu triangles): volume %.2e area %.2e inertia %.2e\n",
                  mesh.body_mesh().triangles.size(), errors[0], errors[1], errors[2]);
      // Measured 1.35e-4, 7.5e-5, 2.25e-4: the inscribed polyhedron is smaller than the sphere.
      EXPECT_LT(errors[0], 3e-4);
      EXPECT_LT(errors[1], 3e-4);
      EXPECT_LT(errors[2], 3e-4);
    }
  }
}

TEST(MeshShape, IcosphereSignAndDistance) {
  const double r = 0.5;
  const TriangleMesh sphere = testing::icosphere(4, r);
  const MeshShape mesh(sphere, "icosphere");
  // The polyhedron lies between the sphere and the sphere shrunk by the largest chord height
  // (r minus the smallest distance of a face plane from the centre): points are within that
  // of the sphere's distance, and points farther than it from the sphere have its sign.
  double chord = 0.0;
  for (std::size_t t = 0; t < sphere.triangles.size(); ++t) {
    const Eigen::Vector3d n = triangle_vector_area(sphere, static_cast<int>(t)).normalized();
    chord = std::max(chord, r - n.dot(sphere.vertices[sphere.triangles[t][0]]));
  }
  EXPECT_LT(chord, 1e-3);
  std::mt19937_64 rng(42);
  for (int i = 0; i < 2000; ++i) {
    const Eigen::Vector3d p = testing::random_in_box(rng, Eigen::Vector3d::Constant(0.8));
    const double exact = p.norm() - r;
    EXPECT_NEAR(mesh.signed_distance(p), exact, chord + 1e-15);
    if (std::abs(exact) > chord) {
      EXPECT_EQ(mesh.contains(p), exact < 0.0) << p.transpose();
    }
  }
}

// L-shaped prism: the polygon (0,0) (2,0) (2,1) (1,1) (1,2) (0,2) extruded over z in [0, h].
TriangleMesh l_prism(double h) {
  const std::vector<Eigen::Vector2d> polygon{{0, 0}, {2, 0}, {2, 1}, {1, 1}, {1, 2}, {0, 2}};
  TriangleMesh mesh;
  for (const auto& p : polygon) mesh.vertices.push_back({p.x(), p.y(), 0.0});
  for (const auto& p : polygon) mesh.vertices.push_back({p.x(), p.y(), h});
  const int n = static_cast<int>(polygon.size());
  for (int i = 0; i < n; ++i) {  // walls, outward for a counterclockwise polygon
    const int j = (i + 1) % n;
    mesh.triangles.push_back({i, j, j + n});
    mesh.triangles.push_back({i, j + n, i + n});
  }
  for (const auto& [a, b, c] : std::vector<std::array<int, 3>>{{0, 1, 2}, {0, 2, 3}, {0, 3, 4}, {0, 4, 5}}) {
    mesh.triangles.push_back({a + n, b + n, c + n});  // top, counterclockwise from +z
    mesh.triangles.push_back({a, c, b});              // bottom, reversed
  }
  return mesh;
}

TEST(MeshShape, NonConvexPrismVolumeSignAndShadows) {
  const double h = 0.5;
  const MeshShape mesh(l_prism(h), "L prism");
  EXPECT_FALSE(mesh.is_convex());
  EXPECT_NEAR(mesh.volume(), 3.0 * h, kExact);
  EXPECT_NEAR(mesh.surface_area(), 2 * 3.0 + 8.0 * h, kExact * 10);
  // The centroid of the L: rectangles of area 2 at (1, 1/2) and 1 at (1/2, 3/2) give (5/6, 5/6),
  // at mid-height.
  EXPECT_TRUE(mesh.volume_moments().centroid.isApprox(Eigen::Vector3d(5.0 / 6.0, 5.0 / 6.0, 0.25), kExact));
  const Eigen::Vector3d c = mesh.volume_moments().centroid;
  auto inside_l = [&](const Eigen::Vector3d& q) {
    return q.z() >= 0 && q.z() <= h && q.x() >= 0 && q.y() >= 0 &&
           ((q.x() <= 2 && q.y() <= 1) || (q.x() <= 1 && q.y() <= 2));
  };
  std::mt19937_64 rng(43);
  for (int i = 0; i < 3000; ++i) {
    const Eigen::Vector3d q = Eigen::Vector3d(1, 1, 0.25) + testing::random_in_box(rng, Eigen::Vector3d(1.3, 1.3, 0.5));
    EXPECT_EQ(mesh.contains(q - c), inside_l(q)) << q.transpose();
  }
  // Shadows (scanlines, second order in 1/4096 rows: 1e-6 is generous): along z the L itself;
  // along x and along the diagonal, the height times the width of the L's convex hull.
  EXPECT_NEAR(mesh.projected_area(Eigen::Vector3d::UnitZ()), 3.0, 1e-6 * 3.0);
  EXPECT_NEAR(mesh.projected_area(Eigen::Vector3d::UnitX()), 2.0 * h, 1e-6);
  EXPECT_NEAR(mesh.projected_area(Eigen::Vector3d(1, 1, 0).normalized()), 2.0 * std::sqrt(2.0) * h, 1e-6);
  // Side views around z: the mean hull width is its perimeter / pi (Cauchy), 6 + sqrt 2.
  // The trapezoidal rule over 128 angles meets the hull's kinks: measured error 3e-5.
  const double mean = mesh.mean_projected_area_perpendicular(Eigen::Vector3d::UnitZ());
  std::printf("L prism mean side shadow %.8f vs %.8f\n", mean, h * (6.0 + std::sqrt(2.0)) / pi);
  EXPECT_NEAR(mean / (h * (6.0 + std::sqrt(2.0)) / pi), 1.0, 1e-4);
}

// The crossing of a link with a mesh is exact: on a rotated box it is where the slab method puts
// the link's entry (in the box's frame; round-off of the plane intersection and the rotation,
// 1e-13 of the link), where the base class's root finder stops within 1e-9 of the link.
TEST(MeshShape, SurfaceCrossingOfABoxIsWhereTheLinkEntersIt) {
  const Eigen::Vector3d size(3.0, 2.0, 1.0), half = 0.5 * size;
  const Eigen::Matrix3d rotation = test_rotation();
  const MeshShape mesh(box_mesh(size, Eigen::Vector3d::Zero(), rotation), "rotated box");
  const Eigen::Vector3d centroid = mesh.volume_moments().centroid;  // input frame = body frame + centroid
  const auto in_box = [&](const Eigen::Vector3d& b) { return (b.cwiseAbs() - half).maxCoeff() < 0.0; };
  std::mt19937_64 rng(44);
  int tested = 0;
  double worst = 0.0;
  for (int i = 0; i < 6000; ++i) {
    const Eigen::Vector3d from = testing::random_in_box(rng, half + Eigen::Vector3d::Constant(0.6));
    const Eigen::Vector3d to = from + (1.0 + 0.4 * std::abs(testing::random_unit(rng).x())) * testing::random_unit(rng);
    if (in_box(from) || !in_box(to)) continue;
    double entry = -1e300;  // the slab method: the latest entry over the three axes
    for (int a = 0; a < 3; ++a) {
      const double d = to[a] - from[a];
      if (d != 0.0) entry = std::max(entry, std::min((-half[a] - from[a]) / d, (half[a] - from[a]) / d));
    }
    const Eigen::Vector3d outside = rotation * from - centroid, inside = rotation * to - centroid;
    const double t = mesh.surface_crossing(outside, inside);
    EXPECT_NEAR(t, entry, 1e-13);
    worst = std::max(worst, std::abs(t - entry));
    ++tested;
  }
  std::printf("rotated box: %d links, |t - slab method| <= %.1e\n", tested, worst);
  EXPECT_GT(tested, 300);
}

// A link that crosses the surface three times (through the L's notch) gets its first crossing, the
// wall nearest the fluid; the contract's ends: 0 from an inside point, 1 to an outside one.
TEST(MeshShape, SurfaceCrossingIsTheFirstOfSeveralAndKeepsTheContract) {
  const double h = 0.5;
  const MeshShape mesh(l_prism(h), "L prism");
  const Eigen::Vector3d c = mesh.volume_moments().centroid;
  // From (2.5, 0.5) to (0.5, 1.5): into the lower arm at x = 2 (t = 1/4), out into the notch at
  // y = 1 (1/2), into the upper arm at x = 1 (3/4).
  const Eigen::Vector3d from = Eigen::Vector3d(2.5, 0.5, 0.25) - c, to = Eigen::Vector3d(0.5, 1.5, 0.25) - c;
  EXPECT_NEAR(mesh.surface_crossing(from, to), 0.25, 1e-14);
  const Eigen::Vector3d inside = Eigen::Vector3d(0.5, 0.5, 0.25) - c, outside = Eigen::Vector3d(3.0, 3.0, 0.25) - c;
  EXPECT_EQ(mesh.surface_crossing(inside, to), 0.0);
  EXPECT_EQ(mesh.surface_crossing(from, outside), 1.0);
  // Through the body and out again: the far end is not inside.
  EXPECT_EQ(mesh.surface_crossing(Eigen::Vector3d(0.5, -0.5, 0.25) - c, Eigen::Vector3d(0.5, 2.5, 0.25) - c), 1.0);
}

// The shipped grain at 10 cells per d_eq (links of 0.1 to 0.14 of its d_eq): all of a cell's links
// at once give the bits of one at a time, and within the base class's tolerance of its root finder
// (stopped within 1e-9 of the link in signed distance, so within 1e-9 / cos of the link in t, cos
// the angle of the link to the surface's normal; links within 6 degrees of tangent are left out);
// seen from a nearby point of known side, the inside test is contains'.
TEST(MeshShape, TheGrainsLinksAtOnceAndItsInsideTestFromANeighbour) {
  const auto grain = load_mesh_shape(std::filesystem::path(SETTLE_SOURCE_DIR) / "cases/grain.stl");
  const double cell = 0.1;
  std::mt19937_64 rng(45);
  const std::vector<Eigen::Vector3d> surface = testing::random_points_on_mesh(grain->body_mesh(), 400, rng);
  std::uniform_real_distribution<double> fraction(0.05, 0.95);
  int links = 0, compared_to_root_finder = 0, inside_tests = 0;
  double worst = 0.0;  // |t - root finder's| cos
  for (const Eigen::Vector3d& s : surface) {
    const Eigen::Vector3d normal = grain->outward_normal(s);
    const Eigen::Vector3d outside = s + fraction(rng) * cell * normal + 0.3 * cell * testing::random_unit(rng);
    if (grain->contains(outside)) continue;
    std::vector<Eigen::Vector3d> ends;
    for (int k = 0; k < 6; ++k) {
      const Eigen::Vector3d end = outside + cell * (1.0 + 0.41 * fraction(rng)) * testing::random_unit(rng);
      if (grain->contains(end)) ends.push_back(end);
    }
    std::vector<double> at_once(ends.size());
    grain->surface_crossings(outside, ends, at_once);
    for (std::size_t k = 0; k < ends.size(); ++k) {
      EXPECT_EQ(at_once[k], grain->surface_crossing(outside, ends[k]));
      const Eigen::Vector3d link = ends[k] - outside;
      const Eigen::Vector3d wall = outside + at_once[k] * link;
      const double cosine = std::abs(link.normalized().dot(grain->outward_normal(grain->closest_surface_point(wall))));
      if (cosine > 0.1) {
        const double root_finder = grain->Shape::surface_crossing(outside, ends[k]);
        EXPECT_NEAR(at_once[k], root_finder, 1e-9 / cosine + 1e-12);
        worst = std::max(worst, std::abs(at_once[k] - root_finder) * cosine);
        ++compared_to_root_finder;
      }
      ++links;
    }
    for (int k = 0; k < 4; ++k) {
      const Eigen::Vector3d p = s + 0.5 * cell * testing::random_unit(rng);
      const Eigen::Vector3d reference = p + cell * testing::random_unit(rng);
      EXPECT_EQ(grain->contains_from(p, reference, grain->contains(reference)), grain->contains(p)) << p.transpose();
      ++inside_tests;
    }
  }
  std::printf("grain: %d links, |t - root finder's| cos <= %.1e\n", links, worst);
  EXPECT_GT(links, 300);
  EXPECT_GT(compared_to_root_finder, 200);
  EXPECT_GT(inside_tests, 1000);
}

TEST(MeshShape, ScanlineShadowOfIcosphereMatchesCauchy) {
  // The icosphere is convex, so Cauchy's formula gives its exact shadow. The scanline measure
  // is second order except where a silhouette edge runs nearly along the rows (first order
  // there); with ~100 silhouette vertices measured errors at 4096 rows are 4e-7 to 5e-6.
  const TriangleMesh sphere = testing::icosphere(4, 1.0);
  std::mt19937_64 rng(44);
  for (int i = 0; i < 5; ++i) {
    const Eigen::Vector3d n = testing::random_unit(rng);
    EXPECT_NEAR(scanline_projected_area(sphere, n, 4096) / convex_projected_area(sphere, n), 1.0, 2e-5);
  }
}

TEST(MeshShape, ShellsWithMixedOrientationAreRefused) {
  // Two disjoint boxes, both outward: one body of two shells (noted).
  TriangleMesh two = box_mesh(Eigen::Vector3d::Ones());
  const TriangleMesh other = box_mesh(Eigen::Vector3d::Ones(), Eigen::Vector3d(3, 0, 0));
  for (const auto& v : other.vertices) two.vertices.push_back(v);
  for (const auto& t : other.triangles) two.triangles.push_back({t[0] + 8, t[1] + 8, t[2] + 8});
  const MeshShape pair(two, "pair");
  EXPECT_NEAR(pair.volume(), 2.0, kExact);
  EXPECT_EQ(pair.notes().size(), 1u);
  // A box with an inverted box inside (a cavity), or beside it: refused, naming the problem.
  for (const Eigen::Vector3d& offset : {Eigen::Vector3d(0, 0, 0), Eigen::Vector3d(3, 0, 0)}) {
    TriangleMesh mesh = box_mesh(Eigen::Vector3d::Constant(2.0));
    const TriangleMesh inner = box_mesh(Eigen::Vector3d::Ones(), offset);
    for (const auto& v : inner.vertices) mesh.vertices.push_back(v);
    for (const auto& t : inner.triangles) mesh.triangles.push_back({t[0] + 8, t[2] + 8, t[1] + 8});
    try {
      MeshShape shape(mesh, "with cavity");
      ADD_FAILURE() << "accepted a mesh with an inward shell";
    } catch (const InputError& e) {
      EXPECT_NE(std::string(e.what()).find("oriented inward"), std::string::npos) << e.what();
    }
  }
}

TEST(MeshShape, NestedOutwardShellsAreRefused) {
  // A 2 m box with a 0.8 m box inside, both wound outward: adding their volumes (8.512 instead of
  // the 8 m^3 the outer surface encloses) would give the body 6.4% too much mass. Refused whichever
  // shell comes first in the file; the disjoint pair above stays accepted.
  const TriangleMesh outer = box_mesh(Eigen::Vector3d::Constant(2.0));
  const TriangleMesh inner = box_mesh(Eigen::Vector3d::Constant(0.8), Eigen::Vector3d(0.1, -0.2, 0.05));
  for (const bool inner_first : {false, true}) {
    TriangleMesh mesh = inner_first ? inner : outer;
    const TriangleMesh& second = inner_first ? outer : inner;
    for (const auto& v : second.vertices) mesh.vertices.push_back(v);
    for (const auto& t : second.triangles) mesh.triangles.push_back({t[0] + 8, t[1] + 8, t[2] + 8});
    try {
      MeshShape shape(mesh, "nested");
      ADD_FAILURE() << "accepted nested outward shells, volume " << shape.volume();
    } catch (const InputError& e) {
      const std::string expected =
          inner_first ? "shell 1 (12 triangles) lies inside shell 2" : "shell 2 (12 triangles) lies inside shell 1";
      EXPECT_NE(std::string(e.what()).find(expected), std::string::npos) << e.what();
    }
  }
}

TEST(MeshShape, MarkersMeetRequirements) {
  struct Case {
    const char* name;
    TriangleMesh mesh;
  };
  const Case cases[] = {{"box", box_mesh(Eigen::Vector3d(1.0, 0.7, 0.4), Eigen::Vector3d(1, 2, 3), test_rotation())},
                        {"icosphere", testing::icosphere(4, 0.5)},
                        {"L prism", l_prism(0.5)}};
  for (const auto& c : cases) {
    const MeshShape mesh(c.mesh, c.name);
    const double h = mesh.equivalent_diameter() / 20.0;
    const SurfaceMarkers markers = mesh.surface_markers(h);
    std::mt19937_64 rng(45);
    const auto q =
        testing::measure_markers(mesh, markers, testing::random_points_on_mesh(mesh.body_mesh(), 20000, rng));
    std::printf("%s: N=%zu area_err=%.2e nn=[%.3f, %.3f]h coverage=%.3fh area=[%.3f, %.3f]h^2 mean %.3f\n", c.name,
                q.count, q.area_error, q.min_nearest, q.max_nearest, q.max_coverage, q.min_area, q.max_area,
                q.mean_area);
    // The patches tile the mesh exactly: the areas sum to its area to round-off.
    EXPECT_LT(std::abs(q.area_error), 1e-12) << c.name;
    EXPECT_LE(q.max_nearest, 1.5) << c.name;
    EXPECT_LE(q.max_coverage, 1.0) << c.name;
    EXPECT_LT(q.max_off_surface, 1e-12) << c.name;  // projected onto the mesh
    EXPECT_NEAR(q.mean_area, 1.0, 0.05) << c.name;
  }
}

}  // namespace test_mesh_shape
}  // namespace settle::body
