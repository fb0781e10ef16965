// VTK XML output: the files are read back here with a minimal parser of our own (the XML header
// by regular expressions, the appended raw block by byte offsets), so nothing depends on VTK.
#include <gtest/gtest.h>

#include <unistd.h>
#include <algorithm>
#include <bit>
#include <cmath>
#include <cstdint>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <map>
#include <numbers>
#include <regex>
#include <sstream>
#include <string>
#include <utility>
#include <vector>

#include <Eigen/Geometry>

#include "body/mesh_shape.hpp"
#include "body/shape_factory.hpp"
#include "body/surface_triangulation.hpp"
#include "common/error.hpp"
#include "io/pvd.hpp"
#include "io/vtk.hpp"
#include "lbm/solver.hpp"
#include "support/vtk_reader.hpp"

namespace settle::io {
namespace test_vtk {

namespace fs = std::filesystem;
using std::numbers::pi;
using namespace settle::test::vtk_reader;

// ---------------------------------------------------------------------------------------------
// Test helpers

/// A fresh directory per test, removed afterwards.
class ScratchDirectory {
 public:
  ScratchDirectory() {
    const auto* info = ::testing::UnitTest::GetInstance()->current_test_info();
    path_ = fs::temp_directory_path() / (std::string("settle_vtk_") + info->test_suite_name() + "_" + info->name() +
                                         "_" + std::to_string(::getpid()));
    fs::remove_all(path_);
    fs::create_directories(path_);
  }
  ~ScratchDirectory() {
    std::error_code ignored;
    fs::remove_all(path_, ignored);
  }
  const fs::path& path() const { return path_; }

 private:
  fs::path path_;
};

/// The blocks tile the appended data with no gap or overlap, in the order of the header, each
/// holding tuples x components values of its type (decompressed, for a compressed file); the file
/// ends right after the last block.
void expect_consistent_blocks(const ParsedVtk& parsed, const std::map<std::string, std::size_t>& tuples) {
  std::uint64_t expected_offset = 0;
  for (const ParsedArray& array : parsed.arrays) {
    EXPECT_EQ(array.offset, expected_offset) << array.name;
    ASSERT_TRUE(tuples.count(array.name)) << array.name;
    EXPECT_EQ(array.byte_count,
              tuples.at(array.name) * static_cast<std::size_t>(array.components) * type_size(array.type))
        << array.name;
    expected_offset = array.offset + array.stored_bytes;
  }
  EXPECT_EQ(parsed.appended.size(), expected_offset + kTrailer.size());
  EXPECT_EQ(parsed.appended.substr(expected_offset), kTrailer);
}

void expect_file_header(const ParsedVtk& parsed, const std::string& type) {
  const auto file = element_attributes(parsed.xml, "VTKFile");
  EXPECT_EQ(file.at("type"), type);
  EXPECT_EQ(file.at("header_type"), "UInt64");
  // The reader decodes with the declared order; the test machine decodes with its own.
  EXPECT_EQ(file.at("byte_order"), std::endian::native == std::endian::little ? "LittleEndian" : "BigEndian");
}

// ---------------------------------------------------------------------------------------------
// Fluid (.vti)

// A field with known lattice values: u linear in the coordinates (so the second-order central
// and one-sided differences of the vorticity are exact) and a density varying cell by cell.
constexpr double kU0 = 0.01, kA = 1.0e-3, kB = -2.0e-3, kC = 3.0e-3;
Eigen::Vector3d known_velocity(int x, int y, int z) { return {kU0 + kA * y, kB * z, kC * x}; }
double known_density(int x, int y, int z) { return 1.0 + 0.01 * std::sin(x + 2.0 * y + 3.0 * z); }
// curl (u0 + a y, b z, c x) = (d(cx)/dy - d(bz)/dz, d(u0 + a y)/dz - d(cx)/dx, d(bz)/dx - d(u0 + a y)/dy)
const Eigen::Vector3d kKnownVorticity(-kB, -kC, -kA);

std::unique_ptr<lbm::Solver> solver_with_known_field(std::array<lbm::Boundary, 3> boundaries) {
  lbm::SolverConfig config;
  config.nx = 6;
  config.ny = 5;
  config.nz = 4;
  config.boundaries = boundaries;
  auto fluid = lbm::make_solver(config);
  fluid->initialise([](int x, int y, int z) {
    return lbm::CellState{known_density(x, y, z), known_velocity(x, y, z)};
  });
  return fluid;
}

FieldScaling test_scaling() {
  FieldScaling scaling;
  scaling.window_origin_si = {0.1, -0.2, 0.3};
  scaling.dx_si = 1.0e-4;
  scaling.dt_si = 2.0e-5;
  scaling.fluid_density_si = 998.2;
  return scaling;
}

/// Relative rounding of one value stored in the file.
double storage_rounding(VtkPrecision precision) {
  return precision == VtkPrecision::float32 ? std::ldexp(1.0, -24) : std::ldexp(1.0, -53);
}

TEST(VtkFluid, HeaderBlocksAndValuesRoundTrip) {
  const ScratchDirectory scratch;
  const auto no_slip = lbm::Boundary::no_slip;
  const auto fluid = solver_with_known_field({no_slip, no_slip, no_slip});
  const FieldScaling scaling = test_scaling();
  const std::size_t cells = fluid->cell_count();
  std::vector<ScalarPointField> extra{{"marker", std::vector<double>(cells)}};
  for (std::size_t n = 0; n < cells; ++n) extra[0].values[n] = 0.5 + static_cast<double>(n);

  for (const VtkCompression compression : {VtkCompression::none, VtkCompression::zlib})
    for (const VtkPrecision precision : {VtkPrecision::float32, VtkPrecision::float64}) {
      SCOPED_TRACE(precision == VtkPrecision::float32 ? "float32" : "float64");
      SCOPED_TRACE(compression == VtkCompression::zlib ? "zlib" : "raw");
      const fs::path path = scratch.path() / "fluid.vti";
      write_fluid_vti(path, *fluid, scaling, {precision, 0.125, compression}, extra);
      EXPECT_FALSE(fs::exists(path.string() + ".tmp"));
      const ParsedVtk parsed = parse_vtk(path);

      expect_file_header(parsed, "ImageData");
      const auto image = element_attributes(parsed.xml, "ImageData");
      EXPECT_EQ(image.at("WholeExtent"), "0 5 0 4 0 3");
      EXPECT_EQ(element_attributes(parsed.xml, "Piece").at("Extent"), "0 5 0 4 0 3");
      // The text round-trips a double exactly (shortest representation); the origin itself is the
      // sum window origin + dx/2, one rounding (1e-16 relative) away from the exact value.
      const Eigen::Vector3d origin = parse_triple(image.at("Origin"));
      const Eigen::Vector3d expected_origin = scaling.window_origin_si + Eigen::Vector3d::Constant(0.5e-4);
      EXPECT_LT((origin - expected_origin).norm(), 1e-15);
      EXPECT_EQ(parse_triple(image.at("Spacing")), Eigen::Vector3d::Constant(scaling.dx_si));

      ASSERT_EQ(parsed.arrays.size(), 5u);
      const std::vector<std::string> names{"TimeValue", "velocity", "pressure", "vorticity", "marker"};
      const std::vector<std::string> sections{"FieldData", "PointData", "PointData", "PointData", "PointData"};
      const std::vector<int> components{1, 3, 1, 3, 1};
      const std::string float_type = precision == VtkPrecision::float32 ? "Float32" : "Float64";
      for (std::size_t i = 0; i < names.size(); ++i) {
        EXPECT_EQ(parsed.arrays[i].name, names[i]);
        EXPECT_EQ(parsed.arrays[i].section, sections[i]);
        EXPECT_EQ(parsed.arrays[i].components, components[i]);
        EXPECT_EQ(parsed.arrays[i].type, i == 0 ? "Float64" : float_type);
      }
      expect_consistent_blocks(
          parsed,
          {{"TimeValue", 1}, {"velocity", cells}, {"pressure", cells}, {"vorticity", cells}, {"marker", cells}});
      EXPECT_EQ(values_of(parsed.array("TimeValue")), std::vector<double>{0.125});

      const std::vector<double> velocity = values_of(parsed.array("velocity"));
      const std::vector<double> pressure = values_of(parsed.array("pressure"));
      const std::vector<double> vorticity = values_of(parsed.array("vorticity"));
      const std::vector<double> marker = values_of(parsed.array("marker"));
      const double rounding = storage_rounding(precision);
      // The solver recovers rho and u from its populations with round-off of ~1e-16 of their
      // magnitudes (rho ~ 1, u ~ 0.03); 1e-14 of the largest SI value leaves a wide margin for
      // that, while storage adds one rounding (relative `rounding`) per value. A swapped component,
      // a wrong scale or a misplaced cell is off by far more.
      const double velocity_scale = scaling.dx_si / scaling.dt_si;
      const double pressure_scale = scaling.fluid_density_si * velocity_scale * velocity_scale;
      const double velocity_floor = 1e-14 * 0.03 * velocity_scale;
      const double pressure_floor = 1e-14 * pressure_scale;
      for (int z = 0; z < 4; ++z)
        for (int y = 0; y < 5; ++y)
          for (int x = 0; x < 6; ++x) {
            const std::size_t n = fluid->linear_index(x, y, z);
            const Eigen::Vector3d u_si = known_velocity(x, y, z) * velocity_scale;
            const Eigen::Vector3d w_si = kKnownVorticity / scaling.dt_si;
            for (int a = 0; a < 3; ++a) {
              EXPECT_NEAR(velocity[3 * n + a], u_si(a), rounding * std::abs(u_si(a)) + velocity_floor);
              EXPECT_NEAR(vorticity[3 * n + a], w_si(a), rounding * std::abs(w_si(a)) + velocity_floor / scaling.dx_si);
            }
            const double p_si = (known_density(x, y, z) - 1.0) / 3.0 * pressure_scale;
            EXPECT_NEAR(pressure[n], p_si, rounding * std::abs(p_si) + pressure_floor);
            EXPECT_NEAR(marker[n], extra[0].values[n], rounding * extra[0].values[n]);  // values passed as given
          }
    }
}

// The compressed layout of VTK's documentation: 32 KiB blocks, the last one partial, each
// inflating to its declared size (the reader checks), the VTKFile element naming the compressor.
// A fluid at rest is the same value everywhere: deflate stores such a run in a few bytes per block
// (a back-reference of at most 258 bytes costs about 2 bytes, so 32 KiB needs ~250 bytes), so
// the compressed velocity is under a tenth of its raw size with a wide margin.
TEST(VtkFluid, ZlibBlocksFollowVtksLayoutAndShrinkAUniformField) {
  const ScratchDirectory scratch;
  lbm::SolverConfig config;
  config.nx = config.ny = config.nz = 40;
  const auto fluid = lbm::make_solver(config);
  fluid->initialise([](int, int, int) { return lbm::CellState{1.0, Eigen::Vector3d::Zero()}; });
  const fs::path path = scratch.path() / "rest.vti";
  write_fluid_vti(path, *fluid, test_scaling(), {VtkPrecision::float32, std::nullopt, VtkCompression::zlib}, {});
  const ParsedVtk parsed = parse_vtk(path);
  EXPECT_EQ(element_attributes(parsed.xml, "VTKFile").at("compressor"), "vtkZLibDataCompressor");
  const ParsedArray& velocity = parsed.array("velocity");
  const std::uint64_t raw_bytes = 40 * 40 * 40 * 3 * 4;  // 768 000 bytes: 23 full blocks and 14 336 bytes
  EXPECT_EQ(velocity.byte_count, raw_bytes);
  EXPECT_EQ(velocity.blocks, 24u);
  EXPECT_LT(velocity.stored_bytes, raw_bytes / 10);
  for (const double v : values_of(velocity)) ASSERT_EQ(v, 0.0);
  expect_consistent_blocks(parsed, {{"velocity", 64000}, {"pressure", 64000}, {"vorticity", 64000}});
}

TEST(VtkFluid, FieldScalingFromTheUnitConverter) {
  const coupling::UnitConverter units(2.0e-4, 5.0e-5, 998.2, 1.0e-6);
  const FieldScaling scaling = field_scaling(units, {1.0, 2.0, 3.0});
  EXPECT_EQ(scaling.window_origin_si, Eigen::Vector3d(1.0, 2.0, 3.0));
  // One lattice velocity is one cell per step: dx/dt = 4 m/s exactly representable up to one rounding.
  EXPECT_NEAR(scaling.velocity_scale_si(), 4.0, 4.0 * 1e-15);
  EXPECT_NEAR(scaling.pressure_scale_si(), 998.2 * 16.0, 998.2 * 16.0 * 1e-15);
  EXPECT_NEAR(scaling.rate_scale_si(), 2.0e4, 2.0e4 * 1e-15);
}

TEST(VtkFluid, SolidFractionWrapsPeriodicAxesAndDropsCellsOutside) {
  const auto fluid = solver_with_known_field({lbm::Boundary::periodic, lbm::Boundary::no_slip, lbm::Boundary::no_slip});
  coupling::SolidCells cells;
  cells.cell = {{-1, 2, 1}, {6, 0, 0}, {2, 5, 0}, {3, 3, 3}};
  cells.alpha = {0.25, 0.5, 0.75, 1.0};
  const std::vector<double> alpha = solid_fraction_field(*fluid, cells);
  ASSERT_EQ(alpha.size(), fluid->cell_count());
  EXPECT_EQ(alpha[fluid->linear_index(5, 2, 1)], 0.25);  // x = -1 wraps to nx - 1
  EXPECT_EQ(alpha[fluid->linear_index(0, 0, 0)], 0.5);   // x = nx wraps to 0
  EXPECT_EQ(alpha[fluid->linear_index(3, 3, 3)], 1.0);
  double sum = 0.0;
  for (const double value : alpha) sum += value;
  EXPECT_EQ(sum, 1.75);  // y = 5 lies beyond the no-slip axis (ny = 5): dropped
}

TEST(VtkFluid, RefusesBadExtraFieldsAndUnwritablePaths) {
  const ScratchDirectory scratch;
  const auto fluid =
      solver_with_known_field({lbm::Boundary::periodic, lbm::Boundary::periodic, lbm::Boundary::periodic});
  const std::vector<ScalarPointField> short_field{{"alpha", std::vector<double>(3)}};
  EXPECT_THROW(write_fluid_vti(scratch.path() / "a.vti", *fluid, test_scaling(), {}, short_field),
               std::invalid_argument);
  const std::vector<ScalarPointField> clash{{"pressure", std::vector<double>(fluid->cell_count())}};
  EXPECT_THROW(write_fluid_vti(scratch.path() / "a.vti", *fluid, test_scaling(), {}, clash), std::invalid_argument);
  EXPECT_FALSE(fs::exists(scratch.path() / "a.vti"));

  const fs::path missing = scratch.path() / "no" / "such" / "dir" / "fluid.vti";
  try {
    write_fluid_vti(missing, *fluid, test_scaling());
    ADD_FAILURE() << "no error for an unwritable path";
  } catch (const InputError& error) {
    EXPECT_NE(std::string(error.what()).find(missing.string()), std::string::npos) << error.what();
  }
}

TEST(VtkFluid, RewritingReplacesTheFileWholeAndLeavesNoTemporary) {
  const ScratchDirectory scratch;
  const auto fluid =
      solver_with_known_field({lbm::Boundary::periodic, lbm::Boundary::periodic, lbm::Boundary::periodic});
  const fs::path path = scratch.path() / "fluid.vti";
  write_fluid_vti(path, *fluid, test_scaling(), {VtkPrecision::float64, std::nullopt});
  const auto first_size = fs::file_size(path);
  write_fluid_vti(path, *fluid, test_scaling(), {VtkPrecision::float32, std::nullopt});
  const ParsedVtk parsed = parse_vtk(path);
  const std::size_t cells = fluid->cell_count();
  expect_consistent_blocks(parsed, {{"velocity", cells}, {"pressure", cells}, {"vorticity", cells}});
  EXPECT_LT(fs::file_size(path), first_size);  // float32 now: nothing of the longer file remains
  EXPECT_EQ(std::distance(fs::directory_iterator(scratch.path()), fs::directory_iterator()), 1);
}

// ---------------------------------------------------------------------------------------------
// Surface triangulation

std::unique_ptr<body::Shape> make(const std::string& kind, auto&& fill) {
  body::ShapeSpec spec;
  spec.shape = kind;
  fill(spec);
  return body::make_shape(spec);
}

double enclosed_volume(const body::TriangleMesh& mesh) {
  double six_volume = 0.0;
  for (const auto& t : mesh.triangles)
    six_volume += mesh.vertices[t[0]].dot(mesh.vertices[t[1]].cross(mesh.vertices[t[2]]));
  return six_volume / 6.0;
}

double longest_edge(const body::TriangleMesh& mesh) {
  double longest = 0.0;
  for (const auto& t : mesh.triangles)
    for (int k = 0; k < 3; ++k)
      longest = std::max(longest, (mesh.vertices[t[k]] - mesh.vertices[t[(k + 1) % 3]]).norm());
  return longest;
}

/// Closed and consistently oriented: every edge is used once in each direction, so each
/// undirected edge is shared by exactly two triangles.
void expect_closed(const body::TriangleMesh& mesh) {
  const auto key = [](int from, int to) {
    return (static_cast<std::uint64_t>(from) << 32) | static_cast<std::uint32_t>(to);
  };
  std::vector<std::uint64_t> directed;
  for (const auto& t : mesh.triangles)
    for (int k = 0; k < 3; ++k) directed.push_back(key(t[k], t[(k + 1) % 3]));
  std::sort(directed.begin(), directed.end());
  const bool unique = std::adjacent_find(directed.begin(), directed.end()) == directed.end();
  EXPECT_TRUE(unique) << "an edge is used twice in the same direction";
  std::size_t unmatched = 0;
  for (const std::uint64_t edge : directed) {
    const auto from = static_cast<int>(edge >> 32), to = static_cast<int>(edge & 0xffffffffu);
    if (!std::binary_search(directed.begin(), directed.end(), key(to, from))) ++unmatched;
  }
  EXPECT_EQ(unmatched, 0u) << "edges not shared by exactly two consistently oriented triangles";
  // Euler characteristic of a sphere: V - E + F = 2 (one shell, no handles).
  const auto edges = static_cast<long>(directed.size() / 2);
  EXPECT_EQ(static_cast<long>(mesh.vertices.size()) - edges + static_cast<long>(mesh.triangles.size()), 2);
}

/// Every vertex lies on the surface: the bisection stops within 1e-13 of the bounding radius,
/// so 1e-11 of it covers that and the round-off of the signed distance.
void expect_vertices_on_surface(const body::Shape& shape, const body::TriangleMesh& mesh) {
  double worst = 0.0;
  for (const auto& v : mesh.vertices) worst = std::max(worst, std::abs(shape.signed_distance(v)));
  EXPECT_LT(worst, 1e-11 * shape.bounding_radius());
}

struct Convergence {
  std::vector<double> edges, errors;
};

/// Relative volume error of the triangulation for each requested grid edge.
Convergence volume_convergence(const body::Shape& shape, double exact_volume, const std::vector<double>& max_edges) {
  Convergence result;
  for (const double max_edge : max_edges) {
    const body::TriangleMesh mesh = body::surface_triangulation(shape, max_edge);
    expect_closed(mesh);
    expect_vertices_on_surface(shape, mesh);
    result.edges.push_back(longest_edge(mesh));
    result.errors.push_back((enclosed_volume(mesh) - exact_volume) / exact_volume);
  }
  return result;
}

/// Grid edges of 1/4, 1/8 and 1/16 of the smallest radius of curvature: coarser grids are not
/// yet in the asymptotic range (measured orders 2.1-2.2 at edges of 1/2 to 1 radius).
std::vector<double> edges_resolving(double smallest_curvature_radius) {
  return {smallest_curvature_radius / 4.0, smallest_curvature_radius / 8.0, smallest_curvature_radius / 16.0};
}

void expect_second_order_from_inside(const Convergence& c) {
  for (std::size_t i = 0; i < c.errors.size(); ++i) {
    // Vertices on a convex surface: the polyhedron is inscribed, so it lies inside the body.
    EXPECT_LT(c.errors[i], 0.0) << "level " << i;
    if (i == 0) continue;
    // An inscribed polyhedron of a smooth surface misses a cap of height ~ h^2 / (2 rho) under
    // each triangle, so the volume error falls as h^2; the next term is smaller by ~(h/rho)^2 <=
    // 1/16, and the grid counts are rounded, so successive meshes are not exactly similar. The
    // order measured against the longest edge must be 2 within 0.05 (measured 1.99-2.02).
    const double order = std::log(c.errors[i - 1] / c.errors[i]) / std::log(c.edges[i - 1] / c.edges[i]);
    EXPECT_NEAR(order, 2.0, 0.05) << "level " << i << ": edge " << c.edges[i] << ", error " << c.errors[i];
  }
}

TEST(VtkSurface, SphereTriangulationIsClosedAndItsVolumeConvergesAtSecondOrder) {
  const auto sphere = make("sphere", [](body::ShapeSpec& s) { s.diameter = 2.0e-3; });
  const double radius = 1.0e-3;
  const Convergence c = volume_convergence(*sphere, 4.0 / 3.0 * pi * radius * radius * radius, edges_resolving(radius));
  expect_second_order_from_inside(c);
  // A triangle inscribed in the sphere with circumradius r misses a cap of height at most
  // r^2 / (2 R) (to leading order), so the relative volume error is at most
  // 4 pi R^2 r^2 / (2 R) / (4/3 pi R^3) = 3 r^2 / (2 R^2); with r <= L / sqrt(3) for the
  // non-obtuse triangles of the grid (L the longest edge), at most L^2 / (2 R^2).
  for (std::size_t i = 0; i < c.errors.size(); ++i) {
    const double relative_edge = c.edges[i] / radius;
    EXPECT_LT(-c.errors[i], 0.5 * relative_edge * relative_edge) << "level " << i;
  }
}

TEST(VtkSurface, SpheroidTriangulationsConvergeToTheExactVolume) {
  for (const double aspect_ratio : {2.5, 0.4}) {
    SCOPED_TRACE(aspect_ratio);
    const auto spheroid = make("spheroid", [&](body::ShapeSpec& s) {
      s.diameter = 2.0;
      s.aspect_ratio = aspect_ratio;
    });
    // Semi-axes a = b = 1 and c = aspect_ratio: V = 4/3 pi a^2 c. The smallest radius of
    // curvature is a^2 / c at the equator of a prolate spheroid, c^2 / a at the rim of an oblate one.
    const double exact = 4.0 / 3.0 * pi * aspect_ratio;
    const double smallest_radius = aspect_ratio > 1.0 ? 1.0 / aspect_ratio : aspect_ratio * aspect_ratio;
    expect_second_order_from_inside(volume_convergence(*spheroid, exact, edges_resolving(smallest_radius)));
  }
}

TEST(VtkSurface, CuboidTriangulationIsExact) {
  const auto cuboid = make("cuboid", [](body::ShapeSpec& s) { s.size = std::array<double, 3>{1.0, 2.0, 0.5}; });
  for (const double max_edge : {0.3, 0.11}) {
    const body::TriangleMesh mesh = body::surface_triangulation(*cuboid, max_edge);
    expect_closed(mesh);
    expect_vertices_on_surface(*cuboid, mesh);
    // The stretched ray directions send the cube's edges to the cuboid's edges, so the faces are
    // tiled exactly; what remains is the bisection's 1e-13 of the radius per vertex.
    EXPECT_NEAR(enclosed_volume(mesh), 1.0, 1e-11);
    // Grid lines are refined to max_edge; a quad's diagonal, on a flat face, is at most sqrt(2)
    // times that (1e-9: round-off).
    EXPECT_LE(longest_edge(mesh), std::sqrt(2.0) * max_edge * (1.0 + 1e-9));
  }
}

TEST(VtkSurface, CylinderAndSuperellipsoidTriangulationsAreClosedAndConverge) {
  const auto cylinder = make("cylinder", [](body::ShapeSpec& s) {
    s.diameter = 2.0;
    s.length = 1.0;
  });
  // Edges of 1/5 to 1/40 of the diameter. The grid does not follow the rims, but the cut
  // corners shrink with the grid too: over edges 8 times smaller the error must fall at least
  // 30 times (second order gives 64, first order 8; measured 57).
  const std::vector<double> edges{0.4, 0.2, 0.1, 0.05};
  const Convergence c = volume_convergence(*cylinder, pi, edges);
  EXPECT_LT(std::abs(c.errors.back()), std::abs(c.errors.front()) / 30.0);

  // Volume from the shape's own closed form (Beta functions; tested in tests/body).
  const auto superellipsoid = make("superellipsoid", [](body::ShapeSpec& s) {
    s.semi_axes = std::array<double, 3>{1.0, 0.8, 0.6};
    s.exponents = std::array<double, 2>{0.5, 0.8};
  });
  const Convergence s = volume_convergence(*superellipsoid, superellipsoid->volume(), edges);
  EXPECT_LT(std::abs(s.errors.back()), std::abs(s.errors.front()) / 30.0);  // measured 69
}

TEST(VtkSurface, MeshesKeepTheirOwnTriangles) {
  const auto cube = body::load_mesh_shape(fs::path(SETTLE_SOURCE_DIR) / "tests/data/cube_ascii.stl");
  const body::TriangleMesh mesh = body::surface_triangulation(*cube, 1e-3);
  EXPECT_EQ(mesh.triangles, cube->body_mesh().triangles);
  EXPECT_EQ(mesh.vertices.size(), cube->body_mesh().vertices.size());
  expect_closed(mesh);
  EXPECT_NEAR(enclosed_volume(mesh), 1.0, 1e-14);  // unit cube about its centroid: exact arithmetic
}

TEST(VtkSurface, RefusesUnusableEdgeLengths) {
  const auto sphere = make("sphere", [](body::ShapeSpec& s) { s.diameter = 1.0; });
  EXPECT_THROW(body::surface_triangulation(*sphere, 0.0), std::invalid_argument);
  EXPECT_THROW(body::surface_triangulation(*sphere, std::nan("")), std::invalid_argument);
  EXPECT_THROW(body::surface_triangulation(*sphere, 1e-5), std::invalid_argument);  // ~1e10 triangles
}

TEST(VtkSurface, PosedSurfaceFileHoldsTheMovedPointsTrianglesAndRigidVelocity) {
  const ScratchDirectory scratch;
  const auto spheroid = make("spheroid", [](body::ShapeSpec& s) {
    s.diameter = 2.0e-3;
    s.aspect_ratio = 2.0;
  });
  const body::TriangleMesh surface_b = body::surface_triangulation(*spheroid, 0.5e-3);
  BodySnapshot body;
  body.position_si = {0.02, 0.03, 1.5};
  body.body_to_inertial = Eigen::AngleAxisd(0.7, Eigen::Vector3d(1.0, -2.0, 0.5).normalized()).toRotationMatrix();
  body.velocity_si = {0.001, -0.002, -0.05};
  body.angular_velocity_n_si = {3.0, -1.0, 2.0};
  const fs::path path = scratch.path() / "surface.vtp";
  write_surface_vtp(path, surface_b, body, {VtkPrecision::float32, 2.5});
  const ParsedVtk parsed = parse_vtk(path);

  expect_file_header(parsed, "PolyData");
  const std::size_t points = surface_b.vertices.size(), triangles = surface_b.triangles.size();
  const auto piece = element_attributes(parsed.xml, "Piece");
  EXPECT_EQ(piece.at("NumberOfPoints"), std::to_string(points));
  EXPECT_EQ(piece.at("NumberOfPolys"), std::to_string(triangles));
  EXPECT_EQ(piece.at("NumberOfVerts"), "0");
  expect_consistent_blocks(parsed, {{"TimeValue", 1},
                                    {"velocity", points},
                                    {"Points", points},
                                    {"connectivity", 3 * triangles},
                                    {"offsets", triangles}});
  EXPECT_EQ(parsed.array("Points").section, "Points");
  EXPECT_EQ(parsed.array("Points").type, "Float64");
  EXPECT_EQ(parsed.array("velocity").section, "PointData");
  EXPECT_EQ(parsed.array("connectivity").section, "Polys");
  EXPECT_EQ(parsed.array("offsets").type, "Int64");
  EXPECT_EQ(values_of(parsed.array("TimeValue")), std::vector<double>{2.5});

  const std::vector<double> xyz = values_of(parsed.array("Points"));
  const std::vector<double> velocity = values_of(parsed.array("velocity"));
  const double speed_scale = body.velocity_si.norm() + body.angular_velocity_n_si.norm() * 2.0e-3;
  for (std::size_t i = 0; i < points; ++i) {
    const Eigen::Vector3d arm = body.body_to_inertial * surface_b.vertices[i];
    const Eigen::Vector3d x = body.position_si + arm;
    const Eigen::Vector3d v = body.velocity_si + body.angular_velocity_n_si.cross(arm);
    for (int a = 0; a < 3; ++a) {
      // Float64 points: the same arithmetic as the writer's, so equal to a few ulp of 1.5 m.
      EXPECT_NEAR(xyz[3 * i + a], x(a), 1e-15);
      // Float32 velocity: one rounding, relative 2^-24.
      EXPECT_NEAR(velocity[3 * i + a], v(a), std::ldexp(1.0, -24) * std::abs(v(a)) + 1e-16 * speed_scale);
    }
  }
  // The written polygons are the triangulation's triangles, and still a closed surface.
  const std::vector<double> connectivity = values_of(parsed.array("connectivity"));
  const std::vector<double> offsets = values_of(parsed.array("offsets"));
  body::TriangleMesh read_back;
  for (std::size_t i = 0; i < points; ++i) read_back.vertices.emplace_back(xyz[3 * i], xyz[3 * i + 1], xyz[3 * i + 2]);
  for (std::size_t t = 0; t < triangles; ++t) {
    EXPECT_EQ(offsets[t], static_cast<double>(3 * (t + 1)));
    read_back.triangles.push_back({static_cast<int>(connectivity[3 * t]), static_cast<int>(connectivity[3 * t + 1]),
                                   static_cast<int>(connectivity[3 * t + 2])});
  }
  EXPECT_EQ(read_back.triangles, surface_b.triangles);
  expect_closed(read_back);
  // A rotation keeps the volume, and the divergence-theorem volume does not depend on the
  // origin for a closed surface: the translated, rotated copy encloses what the body-frame one
  // does, to the round-off of coordinates of size 1.5 m (1e-16 relative times ~1e3 triangles).
  EXPECT_NEAR(enclosed_volume(read_back), enclosed_volume(surface_b), 1e-13 * enclosed_volume(surface_b) + 1e-18);
}

// ---------------------------------------------------------------------------------------------
// Collections (.pvd)

std::vector<PvdCollection::Entry> read_pvd(const fs::path& path) {
  const std::string content = read_bytes(path);
  EXPECT_NE(content.find("<VTKFile type=\"Collection\""), std::string::npos);
  EXPECT_NE(content.find("</Collection>\n</VTKFile>\n"), std::string::npos);
  static const std::regex dataset(R"re(<DataSet ([^>]*)/>)re");
  std::vector<PvdCollection::Entry> entries;
  for (auto it = std::sregex_iterator(content.begin(), content.end(), dataset); it != std::sregex_iterator(); ++it) {
    auto attributes = attributes_of((*it)[1].str());
    entries.push_back({std::stod(attributes["timestep"]), attributes["file"]});
  }
  return entries;
}

TEST(VtkPvd, ListsEntriesInOrderAndKeepsEarlierOnesOnEveryRewrite) {
  const ScratchDirectory scratch;
  const fs::path pvd = scratch.path() / "fluid.pvd";
  PvdCollection collection(pvd);
  EXPECT_FALSE(fs::exists(pvd));
  const std::vector<double> times{0.0, 0.1, 0.2 + 1e-12, 1.0 / 3.0};
  for (std::size_t i = 0; i < times.size(); ++i) {
    const fs::path file = scratch.path() / "fields" / ("fluid_" + std::to_string(i) + ".vti");
    collection.add(times[i], file);
    const auto entries = read_pvd(pvd);
    ASSERT_EQ(entries.size(), i + 1);
    for (std::size_t k = 0; k <= i; ++k) {
      EXPECT_EQ(entries[k].time_si, times[k]);  // the shortest round-trip text reads back exactly
      EXPECT_EQ(entries[k].file, "fields/fluid_" + std::to_string(k) + ".vti");  // relative to the .pvd
    }
  }
  EXPECT_EQ(collection.entries().size(), times.size());
  EXPECT_FALSE(fs::exists(pvd.string() + ".tmp"));

  // Time must increase: a repeated or earlier time is refused and the file stays as it was.
  const std::string before = read_bytes(pvd);
  EXPECT_THROW(collection.add(1.0 / 3.0, scratch.path() / "x.vti"), std::invalid_argument);
  EXPECT_THROW(collection.add(0.05, scratch.path() / "x.vti"), std::invalid_argument);
  EXPECT_EQ(read_bytes(pvd), before);
}

TEST(VtkPvd, RelativeWorkingDirectoryPathsAndSpecialCharacters) {
  const ScratchDirectory scratch;
  const fs::path previous = fs::current_path();
  fs::current_path(scratch.path());
  PvdCollection collection(fs::path("run") / "vtk" / "surface.pvd");
  fs::create_directories("run/vtk");
  collection.add(0.5, fs::path("run") / "vtk" / "a&b \"1\".vtp");
  collection.add(0.75, scratch.path() / "run" / "surface_2.vtp");  // absolute, one folder up
  const auto entries = read_pvd("run/vtk/surface.pvd");
  fs::current_path(previous);
  ASSERT_EQ(entries.size(), 2u);
  EXPECT_EQ(entries[0].file, "a&amp;b &quot;1&quot;.vtp");  // XML-escaped in the file
  EXPECT_EQ(entries[1].file, "../surface_2.vtp");
  EXPECT_EQ(collection.entries()[0].file, "a&b \"1\".vtp");
}

TEST(VtkPvd, ResumeKeepsEntriesUpToTheRestartTime) {
  const ScratchDirectory scratch;
  const fs::path pvd = scratch.path() / "fluid.pvd";
  EXPECT_TRUE(PvdCollection::resume(pvd, 1.0).entries().empty());  // no file yet
  {
    PvdCollection collection(pvd);
    for (int i = 0; i < 5; ++i) collection.add(0.1 * i, scratch.path() / ("f&" + std::to_string(i) + ".vti"));
  }
  PvdCollection resumed = PvdCollection::resume(pvd, 0.25);
  ASSERT_EQ(resumed.entries().size(), 3u);
  EXPECT_EQ(resumed.entries()[2].time_si, 0.1 * 2);
  EXPECT_EQ(resumed.entries()[2].file, "f&2.vti");
  EXPECT_EQ(read_pvd(pvd).size(), 3u);  // rewritten at once: the dropped entries are gone
  resumed.add(0.3, scratch.path() / "g.vti");
  const auto entries = read_pvd(pvd);
  ASSERT_EQ(entries.size(), 4u);
  EXPECT_EQ(entries[3].file, "g.vti");
  EXPECT_EQ(entries[0].file, "f&amp;0.vti");

  std::ofstream(scratch.path() / "junk.pvd") << "not a collection";
  EXPECT_THROW(PvdCollection::resume(scratch.path() / "junk.pvd", 1.0), InputError);
}

TEST(VtkPvd, UnwritableCollectionNamesItsPath) {
  const ScratchDirectory scratch;
  const fs::path pvd = scratch.path() / "missing" / "fluid.pvd";
  PvdCollection collection(pvd);
  try {
    collection.add(0.0, scratch.path() / "a.vti");
    ADD_FAILURE() << "no error for an unwritable collection";
  } catch (const InputError& error) {
    EXPECT_NE(std::string(error.what()).find(pvd.string()), std::string::npos) << error.what();
  }
}

}  // namespace test_vtk
}  // namespace settle::io
