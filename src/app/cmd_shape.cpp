// `settle shape`: mass properties, shape factors and (optionally) surface markers of one
// particle shape, as JSON on stdout. The shape comes from flags or from the [particle] table
// of a case file. Numbers are in the input's units (SI for case files); the inertia is about
// the centroid, in the axes of the input frame, for the given density.
#include <algorithm>
#include <filesystem>
#include <iostream>
#include <memory>
#include <optional>
#include <string>

#include <nlohmann/json.hpp>

#include "app/commands.hpp"
#include "app/flag_values.hpp"
#include "app/output_values.hpp"
#include "app/shape_flags.hpp"
#include "body/shape_factors.hpp"
#include "body/shape_factory.hpp"
#include "body/surface_markers.hpp"
#include "common/error.hpp"
#include "io/case.hpp"

namespace settle::app {
namespace {

// Keys in the order written (the contract keys first), not alphabetical.
using json = nlohmann::ordered_json;

// Raw flag values; parsed and validated by run() so that every message names its flag.
struct ShapeOptions {
  std::string case_file;
  ShapeFlags shape;
  std::optional<std::string> density, marker_spacing, flow_direction;
};

// ------------------------------------------------------------------ case file
// The shape and, when the case gives one, the density of a case file's [particle] table, read by
// the case reader every command uses (the schema checks every key that is present; a case need not
// be runnable here).
struct CaseParticle {
  std::unique_ptr<body::Shape> shape;
  std::optional<double> density;
};

bool has_particle_table(const io::CaseValues& values) {
  const auto& keys = values.schema().keys();
  return std::any_of(keys.begin(), keys.end(), [&](const io::KeySpec& key) {
    return key.path.rfind("particle.", 0) == 0 && values.given(key.path);
  });
}

CaseParticle read_case_particle(const std::filesystem::path& path) {
  const io::CaseValues values = io::load_case(path, {});
  if (!has_particle_table(values)) throw InputError(path.string() + ": no [particle] table");
  body::ShapeFactoryOptions options;
  options.base_directory = path.parent_path();
  CaseParticle particle;
  particle.shape = body::make_shape(io::shape_spec(values), options);
  if (values.given("particle.density")) particle.density = values.real("particle.density");
  return particle;
}

// ------------------------------------------------------------------ output
json matrix_json(const Eigen::Matrix3d& m) {
  return json::array(
      {vector_json(m.row(0).transpose()), vector_json(m.row(1).transpose()), vector_json(m.row(2).transpose())});
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
    if (const std::string flags = shape_flags_given(o.shape); !flags.empty()) {
      throw InputError(flags + ": cannot be combined with a case file (its [particle] table describes the shape)");
    }
    const std::filesystem::path path(o.case_file);
    // Messages about the case's keys start with the file's name.
    try {
      CaseParticle particle = read_case_particle(path);
      shape = std::move(particle.shape);
      density = particle.density;
    } catch (const InputError& e) {
      const std::string message = e.what();
      if (message.rfind(path.string(), 0) == 0) throw;
      throw InputError(path.string() + ": " + message);
    }
  } else {
    shape = body::make_shape(shape_spec_from_flags(o.shape), flag_shape_options());
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
  add_shape_flags(*cmd, options->shape, "", "output units");
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
