// Building shapes from the [particle] keys: every shape, and every refusal names its key.
#include <cmath>
#include <numbers>

#include <gtest/gtest.h>
#include <ostream>

#include "body/shape_factory.hpp"
#include "common/error.hpp"

namespace settle::body {
namespace test_shape_factory {

using std::numbers::pi;

template <class F>
std::string refusal(F&& f) {
  try {
    f();
  } catch (const InputError& e) {
    return e.what();
  }
  return "";
}

ShapeSpec spec_of(const std::string& shape) {
  ShapeSpec spec;
  spec.shape = shape;
  return spec;
}

TEST(ShapeFactory, BuildsEveryShape) {
  ShapeSpec sphere = spec_of("sphere");
  sphere.diameter = 2e-3;
  EXPECT_EQ(make_shape(sphere)->kind(), "sphere");
  EXPECT_NEAR(make_shape(sphere)->volume(), pi / 6 * 8e-9, 1e-22);

  ShapeSpec spheroid = spec_of("spheroid");
  spheroid.diameter = 2.0;
  spheroid.aspect_ratio = 2.5;
  EXPECT_NEAR(make_shape(spheroid)->volume(), 4.0 / 3.0 * pi * 2.5, 1e-13);
  EXPECT_NEAR(make_shape(spheroid)->bounding_box().upper.z(), 2.5, 1e-15);  // symmetry axis = z

  ShapeSpec ellipsoid = spec_of("ellipsoid");
  ellipsoid.semi_axes = std::array<double, 3>{3.0, 2.0, 1.0};
  EXPECT_NEAR(make_shape(ellipsoid)->volume(), 8.0 * pi, 1e-13);

  ShapeSpec cylinder = spec_of("cylinder");
  cylinder.diameter = 2.0;
  cylinder.length = 0.5;
  EXPECT_NEAR(make_shape(cylinder)->volume(), 0.5 * pi, 1e-14);

  ShapeSpec cuboid = spec_of("cuboid");
  cuboid.size = std::array<double, 3>{1.0, 2.0, 3.0};
  EXPECT_NEAR(make_shape(cuboid)->volume(), 6.0, 1e-14);

  ShapeSpec superellipsoid = spec_of("superellipsoid");
  superellipsoid.semi_axes = std::array<double, 3>{1.0, 1.0, 1.0};
  superellipsoid.exponents = std::array<double, 2>{1.0, 1.0};
  EXPECT_NEAR(make_shape(superellipsoid)->volume(), 4.0 / 3.0 * pi, 1e-13);

  ShapeSpec mesh = spec_of("mesh");
  mesh.file = "cube_ascii.stl";  // relative to the base directory
  mesh.scale = 2.0;
  ShapeFactoryOptions options;
  options.base_directory = std::filesystem::path(SETTLE_SOURCE_DIR) / "tests/data";
  EXPECT_NEAR(make_shape(mesh, options)->volume(), 8.0, 1e-14);
}

struct BadSpec {
  const char* label;
  ShapeSpec spec;
  const char* message;
};

// Names the parameter in test listings (instead of a byte dump).
void PrintTo(const BadSpec& b, std::ostream* os) { *os << b.label; }

ShapeSpec with(ShapeSpec spec, void (*edit)(ShapeSpec&)) {
  edit(spec);
  return spec;
}

class ShapeFactoryRefusal : public ::testing::TestWithParam<BadSpec> {};

TEST_P(ShapeFactoryRefusal, NamesTheKey) {
  const std::string message = refusal([] { make_shape(GetParam().spec); });
  EXPECT_NE(message.find(GetParam().message), std::string::npos) << "got: " << message;
}

INSTANTIATE_TEST_SUITE_P(
    Keys, ShapeFactoryRefusal,
    ::testing::Values(
        BadSpec{"unknown_shape", spec_of("blob"), "particle.shape: unknown shape 'blob' (allowed: sphere, spheroid"},
        BadSpec{"missing_diameter", spec_of("sphere"), "particle.diameter: required for shape 'sphere'"},
        BadSpec{"negative_diameter", with(spec_of("sphere"), [](ShapeSpec& s) { s.diameter = -1.0; }),
                "particle.diameter: must be finite and > 0, got -1"},
        BadSpec{"nan_length",
                with(spec_of("cylinder"), [](ShapeSpec& s) { s.diameter = 1.0, s.length = std::nan(""); }),
                "particle.length: must be finite and > 0, got nan"},
        BadSpec{"unused_key",
                with(spec_of("cylinder"), [](ShapeSpec& s) { s.diameter = 1.0, s.length = 1.0, s.aspect_ratio = 2.0; }),
                "particle.aspect_ratio: not used by shape 'cylinder' (it takes particle.diameter, particle.length)"},
        BadSpec{"extreme_aspect",
                with(spec_of("spheroid"), [](ShapeSpec& s) { s.diameter = 1.0, s.aspect_ratio = 1e4; }),
                "particle.aspect_ratio: the ratio of polar to equatorial diameter must lie in [0.001, 1000]"},
        BadSpec{"flat_semi_axes",
                with(spec_of("ellipsoid"),
                     [](ShapeSpec& s) {
                       s.semi_axes = std::array<double, 3>{1.0, 1.0, 1e-5};
                     }),
                "particle.semi_axes: the ratio of the largest to the smallest value must lie in"},
        BadSpec{"zero_size",
                with(spec_of("cuboid"),
                     [](ShapeSpec& s) {
                       s.size = std::array<double, 3>{1.0, 0.0, 1.0};
                     }),
                "particle.size (value 2 of 3): must be finite and > 0, got 0"},
        BadSpec{"exponent_range",
                with(spec_of("superellipsoid"),
                     [](ShapeSpec& s) {
                       s.semi_axes = std::array<double, 3>{1.0, 1.0, 1.0};
                       s.exponents = std::array<double, 2>{1.0, 3.0};
                     }),
                "particle.exponents: e2 must lie in [0.1, 2] (convex superellipsoids), got 3"},
        BadSpec{"missing_exponents",
                with(spec_of("superellipsoid"),
                     [](ShapeSpec& s) {
                       s.semi_axes = std::array<double, 3>{1.0, 1.0, 1.0};
                     }),
                "particle.exponents: required for shape 'superellipsoid'"},
        BadSpec{"missing_file", spec_of("mesh"), "particle.file: required for shape 'mesh'"},
        BadSpec{"bad_scale", with(spec_of("mesh"), [](ShapeSpec& s) { s.file = "x.stl", s.scale = 0.0; }),
                "particle.scale: must be finite and > 0, got 0"},
        BadSpec{"file_not_found", with(spec_of("mesh"), [](ShapeSpec& s) { s.file = "/nonexistent/grain.stl"; }),
                "/nonexistent/grain.stl: no such file"}),
    [](const auto& param_info) { return std::string(param_info.param.label); });

TEST(ShapeFactory, KeyNamesFollowTheCaller) {
  ShapeFactoryOptions options;
  options.key_name = [](std::string_view key) {
    std::string flag = "--" + std::string(key);
    std::replace(flag.begin(), flag.end(), '_', '-');
    return flag;
  };
  ShapeSpec spec = spec_of("spheroid");
  spec.diameter = 1.0;
  spec.aspect_ratio = -2.0;
  EXPECT_EQ(refusal([&] { make_shape(spec, options); }), "--aspect-ratio: must be finite and > 0, got -2");
}

TEST(ShapeFactory, UnusedKeysCanBeAllowed) {
  // A caller that fills every key from schema defaults (e.g. scale = 1) can opt out.
  ShapeSpec spec = spec_of("sphere");
  spec.diameter = 1.0;
  spec.scale = 1.0;
  EXPECT_NE(refusal([&] { make_shape(spec); }).find("particle.scale: not used by shape 'sphere'"), std::string::npos);
  ShapeFactoryOptions lenient;
  lenient.reject_unused_keys = false;
  EXPECT_EQ(make_shape(spec, lenient)->kind(), "sphere");
}

}  // namespace test_shape_factory
}  // namespace settle::body
