// `settle predict`: terminal velocity, Reynolds number and drag coefficient of one particle
// from every empirical correlation of src/analysis/correlations.hpp, each with its validity
// range and a flag when the particle lies outside it. The particle and fluid come from a case
// file ([fluid] and [particle]) or from flags; output is a table, or with --json a list of
// objects (docs/correlations.md).
#include <array>
#include <charconv>
#include <cmath>
#include <filesystem>
#include <iostream>
#include <memory>
#include <optional>
#include <string>
#include <vector>

#include <fmt/core.h>
#include <nlohmann/json.hpp>

#include "analysis/correlations.hpp"
#include "app/commands.hpp"
#include "app/flag_values.hpp"
#include "app/shape_flags.hpp"
#include "app/summary_fields.hpp"
#include "attitude/attitude.hpp"
#include "body/shape_factory.hpp"
#include "common/error.hpp"
#include "common/physical_defaults.hpp"
#include "io/case.hpp"

namespace settle::app {
namespace {

namespace fs = std::filesystem;
using json = nlohmann::ordered_json;  // keys in the order written

// Raw flag values; parsed and validated in run() so that every message names its flag.
struct PredictOptions {
  std::string case_file;
  ShapeFlags shape;
  std::optional<std::string> density, fluid_density, viscosity, gravity, euler;
  std::string orientation = "broadside";
  std::optional<std::string> powers_roundness;
  bool as_json = false;
};

// What the laws need: the particle's descriptors and the fluid.
struct Problem {
  analysis::ParticleDescriptors particle;
  double fluid_density_si = 0.0;
  double dynamic_viscosity_si = 0.0;
  double gravity_si = 0.0;
};

// ------------------------------------------------------------------ parsing

// The flags that describe the particle or fluid, e.g. "--shape, --density" (empty if none).
std::string particle_flags_given(const PredictOptions& o) {
  const std::pair<const char*, bool> flags[] = {{"--density", o.density.has_value()},
                                                {"--fluid-density", o.fluid_density.has_value()},
                                                {"--viscosity", o.viscosity.has_value()},
                                                {"--gravity", o.gravity.has_value()},
                                                {"--euler", o.euler.has_value()}};
  std::string given = shape_flags_given(o.shape);
  for (const auto& [flag, present] : flags) {
    if (present) given += (given.empty() ? "" : ", ") + std::string(flag);
  }
  return given;
}

double required_positive(const std::optional<std::string>& text, const char* flag, const char* what) {
  if (!text) throw InputError(fmt::format("{}: required without a case file ({}, > 0)", flag, what));
  return positive_number(*text, flag);
}

analysis::Orientation parse_orientation(const std::string& text) {
  const auto orientation = analysis::parse_orientation(text);
  if (!orientation) throw InputError(fmt::format("--orientation: expected broadside, initial or mean, got '{}'", text));
  return *orientation;
}

double parse_roundness(const PredictOptions& o) {
  if (!o.powers_roundness) return 6.0;
  const double p = parse_number(*o.powers_roundness, "--powers-roundness");
  if (p < 0.0 || p > 6.0)
    throw InputError(fmt::format("--powers-roundness: must be in [0, 6], got {}", *o.powers_roundness));
  return p;
}

// ------------------------------------------------------------------ the particle

Problem problem_from_flags(const PredictOptions& o, analysis::Orientation orientation, double roundness) {
  const std::unique_ptr<body::Shape> shape = body::make_shape(shape_spec_from_flags(o.shape), flag_shape_options());
  Problem p;
  const double density = required_positive(o.density, "--density", "particle density, kg/m^3");
  p.fluid_density_si = required_positive(o.fluid_density, "--fluid-density", "fluid density, kg/m^3");
  p.dynamic_viscosity_si = required_positive(o.viscosity, "--viscosity", "dynamic viscosity, Pa s");
  p.gravity_si = o.gravity ? positive_number(*o.gravity, "--gravity") : defaults::gravity_si;
  if (density == p.fluid_density_si) {
    throw InputError(
        fmt::format("--density: must differ from --fluid-density ({}), else nothing settles", *o.fluid_density));
  }
  // Gravity points along -z; --euler is the initial attitude (set 1, body to inertial).
  Eigen::Vector3d fall_body = -Eigen::Vector3d::UnitZ();
  if (o.euler) {
    const auto e = parse_list<3>(*o.euler, "--euler");
    fall_body = attitude::Attitude::from_set1(e[0], e[1], e[2]).inertial_to_body() * fall_body;
  }
  p.particle = analysis::describe_particle(*shape, density, orientation, fall_body, roundness);
  return p;
}

Eigen::Vector3d vector3_of(const io::CaseValues& v, std::string_view key) {
  const auto& x = v.reals(key);
  return {x[0], x[1], x[2]};
}

// Only [fluid] and [particle] matter here, so a case without [domain] (not runnable) is fine;
// the schema still checks every key that is present.
Problem problem_from_case(const fs::path& path, analysis::Orientation orientation, double roundness) {
  const io::CaseValues values = io::load_case(path, {});
  try {
    body::ShapeFactoryOptions factory;
    factory.base_directory = fs::absolute(path).parent_path();
    const std::unique_ptr<body::Shape> shape = body::make_shape(io::shape_spec(values), factory);
    Problem p;
    p.fluid_density_si = values.real("fluid.density");
    p.dynamic_viscosity_si = values.real("fluid.dynamic_viscosity");
    const double density = io::particle_density_si(values);
    if (density == p.fluid_density_si) {
      throw InputError(fmt::format("particle.density: must differ from fluid.density ({}), else nothing settles",
                                   p.fluid_density_si));
    }
    const Eigen::Vector3d gravity = vector3_of(values, "fluid.gravity");
    p.gravity_si = gravity.norm();
    if (!(p.gravity_si > 0.0)) throw InputError("fluid.gravity: must be non-zero for a terminal velocity");
    const Eigen::Vector3d euler = vector3_of(values, "particle.euler");
    const Eigen::Vector3d fall_body =
        attitude::Attitude::from_set1(euler[0], euler[1], euler[2]).inertial_to_body() * (gravity / p.gravity_si);
    p.particle = analysis::describe_particle(*shape, density, orientation, fall_body, roundness);
    return p;
  } catch (const InputError& e) {
    const std::string message = e.what();
    if (message.rfind(path.string(), 0) == 0) throw;
    throw InputError(path.string() + ": " + message);
  }
}

// ------------------------------------------------------------------ output

std::string table(const Problem& problem, const std::vector<analysis::LawPrediction>& predictions) {
  const analysis::ParticleDescriptors& d = problem.particle;
  std::string out = fmt::format(
      "{}: d_v = {:.5g} m, rho_p = {:.6g} kg/m^3; fluid rho_f = {:.6g} kg/m^3, mu = {:.4g} Pa s, g = {:.4g} m/s^2\n",
      d.shape_kind, d.equivalent_diameter_si, d.density_si, problem.fluid_density_si, problem.dynamic_viscosity_si,
      problem.gravity_si);
  const Eigen::Vector3d& f = d.fall_direction_body;
  out += d.orientation == analysis::Orientation::mean
             ? std::string("orientation mean (averaged over all orientations)")
             : fmt::format("orientation {} (fall along body ({:.3f}, {:.3f}, {:.3f}))",
                           analysis::orientation_name(d.orientation), f.x(), f.y(), f.z());
  out += fmt::format(
      ": sphericity {:.4g}, crosswise {:.4g}, lengthwise {:.4g}, flatness {:.4g}, elongation {:.4g}, Corey {:.4g}, "
      "Powers roundness {:.3g}\n\n",
      d.sphericity, d.crosswise_sphericity, d.lengthwise_sphericity, d.flatness, d.elongation, d.corey_shape_factor,
      d.powers_roundness);
  out += fmt::format("{:<18} {:>11} {:>11} {:>11}  {:<8}  {}\n", "law", "U (m/s)", "Re", "C_D", "in range",
                     "range / note");
  for (const auto& p : predictions) {
    const auto cell = [&](double v) {
      return p.state.solved ? fmt::format("{:>11.4e}", v) : fmt::format("{:>11}", "-");
    };
    out += fmt::format("{:<18} {} {} {}  {:<8}  {}{}\n", p.law, cell(p.state.terminal_velocity_si),
                       cell(p.state.reynolds), cell(p.state.drag_coefficient), p.in_range ? "yes" : "NO", p.range,
                       p.reason.empty() ? "" : " -- " + p.reason);
  }
  return out;
}

void run(const PredictOptions& o) {
  const analysis::Orientation orientation = parse_orientation(o.orientation);
  const double roundness = parse_roundness(o);
  if (o.euler && orientation != analysis::Orientation::initial) {
    throw InputError(
        fmt::format("--euler: only used with --orientation initial (got --orientation {})", o.orientation));
  }
  Problem problem;
  if (!o.case_file.empty()) {
    if (const std::string flags = particle_flags_given(o); !flags.empty()) {
      throw InputError(flags + ": cannot be combined with a case file (its [fluid] and [particle] tables are used)");
    }
    problem = problem_from_case(o.case_file, orientation, roundness);
  } else {
    problem = problem_from_flags(o, orientation, roundness);
  }
  const std::vector<analysis::LawPrediction> predictions = analysis::predict_terminal_velocities(
      problem.particle, problem.fluid_density_si, problem.dynamic_viscosity_si, problem.gravity_si);
  if (o.as_json) {
    json list = json::array();
    for (const auto& p : predictions) list.push_back(prediction_json(p, orientation));
    std::cout << list.dump(2) << '\n';
  } else {
    std::cout << table(problem, predictions);
  }
}

}  // namespace

void add_predict_command(CLI::App& app) {
  auto options = std::make_shared<PredictOptions>();
  CLI::App* cmd = app.add_subcommand(
      "predict",
      "Terminal velocity and drag coefficient of a particle from empirical correlations (Schiller-Naumann, "
      "Clift-Grace-Weber, Haider-Levenspiel, Ganser, Hoelzer-Sommerfeld, Bagheri-Bonadonna, Dietrich), each solved to "
      "force balance and flagged when the particle is outside its range. The particle and fluid come from a case file "
      "or from flags; SI units.");
  cmd->add_option("case", options->case_file, "case file (TOML) whose [fluid] and [particle] tables are used")
      ->type_name("CASE.toml");
  add_shape_flags(*cmd, options->shape, ", m", "metres");
  cmd->add_option("--density", options->density, "particle density, kg/m^3 (required without a case)")
      ->type_name("RHO_P");
  cmd->add_option("--fluid-density", options->fluid_density, "fluid density, kg/m^3 (required without a case)")
      ->type_name("RHO_F");
  cmd->add_option("--viscosity", options->viscosity, "dynamic viscosity, Pa s (required without a case)")
      ->type_name("MU");
  cmd->add_option("--gravity", options->gravity, "gravitational acceleration, m/s^2 (default 9.81)")->type_name("G");
  cmd->add_option("--orientation", options->orientation,
                  "which side faces the fall, for the crosswise/lengthwise sphericity and Ganser's d_n: broadside "
                  "(default; fall along the thinnest principal axis), initial (the case's euler, or --euler) or mean "
                  "(tumbling: orientation-averaged shadow)")
      ->type_name("broadside|initial|mean");
  cmd->add_option("--euler", options->euler,
                  "without a case, with --orientation initial: initial attitude (set 1 angles psi,theta,gamma in rad, "
                  "body to inertial; gravity along -z)")
      ->type_name("psi,theta,gamma");
  cmd->add_option("--powers-roundness", options->powers_roundness,
                  "Powers roundness for Dietrich's law, 0 (angular) to 6 (perfectly round); default 6 (smooth bodies)")
      ->type_name("P");
  cmd->add_flag("--json", options->as_json, "print a JSON list with one object per law instead of a table");
  cmd->callback([options] { run(*options); });
}

}  // namespace settle::app
