// The STL reader: ASCII and binary files (made by tests/data/make_test_meshes.py, not by
// settle's writer) give identical meshes; every broken file is refused with a message that
// names the defect; random and mutated bytes never crash it.
#include <filesystem>
#include <fstream>
#include <random>
#include <string>

#include <gtest/gtest.h>
#include <ostream>

#include "body/mesh_shape.hpp"
#include "body/stl_io.hpp"
#include "common/error.hpp"
#include "shape_test_support.hpp"

namespace settle::body {
namespace test_stl {

std::filesystem::path data(const std::string& name) {
  return std::filesystem::path(SETTLE_SOURCE_DIR) / "tests/data" / name;
}

std::string read_bytes(const std::filesystem::path& path) {
  std::ifstream in(path, std::ios::binary);
  return {std::istreambuf_iterator<char>(in), std::istreambuf_iterator<char>()};
}

// The message of the InputError thrown by f, or "" if none.
template <class F>
std::string refusal(F&& f) {
  try {
    f();
  } catch (const InputError& e) {
    return e.what();
  }
  return "";
}

TEST(Stl, AsciiAndBinaryCubeGiveTheSameMesh) {
  StlReadInfo ascii_info, binary_info;
  const TriangleMesh ascii = read_stl(data("cube_ascii.stl"), &ascii_info);
  const TriangleMesh binary = read_stl(data("cube_binary.stl"), &binary_info);
  EXPECT_FALSE(ascii_info.binary);
  // The binary file's header starts with "solid": detected by its exact size.
  EXPECT_TRUE(binary_info.binary);
  EXPECT_EQ(ascii_info.facet_count, 12u);
  EXPECT_EQ(ascii.vertices.size(), 8u);  // welded
  ASSERT_EQ(ascii.triangles.size(), binary.triangles.size());
  ASSERT_EQ(ascii.vertices.size(), binary.vertices.size());
  for (std::size_t i = 0; i < ascii.vertices.size(); ++i) EXPECT_EQ(ascii.vertices[i], binary.vertices[i]);
  EXPECT_EQ(ascii.triangles, binary.triangles);
}

TEST(Stl, TetrahedronMassPropertiesFromBothFormats) {
  // Legs 2, 3, 4 along the axes: V = 4, centroid (0.5, 0.75, 1); the coordinates are exact
  // in float, so both formats give the same numbers to round-off.
  for (const char* name : {"tetrahedron_ascii.stl", "tetrahedron_binary.stl"}) {
    const auto shape = load_mesh_shape(data(name));
    const VolumeMoments m = shape->volume_moments();
    EXPECT_NEAR(m.volume, 4.0, 1e-14) << name;
    EXPECT_TRUE(m.centroid.isApprox(Eigen::Vector3d(0.5, 0.75, 1.0), 1e-14)) << name;
  }
}

TEST(Stl, SeveralSolidsFormOneBody) {
  const auto shape = load_mesh_shape(data("two_solids_ascii.stl"));
  EXPECT_NEAR(shape->volume(), 8.0, 1e-13);
  ASSERT_EQ(shape->notes().size(), 1u);
  EXPECT_NE(shape->notes()[0].find("2 separate shells"), std::string::npos);
}

TEST(Stl, InvertedMeshIsReversedWithANote) {
  const auto inverted = load_mesh_shape(data("inverted_cube.stl"));
  EXPECT_NEAR(inverted->volume(), 1.0, 1e-15);
  ASSERT_EQ(inverted->notes().size(), 1u);
  EXPECT_NE(inverted->notes()[0].find("reversed"), std::string::npos);
  const auto cube = load_mesh_shape(data("cube_ascii.stl"));
  EXPECT_TRUE(inverted->mass_properties(1.0).inertia.isApprox(cube->mass_properties(1.0).inertia, 1e-15));
}

TEST(Stl, ScaleMultipliesCoordinates) {
  const auto shape = load_mesh_shape(data("cube_ascii.stl"), 1e-3);
  EXPECT_NEAR(shape->volume(), 1e-9, 1e-24);
  EXPECT_TRUE(shape->volume_moments().centroid.isApprox(Eigen::Vector3d::Constant(0.5e-3), 1e-14));
  EXPECT_NE(refusal([] { load_mesh_shape(data("cube_ascii.stl"), -1.0); }).find("scale"), std::string::npos);
}

struct Broken {
  const char* file;
  const char* message_part;
};

// Names the parameter in test listings (instead of a byte dump).
void PrintTo(const Broken& b, std::ostream* os) { *os << b.file; }

class BrokenStl : public ::testing::TestWithParam<Broken> {};

TEST_P(BrokenStl, IsRefusedWithAClearMessage) {
  const std::string message = refusal([] { load_mesh_shape(data(GetParam().file)); });
  ASSERT_FALSE(message.empty()) << GetParam().file << " was accepted";
  EXPECT_NE(message.find(GetParam().message_part), std::string::npos) << message;
  EXPECT_NE(message.find(GetParam().file), std::string::npos) << "the message must name the file: " << message;
}

INSTANTIATE_TEST_SUITE_P(
    Files, BrokenStl,
    ::testing::Values(Broken{"open_box.stl", "not watertight"}, Broken{"flipped_facet.stl", "inconsistent orientation"},
                      Broken{"nonmanifold.stl", "not manifold"}, Broken{"empty.stl", "empty"},
                      Broken{"no_facets.stl", "no triangles"}, Broken{"nan_ascii.stl", "not finite"},
                      Broken{"nan_binary.stl", "non-finite"}, Broken{"truncated_binary.stl", "announces 12 triangles"},
                      Broken{"count_too_large_binary.stl", "announces 4294967295 triangles"},
                      Broken{"quad_facet.stl", "more than 3 vertices"}, Broken{"garbage.stl", "not an STL file"},
                      Broken{"flat_sheet.stl", "encloses no volume"}, Broken{"does_not_exist.stl", "no such file"}),
    [](const auto& param_info) {
      std::string name = param_info.param.file;
      return name.substr(0, name.find('.'));
    });

TEST(Stl, WriterRoundTripsThroughBothFormats) {
  const TriangleMesh sphere = testing::icosphere(3, 0.7);
  const auto dir = std::filesystem::temp_directory_path();
  write_stl_ascii(sphere, dir / "settle_roundtrip_ascii.stl");
  write_stl_binary(sphere, dir / "settle_roundtrip_binary.stl");
  const double exact = polyhedron_moments(sphere).volume;
  // ASCII keeps 17 digits (exact); binary stores floats (relative rounding 6e-8 per coordinate).
  EXPECT_NEAR(load_mesh_shape(dir / "settle_roundtrip_ascii.stl")->volume(), exact, 1e-14 * exact);
  EXPECT_NEAR(load_mesh_shape(dir / "settle_roundtrip_binary.stl")->volume(), exact, 3e-7 * exact);
  std::filesystem::remove(dir / "settle_roundtrip_ascii.stl");
  std::filesystem::remove(dir / "settle_roundtrip_binary.stl");
}

// Whatever the bytes, the reader returns a mesh or throws InputError, and so does building a
// shape from what it returned: anything else (another exception, a crash) fails the test.
void expect_graceful(const std::string& bytes) {
  try {
    TriangleMesh mesh = parse_stl(bytes, "fuzz");
    MeshShape shape(std::move(mesh), "fuzz");
  } catch (const InputError&) {}
}

TEST(Stl, RandomBytesNeverCrash) {
  std::mt19937_64 rng(30);
  for (int trial = 0; trial < 3000; ++trial) {
    std::string bytes(rng() % 400, '\0');
    for (auto& c : bytes) c = static_cast<char>(rng() & 0xFF);
    if (trial % 3 == 0 && bytes.size() >= 84) {  // a plausible binary count
      const std::uint32_t count = static_cast<std::uint32_t>((bytes.size() - 84) / 50 + rng() % 3);
      for (int i = 0; i < 4; ++i) bytes[80 + i] = static_cast<char>((count >> (8 * i)) & 0xFF);
    }
    if (trial % 3 == 1) bytes = "solid x\n" + bytes;
    EXPECT_NO_FATAL_FAILURE(expect_graceful(bytes));
  }
}

TEST(Stl, MutatedFilesNeverCrash) {
  std::mt19937_64 rng(31);
  for (const char* name : {"cube_ascii.stl", "cube_binary.stl", "tetrahedron_ascii.stl", "tetrahedron_binary.stl"}) {
    const std::string original = read_bytes(data(name));
    for (int trial = 0; trial < 1500; ++trial) {
      std::string bytes = original;
      const int edits = 1 + static_cast<int>(rng() % 4);
      for (int e = 0; e < edits && !bytes.empty(); ++e) {
        const std::size_t at = rng() % bytes.size();
        switch (rng() % 4) {
          case 0:
            bytes[at] = static_cast<char>(rng() & 0xFF);
            break;
          case 1:
            bytes.erase(at, 1 + rng() % 8);
            break;
          case 2:
            bytes.insert(at, 1, static_cast<char>("0123456789.-e \nvertxfacetnormal"[rng() % 31]));
            break;
          default:
            bytes.resize(at);
            break;
        }
      }
      EXPECT_NO_FATAL_FAILURE(expect_graceful(bytes));
    }
  }
}

}  // namespace test_stl
}  // namespace settle::body
