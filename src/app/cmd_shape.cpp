// `settle shape`: mass properties, shape factors and (optionally) surface markers of one
// particle shape, as JSON on stdout. The shape comes from flags or from the [particle] table
// of a case file. Numbers are in the input's units (SI for case files); the inertia is about
// the centroid, in the axes of the input frame, for the given density.
#include <charconv>
#include <cmath>
#include <filesystem>
#include <iostream>
#include <memory>
#include <optional>
#include <set>
#include <string>
#include <vector>

#include <fmt/core.h>
#include <nlohmann/json.hpp>
#include <toml++/toml.h>

#include "app/commands.hpp"
#include "body/shape_factors.hpp"
#include "body/shape_factory.hpp"
#include "body/surface_markers.hpp"
#include "common/error.hpp"

namespace settle::app {
namespace {

// Keys in the order written (the contract keys first), not alphabetical.
using json = nlohmann::ordered_json;

// Raw flag values; parsed and validated by run() so that every message names its flag.
struct ShapeOptions {
  std::string case_file;
  std::optional<std::string> shape, diameter, aspect_ratio, semi_axes, length, size, exponents, mesh, scale;
  std::optional<std::string> density, marker_spacing, flow_direction;
};

// The command-line flag of each shape key, for error messages.
std::string flag_of(std::string_view key) {
  if (key == "file") return "--mesh";
  std::string flag = "--" + std::string(key);
  for (char& c : flag) c = c == '_' ? '-' : c;
  return flag;
}

double parse_number(const std::string& text, const std::string& flag) {
  double value = 0.0;
  const char* end = text.data() + text.size();
  const auto [stop, ec] = std::from_chars(text.data(), end, value);
  if (ec != std::errc() || stop != end || !std::isfinite(value)) {
    throw InputError(fmt::format("{}: expected a finite number, got '{}'", flag, text));
  }
  return value;
}

template <std::size_t N>
std::array<double, N> parse_list(const std::string& text, const std::string& flag) {
  std::array<double, N> values{};
  std::size_t begin = 0, count = 0;
  while (begin <= text.size()) {
    const std::size_t comma = std::min(text.find(',', begin), text.size());
    if (count == N) throw InputError(fmt::format("{}: expected {} comma-separated numbers, got '{}'", flag, N, text));
    values[count++] = parse_number(text.substr(begin, comma - begin), flag);
    begin = comma + 1;
  }
  if (count != N) throw InputError(fmt::format("{}: expected {} comma-separated numbers, got '{}'", flag, N, text));
  return values;
}

double positive_number(const std::string& text, const std::string& flag) {
  const double value = parse_number(text, flag);
  if (!(value > 0.0)) throw InputError(fmt::format("{}: must be > 0, got {}", flag, text));
  return value;
}

// ------------------------------------------------------------------ case file
// Keys of [particle] (docs/architecture.md, "Case file"); those that do not describe the shape are checked
// for their type only.
const std::set<std::string, std::less<>> kVectorKeys{"towing_velocity", "position", "euler", "velocity", "angular_velocity"};

std::string case_key(std::string_view key) { return "particle." + std::string(key); }

std::string type_name(const toml::node& node) {
  switch (node.type()) {
    case toml::node_type::string: return "a string";
    case toml::node_type::integer: return "an integer";
    case toml::node_type::floating_point: return "a number";
    case toml::node_type::boolean: return "a boolean";
    case toml::node_type::array: return "an array";
    case toml::node_type::table: return "a table";
    default: return "a date or time";
  }
}

double toml_number(const toml::node& node, std::string_view key) {
  if (!node.is_number()) throw InputError(fmt::format("{}: expected a number, got {}", case_key(key), type_name(node)));
  return *node.value<double>();
}

template <std::size_t N>
std::array<double, N> toml_numbers(const toml::node& node, std::string_view key) {
  const toml::array* array = node.as_array();
  if (!array || array->size() != N) {
    throw InputError(fmt::format("{}: expected an array of {} numbers, got {}", case_key(key), N,
                                 array ? fmt::format("{} values", array->size()) : type_name(node)));
  }
  std::array<double, N> values{};
  for (std::size_t i = 0; i < N; ++i) values[i] = toml_number(*array->get(i), key);
  return values;
}

std::string toml_string(const toml::node& node, std::string_view key) {
  if (!node.is_string()) throw InputError(fmt::format("{}: expected a string, got {}", case_key(key), type_name(node)));
  return *node.value<std::string>();
}

struct CaseParticle {
  body::ShapeSpec spec;
  std::optional<double> density;
};

CaseParticle read_particle_table(const toml::table& particle);

CaseParticle read_case_particle(const std::filesystem::path& path) {
  toml::table root;
  try {
    root = toml::parse_file(path.string());
  } catch (const toml::parse_error& e) {
    const auto& where = e.source().begin;
    throw InputError(fmt::format("{}:{}:{}: {}", path.string(), where.line, where.column, e.description()));
  }
  const toml::table* particle = root["particle"].as_table();
  if (!particle) throw InputError(path.string() + ": no [particle] table");
  return read_particle_table(*particle);
}

CaseParticle read_particle_table(const toml::table& particle) {
  CaseParticle result;
  body::ShapeSpec& spec = result.spec;
  spec.shape = "sphere";  // the schema's default
  for (const auto& [key_node, node] : particle) {
    const std::string_view key = key_node.str();
    if (key == "shape") spec.shape = toml_string(node, key);
    else if (key == "diameter") spec.diameter = toml_number(node, key);
    else if (key == "aspect_ratio") spec.aspect_ratio = toml_number(node, key);
    else if (key == "length") spec.length = toml_number(node, key);
    else if (key == "scale") spec.scale = toml_number(node, key);
    else if (key == "semi_axes") spec.semi_axes = toml_numbers<3>(node, key);
    else if (key == "size") spec.size = toml_numbers<3>(node, key);
    else if (key == "exponents") spec.exponents = toml_numbers<2>(node, key);
    else if (key == "file") spec.file = toml_string(node, key);
    else if (key == "density") result.density = toml_number(node, key);
    else if (key == "motion") toml_string(node, key);
    else if (kVectorKeys.contains(key)) toml_numbers<3>(node, key);
    else throw InputError(fmt::format("{}: unknown key", case_key(key)));
  }
  return result;
}

// ------------------------------------------------------------------ flags
// The shape flags given, e.g. "--shape, --diameter" (empty if none).
std::string shape_flags_given(const ShapeOptions& o) {
  const std::pair<const char*, bool> flags[] = {
      {"--shape", o.shape.has_value()},         {"--diameter", o.diameter.has_value()},
      {"--aspect-ratio", o.aspect_ratio.has_value()}, {"--semi-axes", o.semi_axes.has_value()},
      {"--length", o.length.has_value()},       {"--size", o.size.has_value()},
      {"--exponents", o.exponents.has_value()}, {"--mesh", o.mesh.has_value()},
      {"--scale", o.scale.has_value()}};
  std::string given;
  for (const auto& [flag, present] : flags) {
    if (present) given += (given.empty() ? "" : ", ") + std::string(flag);
  }
  return given;
}

body::ShapeSpec spec_from_flags(const ShapeOptions& o) {
  body::ShapeSpec spec;
  if (o.mesh) {
    if (o.shape && *o.shape != "mesh") throw InputError(fmt::format("--mesh: cannot be used with --shape {}", *o.shape));
    spec.shape = "mesh";
    spec.file = *o.mesh;
  } else if (o.shape) {
    spec.shape = *o.shape;
  } else {
    throw InputError("--shape: give a shape (sphere, spheroid, ellipsoid, cylinder, cuboid, superellipsoid) or --mesh FILE");
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

// ------------------------------------------------------------------ output
json vector_json(const Eigen::Vector3d& v) { return json::array({v.x(), v.y(), v.z()}); }

json matrix_json(const Eigen::Matrix3d& m) {
  return json::array({vector_json(m.row(0).transpose()), vector_json(m.row(1).transpose()), vector_json(m.row(2).transpose())});
}

json markers_json(const body::Shape& shape, double spacing) {
  const body::SurfaceMarkers markers = shape.surface_markers(spacing);
  const std::vector<double> nearest = body::nearest_marker_distances(markers);
  const double area = markers.total_area();
  return {{"spacing", spacing},
          {"count", markers.size()},
          {"area_sum", area},
          {"area_sum_relative_error", area / shape.surface_area() - 1.0},
          {"mean_area_over_spacing_squared", area / static_cast<double>(markers.size()) / (spacing * spacing)},
          {"nearest_neighbour_max_over_spacing", *std::max_element(nearest.begin(), nearest.end()) / spacing},
          {"nearest_neighbour_min_over_spacing", *std::min_element(nearest.begin(), nearest.end()) / spacing}};
}

json report(const body::Shape& shape, double density, const Eigen::Vector3d& flow, std::optional<double> spacing) {
  const body::MassProperties mass = shape.mass_properties(density);
  const body::ShapeFactors factors = body::compute_shape_factors(shape, flow);
  const Eigen::Quaterniond q = mass.rotation_body_from_principal();
  const body::Aabb box = shape.bounding_box();
  json out = {
      {"shape", shape.kind()},
      {"density", density},
      {"volume", factors.volume},
      {"mass", mass.mass},
      {"surface_area", factors.surface_area},
      {"equivalent_diameter", factors.equivalent_diameter},
      {"centroid", vector_json(mass.centroid)},
      {"inertia", matrix_json(mass.inertia)},
      {"principal_moments", vector_json(mass.principal.moments)},
      {"principal_axes", json::array({vector_json(mass.principal.axes.col(0)), vector_json(mass.principal.axes.col(1)),
                                      vector_json(mass.principal.axes.col(2))})},
      {"rotation_body_from_principal_wxyz", json::array({q.w(), q.x(), q.y(), q.z()})},
      {"sphericity", factors.sphericity},
      {"flow_direction", vector_json(factors.flow_direction)},
      {"crosswise_sphericity", factors.crosswise_sphericity},
      {"lengthwise_sphericity", factors.lengthwise_sphericity},
      {"projected_area_along_flow", factors.projected_area_along_flow},
      {"mean_projected_area_across_flow", factors.mean_projected_area_across_flow},
      {"principal_extents", vector_json(factors.principal_extents)},
      {"corey_shape_factor", factors.corey_shape_factor},
      {"flatness", factors.flatness},
      {"elongation", factors.elongation},
      {"projected_area_z", shape.projected_area(Eigen::Vector3d::UnitZ())},
      {"projected_area_x", shape.projected_area(Eigen::Vector3d::UnitX())},
      {"projected_area_y", shape.projected_area(Eigen::Vector3d::UnitY())},
      {"bounding_radius", shape.bounding_radius()},
      {"bounding_box_body", {{"lower", vector_json(box.lower)}, {"upper", vector_json(box.upper)}}},
      {"notes", shape.notes()},
  };
  if (spacing) out["markers"] = markers_json(shape, *spacing);
  return out;
}

void run(const ShapeOptions& o) {
  std::unique_ptr<body::Shape> shape;
  std::optional<double> density;
  if (!o.case_file.empty()) {
    if (const std::string flags = shape_flags_given(o); !flags.empty()) {
      throw InputError(flags + ": cannot be combined with a case file (its [particle] table describes the shape)");
    }
    const std::filesystem::path path(o.case_file);
    // Messages about the case's keys start with the file's name.
    try {
      const CaseParticle particle = read_case_particle(path);
      body::ShapeFactoryOptions options;
      options.base_directory = path.parent_path();
      shape = body::make_shape(particle.spec, options);
      density = particle.density;
      if (density && !(*density > 0.0 && std::isfinite(*density))) {
        throw InputError(fmt::format("particle.density: must be finite and > 0, got {}", *density));
      }
    } catch (const InputError& e) {
      const std::string message = e.what();
      if (message.rfind(path.string(), 0) == 0) throw;
      throw InputError(path.string() + ": " + message);
    }
  } else {
    body::ShapeFactoryOptions options;
    options.key_name = flag_of;
    shape = body::make_shape(spec_from_flags(o), options);
  }
  if (o.density) density = positive_number(*o.density, "--density");
  Eigen::Vector3d flow = Eigen::Vector3d::UnitZ();
  if (o.flow_direction) {
    const auto f = parse_list<3>(*o.flow_direction, "--flow-direction");
    flow = body::unit_direction(Eigen::Vector3d(f[0], f[1], f[2]), "--flow-direction");
  }
  std::optional<double> spacing;
  if (o.marker_spacing) {
    spacing = positive_number(*o.marker_spacing, "--marker-spacing");
    body::validate_marker_spacing(*spacing, shape->surface_area(), "--marker-spacing");
  }
  std::cout << report(*shape, density.value_or(1.0), flow, spacing).dump(2) << '\n';
}

}  // namespace

void add_shape_command(CLI::App& app) {
  auto options = std::make_shared<ShapeOptions>();
  CLI::App* cmd = app.add_subcommand(
      "shape",
      "Mass properties, shape factors and surface markers of a particle shape, as JSON. The shape comes from a case "
      "file's [particle] table or from the flags; lengths in any unit (SI in cases), inertia about the centroid in the "
      "input's axes.");
  cmd->add_option("case", options->case_file, "case file (TOML) whose [particle] table describes the shape")
      ->type_name("CASE.toml");
  cmd->add_option("--shape", options->shape, "sphere | spheroid | ellipsoid | cylinder | cuboid | superellipsoid | mesh")
      ->type_name("NAME");
  cmd->add_option("--diameter", options->diameter, "sphere, spheroid (equatorial) and cylinder diameter")->type_name("D");
  cmd->add_option("--aspect-ratio", options->aspect_ratio, "spheroid: polar / equatorial diameter (symmetry axis z)")
      ->type_name("A");
  cmd->add_option("--semi-axes", options->semi_axes, "ellipsoid, superellipsoid: semi-axes along body x,y,z")
      ->type_name("a,b,c");
  cmd->add_option("--length", options->length, "cylinder length along body z")->type_name("L");
  cmd->add_option("--size", options->size, "cuboid edge lengths along body x,y,z")->type_name("a,b,c");
  cmd->add_option("--exponents", options->exponents,
                  "superellipsoid exponents in [0.1, 2], Barr's convention: "
                  "(|x/a|^(2/e2) + |y/b|^(2/e2))^(e2/e1) + |z/c|^(2/e1) <= 1")
      ->type_name("e1,e2");
  cmd->add_option("--mesh", options->mesh, "watertight STL file (ASCII or binary); implies --shape mesh")
      ->type_name("FILE");
  cmd->add_option("--scale", options->scale, "mesh: factor from file units to output units (default 1)")->type_name("S");
  cmd->add_option("--density", options->density, "density for mass and inertia (default: the case's, else 1)")
      ->type_name("RHO");
  cmd->add_option("--marker-spacing", options->marker_spacing,
                  "also build surface markers of this nominal spacing and report their count and area sum")
      ->type_name("H");
  cmd->add_option("--flow-direction", options->flow_direction,
                  "flow direction in the body frame, for the crosswise and lengthwise sphericities (default 0,0,1)")
      ->type_name("x,y,z");
  cmd->callback([options] { run(*options); });
}

}  // namespace settle::app
