#include "io/case.hpp"

#include <array>
#include <filesystem>
#include <fstream>
#include <memory>
#include <span>
#include <sstream>

#include <fmt/core.h>

#include "body/shape_factory.hpp"
#include "common/error.hpp"
#include "io/case_schema.hpp"
#include "io/fluid_presets.hpp"
#include "lbm/config.hpp"

namespace settle::io {
namespace {

// Water at 20 C, a prolate spheroid (aspect ratio 2, d_eq = 1.26 mm, density ratio 1.1,
// Galileo number about 45) released tilted by 0.5 rad; 8 cells per equivalent diameter in a
// 8 x 8 x 12 d_eq window that follows it (sides 4 d_eq from the axis: under 1% of drag, docs/
// validation.md, "How large a window"). It runs its whole 2 s
// rather than stopping at the terminal state: that is detected on the velocity, at about 0.5 s,
// while the spheroid still swings about its broadside attitude for another half second
// (docs/analysis.md, "Averaging window"). The fluid's density and
// viscosity are the schema defaults, left unwritten so that
// --set fluid.preset=... applies to the default case too (written values would override it).
constexpr std::string_view kDefaultCase = R"toml(# settle's built-in default case (settle run without a case file)
[fluid]
gravity = [0.0, 0.0, -9.81]

[particle]
shape = "spheroid"
diameter = 1.0e-3
aspect_ratio = 2.0
density = 1100.0
motion = "free"
position = [5.04e-3, 5.04e-3, 7.56e-3]
euler = [0.0, 0.5, 0.0]

[domain]
size = [10.08e-3, 10.08e-3, 15.12e-3]
walls = { x = "no-slip", y = "no-slip", z = "no-slip" }
follow_particle = true

[numerics]
cells_per_diameter = 8

[run]
end_time = 2.0
stop_at_terminal = false
output_interval = 0.005
)toml";

// True when the case sets `key` to a value other than its schema default.
bool set_away_from_default(const CaseValues& v, std::string_view key) {
  const KeySpec* spec = v.schema().find(key);
  return v.has(key) && (!spec->default_value || v.value(key) != *spec->default_value);
}

// Keys that one coupling reads and the other ignores: set away from their default for the other,
// they change nothing, which a case written before the default coupling changed would not show.
// (A resolved case writes every key at its default: those are not reported.)
std::vector<std::string> coupling_key_warnings(const CaseValues& v) {
  static constexpr std::array<std::string_view, 4> kImmersedBoundaryKeys{
      "numerics.delta_kernel", "numerics.forcing_iterations", "numerics.marker_retraction",
      "numerics.interior_markers"};
  static constexpr std::array<std::string_view, 2> kMomentumExchangeKeys{"numerics.wall_rule",
                                                                         "numerics.covered_cell_torque"};
  const auto kind = coupling::parse_coupling(v.string("numerics.coupling"), "numerics.coupling");
  const bool immersed = kind == coupling::CouplingKind::immersed_boundary;
  const auto other = immersed ? coupling::CouplingKind::momentum_exchange : coupling::CouplingKind::immersed_boundary;
  const std::span<const std::string_view> ignored = immersed ? std::span<const std::string_view>(kMomentumExchangeKeys)
                                                             : std::span<const std::string_view>(kImmersedBoundaryKeys);
  std::vector<std::string> warnings;
  for (std::string_view key : ignored)
    if (set_away_from_default(v, key))
      warnings.push_back(
          fmt::format("{}: read only with numerics.coupling = \"{}\"; this case couples by {}, so it has "
                      "no effect",
                      key, coupling::to_string(other), coupling::to_string(kind)));
  return warnings;
}

// numerics.trt_magic set away from its default with another collision operator changes nothing, nor
// numerics.smagorinsky_constant without the Smagorinsky model.
std::vector<std::string> collision_key_warnings(const CaseValues& v) {
  std::vector<std::string> warnings;
  if (set_away_from_default(v, "numerics.trt_magic") && v.string("numerics.collision") != "trt")
    warnings.push_back(
        fmt::format("numerics.trt_magic: read only with numerics.collision = \"trt\"; this case uses \"{}\", "
                    "so it has no effect",
                    v.string("numerics.collision")));
  if (set_away_from_default(v, "numerics.smagorinsky_constant") && v.string("numerics.subgrid_model") == "none")
    warnings.push_back(
        "numerics.smagorinsky_constant: read only with numerics.subgrid_model = \"smagorinsky\" or \"auto\"; this "
        "case uses \"none\", so it has no effect");
  return warnings;
}

// Cases are kilobytes; 10 MB of comments were read in 0.25 s (27 MB of memory), and the bound
// leaves room for such files while keeping a stream without end from exhausting the memory.
constexpr std::size_t kMaxCaseFileBytes = std::size_t{64} << 20;

}  // namespace

std::string read_toml_file(const std::filesystem::path& path, std::string_view what) {
  std::error_code error;
  const auto status = std::filesystem::status(path, error);
  if (!std::filesystem::exists(status)) throw InputError(fmt::format("{}: no such {}", path.string(), what));
  // An ifstream opens a directory without complaint and reads nothing, which would silently
  // run the defaults.
  if (std::filesystem::is_directory(status))
    throw InputError(fmt::format("{}: is a directory, not a {} (TOML)", path.string(), what));
  std::ifstream in(path, std::ios::binary);
  if (!in) throw InputError(fmt::format("{}: cannot open the {} (permission?)", path.string(), what));
  // Read in pieces up to a bound: /dev/zero (or any endless stream) used to be read forever, the
  // memory growing by 250 MB/s. A pipe (/dev/stdin) is still read, up to the bound.
  std::string text;
  std::array<char, 1 << 16> buffer{};
  while (in.read(buffer.data(), buffer.size()) || in.gcount() > 0) {
    text.append(buffer.data(), static_cast<std::size_t>(in.gcount()));
    if (text.size() > kMaxCaseFileBytes)
      throw InputError(fmt::format("{}: more than {} MiB, not a {} (a {} is a few kilobytes of TOML)", path.string(),
                                   kMaxCaseFileBytes >> 20, what, what));
  }
  if (in.bad()) throw InputError(fmt::format("{}: could not read the {}", path.string(), what));
  return text;
}

namespace {

// The mesh reader names the file it read, not the case key; a user fixing the case needs both.
std::unique_ptr<body::Shape> shape_of(const CaseValues& v, const body::ShapeSpec& spec,
                                      const body::ShapeFactoryOptions& options) {
  try {
    return body::make_shape(spec, options);
  } catch (const InputError& e) {
    const std::string message = e.what();
    if (spec.shape != "mesh" || message.rfind("particle.", 0) == 0) throw;
    throw InputError(fmt::format("particle.file = {}: {}", to_toml(v.value("particle.file")), message));
  }
}

Eigen::Vector3d vector3(const CaseValues& v, std::string_view key) {
  const auto& x = v.reals(key);
  return {x[0], x[1], x[2]};
}

template <std::size_t N>
std::array<double, N> array_of(const CaseValues& v, std::string_view key) {
  std::array<double, N> a{};
  const auto& x = v.reals(key);
  for (std::size_t i = 0; i < N; ++i) a[i] = x[i];
  return a;
}

lbm::Boundary wall(const CaseValues& v, std::string_view key) {
  const std::string& name = v.string(key);
  if (name == "periodic") return lbm::Boundary::periodic;
  if (name == "free-slip") return lbm::Boundary::free_slip;
  return lbm::Boundary::no_slip;
}

}  // namespace

body::MotionKind motion_kind(const std::string& name) {
  if (name == "towed") return body::MotionKind::towed;
  if (name == "fixed") return body::MotionKind::fixed;
  return body::MotionKind::free;
}

body::ShapeSpec shape_spec(const CaseValues& v) {
  body::ShapeSpec spec;
  spec.shape = v.string("particle.shape");
  if (v.has("particle.diameter")) spec.diameter = v.real("particle.diameter");
  if (v.has("particle.aspect_ratio")) spec.aspect_ratio = v.real("particle.aspect_ratio");
  if (v.has("particle.semi_axes")) spec.semi_axes = array_of<3>(v, "particle.semi_axes");
  if (v.has("particle.exponents")) spec.exponents = array_of<2>(v, "particle.exponents");
  if (v.has("particle.length")) spec.length = v.real("particle.length");
  if (v.has("particle.size")) spec.size = array_of<3>(v, "particle.size");
  if (v.has("particle.file")) spec.file = v.string("particle.file");
  if (v.has("particle.scale")) spec.scale = v.real("particle.scale");
  return spec;
}

CaseValues load_case(const std::filesystem::path& path, const std::vector<std::string>& overrides) {
  CaseValues values = path.empty() ? parse_case(case_schema(), kDefaultCase, "built-in default case")
                                   : parse_case(case_schema(), read_toml_file(path, "case file"), path.string());
  for (const std::string& assignment : overrides) apply_override(values, assignment);
  // After the overrides: --set may choose the preset, its temperature or an explicit value.
  apply_fluid_preset(values);
  return values;
}

CaseValues load_case_text(std::string_view toml_text, std::string_view origin) {
  CaseValues values = parse_case(case_schema(), toml_text, origin);
  apply_fluid_preset(values);
  return values;
}

namespace {

// domain.inflow, domain.inflow_velocity and domain.outflow: each open face replaces the walls of
// its axis on that face, so that axis must not be periodic.
void read_open_faces(const CaseValues& v, coupling::SimulationSetup& s) {
  const auto face = [&](const char* key) -> std::optional<lbm::Face> {
    const std::string name = v.string(key);
    if (name == "none") return std::nullopt;
    const lbm::Face f = lbm::parse_face(name, key);
    if (s.boundaries[static_cast<std::size_t>(f.axis)] == lbm::Boundary::periodic)
      throw InputError(
          fmt::format("{}: face {} lies on an axis whose domain.walls.{} is \"periodic\"; an inlet or outlet "
                      "needs walls on its axis (\"no-slip\" or \"free-slip\")",
                      key, name, "xyz"[f.axis]));
    return f;
  };
  s.inflow = face("domain.inflow");
  s.outflow = face("domain.outflow");
  if (s.inflow && s.outflow && *s.inflow == *s.outflow)
    throw InputError("domain.outflow: the same face as domain.inflow; choose another face");
  if (s.inflow.has_value() != v.has("domain.inflow_velocity"))
    throw InputError(s.inflow ? "domain.inflow_velocity: required with domain.inflow (m/s, e.g. [0, 0, 0.05])"
                              : "domain.inflow_velocity: only with domain.inflow (the face the stream enters by)");
  if (s.inflow) s.inflow_velocity_si = vector3(v, "domain.inflow_velocity");
}

// particle.lock_rotation: a free body that cannot turn; it starts and stays without spin.
void read_rotation_lock(const CaseValues& v, coupling::SimulationSetup& s) {
  s.rotation_locked = v.boolean("particle.lock_rotation");
  if (!s.rotation_locked) return;
  if (s.motion != body::MotionKind::free)
    throw InputError(
        "particle.lock_rotation: only for particle.motion = \"free\" (a towed or fixed body's rotation is "
        "prescribed); remove it or set motion = \"free\"");
  const Eigen::Vector3d omega = s.initial.angular_velocity_b_si;
  if (!omega.isZero(0.0))
    throw InputError(fmt::format(
        "particle.lock_rotation: a body with its rotation locked cannot start spinning (particle.angular_velocity "
        "= [{:g}, {:g}, {:g}] rad/s); set particle.angular_velocity = [0, 0, 0] or lock_rotation = false",
        omega.x(), omega.y(), omega.z()));
}

}  // namespace

coupling::SimulationSetup simulation_setup(const CaseValues& v, const std::filesystem::path& base_directory,
                                           std::string name) {
  coupling::SimulationSetup s;
  s.name = std::move(name);
  body::ShapeFactoryOptions shape_options;
  shape_options.base_directory = base_directory;
  s.shape = std::shared_ptr<const body::Shape>(shape_of(v, shape_spec(v), shape_options));
  s.particle_density_si = particle_density_si(v);
  s.motion = motion_kind(v.string("particle.motion"));

  s.fluid_density_si = v.real("fluid.density");
  s.dynamic_viscosity_si = v.real("fluid.dynamic_viscosity");
  s.gravity_si = vector3(v, "fluid.gravity");
  s.body_force_si = vector3(v, "fluid.body_force");

  if (!v.has("domain.size"))
    throw InputError("domain.size: required (extent of the domain in m, e.g. [0.04, 0.04, 0.12])");
  s.domain_size_si = vector3(v, "domain.size");
  s.boundaries = {wall(v, "domain.walls.x"), wall(v, "domain.walls.y"), wall(v, "domain.walls.z")};
  read_open_faces(v, s);
  s.follow_particle = v.boolean("domain.follow_particle");

  s.initial.position_si =
      v.has("particle.position") ? vector3(v, "particle.position") : Eigen::Vector3d(0.5 * s.domain_size_si);
  const Eigen::Vector3d euler = vector3(v, "particle.euler");
  s.initial.attitude =
      attitude::Attitude::from_matrix(attitude::Attitude::from_set1(euler[0], euler[1], euler[2]).body_to_inertial());
  s.initial.velocity_si = vector3(v, "particle.velocity");
  s.initial.angular_velocity_b_si = vector3(v, "particle.angular_velocity");
  if (s.motion == body::MotionKind::towed) {
    if (!v.has("particle.towing_velocity"))
      throw InputError("particle.towing_velocity: required when particle.motion = \"towed\" (m/s, e.g. [0, 0, -0.05])");
    s.initial.velocity_si = vector3(v, "particle.towing_velocity");
  } else if (v.has("particle.towing_velocity")) {
    throw InputError(
        "particle.towing_velocity: only for particle.motion = \"towed\"; remove it or set motion = \"towed\"");
  }
  s.release_time_si = v.real("particle.release_time");
  if (s.release_time_si > 0.0 && s.motion != body::MotionKind::free)
    throw InputError(
        "particle.release_time: only for particle.motion = \"free\" (a towed or fixed body is never "
        "released); remove it or set motion = \"free\"");
  if (s.release_time_si > 0.0 && s.release_time_si >= v.real("run.end_time"))
    throw InputError(
        fmt::format("particle.release_time: {:g} s is not before run.end_time ({:g} s), so the body would "
                    "never move freely; lower it or raise run.end_time",
                    s.release_time_si, v.real("run.end_time")));
  s.hold_ramp_time_si = v.real("particle.hold_ramp_time");
  if (s.motion == body::MotionKind::towed && s.hold_ramp_time_si > v.real("run.end_time"))
    throw InputError(fmt::format(
        "particle.hold_ramp_time: {:g} s is longer than the run (run.end_time = {:g} s); allowed for a towed body: "
        "0 to run.end_time",
        s.hold_ramp_time_si, v.real("run.end_time")));
  if (s.motion != body::MotionKind::towed && s.hold_ramp_time_si > s.release_time_si)
    throw InputError(fmt::format(
        "particle.hold_ramp_time: {:g} s is longer than the hold (particle.release_time = {:g} s); allowed: 0 to "
        "particle.release_time (towed bodies: 0 to run.end_time)",
        s.hold_ramp_time_si, s.release_time_si));
  if (s.motion == body::MotionKind::fixed) {
    s.initial.velocity_si.setZero();
    s.initial.angular_velocity_b_si.setZero();
  }
  read_rotation_lock(v, s);

  s.cells_per_diameter = v.real("numerics.cells_per_diameter");
  s.lattice = lbm::parse_lattice(v.string("numerics.lattice"), "numerics.lattice");
  s.collision = lbm::parse_collision(v.string("numerics.collision"), "numerics.collision");
  s.trt_magic = v.real("numerics.trt_magic");
  s.subgrid_model = lbm::parse_subgrid_model(v.string("numerics.subgrid_model"), "numerics.subgrid_model");
  s.smagorinsky_constant = v.real("numerics.smagorinsky_constant");
  s.precision = lbm::parse_precision(v.string("numerics.precision"), "numerics.precision");
  s.coupling = coupling::parse_coupling(v.string("numerics.coupling"), "numerics.coupling");
  s.wall_rule = lbm::parse_wall_rule(v.string("numerics.wall_rule"), "numerics.wall_rule");
  s.covered_cell_torque = v.boolean("numerics.covered_cell_torque");
  s.lattice_steps_per_body_step = static_cast<int>(v.integer("numerics.lattice_steps_per_body_step"));
  s.kernel = ibm::delta_kernel_from_string(v.string("numerics.delta_kernel"), "numerics.delta_kernel");
  s.forcing_iterations = static_cast<int>(v.integer("numerics.forcing_iterations"));
  s.interior_markers = v.boolean("numerics.interior_markers");
  s.marker_retraction_cells = v.has("numerics.marker_retraction")
                                  ? v.real("numerics.marker_retraction")
                                  : coupling::calibrated_marker_retraction_cells(s.interior_markers);
  s.max_lattice_velocity = v.real("numerics.max_lattice_velocity");
  s.max_tau = v.real("numerics.max_tau");
  if (v.has("numerics.tau")) s.tau = v.real("numerics.tau");

  s.wall_contact = v.boolean("contact.enabled");
  s.contact_restitution = v.real("contact.restitution");
  s.contact_wet_stokes_scale = v.real("contact.wet_stokes_scale");
  s.contact_collision_steps = v.real("contact.collision_steps");
  if (v.has("contact.distance_cells")) s.contact_distance_cells = v.real("contact.distance_cells");

  s.end_time_si = v.real("run.end_time");
  s.output_interval_si = v.real("run.output_interval");
  return s;
}

double particle_density_si(const CaseValues& v) {
  if (!v.has("particle.density"))
    throw InputError(
        "particle.density: required (kg/m^3; e.g. 2650 for quartz sand, 2500 for glass, 1050 for polystyrene); "
        "settle has no default for it");
  return v.real("particle.density");
}

std::vector<std::string> unsupported_key_warnings(const CaseValues& v) {
  std::vector<std::string> warnings;
  for (std::string& w : fluid_preset_warnings(v)) warnings.push_back(std::move(w));
  for (std::string& w : coupling_key_warnings(v)) warnings.push_back(std::move(w));
  for (std::string& w : collision_key_warnings(v)) warnings.push_back(std::move(w));
  return warnings;
}

}  // namespace settle::io
