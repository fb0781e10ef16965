#include "app/shape_flags.hpp"

#include <utility>

#include <fmt/core.h>

#include "app/flag_values.hpp"
#include "common/error.hpp"

namespace settle::app {
namespace {

// The command-line flag of each shape key, for the shape factory's messages.
std::string flag_of(std::string_view key) {
  if (key == "file") return "--mesh";
  std::string flag = "--" + std::string(key);
  for (char& c : flag) c = c == '_' ? '-' : c;
  return flag;
}

}  // namespace

void add_shape_flags(CLI::App& command, ShapeFlags& flags, std::string_view length_unit,
                     std::string_view scale_target) {
  const auto help = [&](std::string_view text) { return fmt::format("{}{}", text, length_unit); };
  command
      .add_option("--shape", flags.shape, "sphere | spheroid | ellipsoid | cylinder | cuboid | superellipsoid | mesh")
      ->type_name("NAME");
  command.add_option("--diameter", flags.diameter, help("sphere, spheroid (equatorial) and cylinder diameter"))
      ->type_name("D");
  command.add_option("--aspect-ratio", flags.aspect_ratio, "spheroid: polar / equatorial diameter (symmetry axis z)")
      ->type_name("A");
  command.add_option("--semi-axes", flags.semi_axes, help("ellipsoid, superellipsoid: semi-axes along body x,y,z"))
      ->type_name("a,b,c");
  command.add_option("--length", flags.length, help("cylinder length along body z"))->type_name("L");
  command.add_option("--size", flags.size, help("cuboid edge lengths along body x,y,z"))->type_name("a,b,c");
  command
      .add_option("--exponents", flags.exponents,
                  "superellipsoid exponents in [0.1, 2], Barr's convention: "
                  "(|x/a|^(2/e2) + |y/b|^(2/e2))^(e2/e1) + |z/c|^(2/e1) <= 1")
      ->type_name("e1,e2");
  command.add_option("--mesh", flags.mesh, "watertight STL file (ASCII or binary); implies --shape mesh")
      ->type_name("FILE");
  command
      .add_option("--scale", flags.scale, fmt::format("mesh: factor from file units to {} (default 1)", scale_target))
      ->type_name("S");
}

std::string shape_flags_given(const ShapeFlags& o) {
  const std::pair<const char*, bool> flags[] = {{"--shape", o.shape.has_value()},
                                                {"--diameter", o.diameter.has_value()},
                                                {"--aspect-ratio", o.aspect_ratio.has_value()},
                                                {"--semi-axes", o.semi_axes.has_value()},
                                                {"--length", o.length.has_value()},
                                                {"--size", o.size.has_value()},
                                                {"--exponents", o.exponents.has_value()},
                                                {"--mesh", o.mesh.has_value()},
                                                {"--scale", o.scale.has_value()}};
  std::string given;
  for (const auto& [flag, present] : flags) {
    if (present) given += (given.empty() ? "" : ", ") + std::string(flag);
  }
  return given;
}

body::ShapeSpec shape_spec_from_flags(const ShapeFlags& o) {
  body::ShapeSpec spec;
  if (o.mesh) {
    if (o.shape && *o.shape != "mesh")
      throw InputError(fmt::format("--mesh: cannot be used with --shape {}", *o.shape));
    spec.shape = "mesh";
    spec.file = *o.mesh;
  } else if (o.shape) {
    spec.shape = *o.shape;
  } else {
    throw InputError(
        "--shape: give a shape (sphere, spheroid, ellipsoid, cylinder, cuboid, superellipsoid) or --mesh FILE");
  }
  if (o.diameter) spec.diameter = parse_number(*o.diameter, "--diameter");
  if (o.aspect_ratio) spec.aspect_ratio = parse_number(*o.aspect_ratio, "--aspect-ratio");
  if (o.length) spec.length = parse_number(*o.length, "--length");
  if (o.scale) spec.scale = parse_number(*o.scale, "--scale");
  if (o.semi_axes) spec.semi_axes = parse_list<3>(*o.semi_axes, "--semi-axes");
  if (o.size) spec.size = parse_list<3>(*o.size, "--size");
  if (o.exponents) spec.exponents = parse_list<2>(*o.exponents, "--exponents");
  return spec;
}

body::ShapeFactoryOptions flag_shape_options() {
  body::ShapeFactoryOptions options;
  options.key_name = flag_of;
  return options;
}

}  // namespace settle::app
