#include "coupling/checkpoint_state.hpp"

#include <algorithm>
#include <exception>
#include <optional>
#include <stdexcept>
#include <string_view>
#include <utility>

#include <fmt/core.h>

#include "settle/version.hpp"

namespace settle::coupling {
namespace {

// Section names. Each caller blob is a section of its own, named with this prefix.
constexpr const char* kVersionSection = "settle/version";
constexpr const char* kCaseSection = "case/resolved.toml";
constexpr const char* kFingerprintSection = "simulation/fingerprint";
constexpr const char* kSimulationSection = "simulation/state";
constexpr const char* kBodySection = "body/state";
constexpr const char* kFluidSection = "fluid/state";
constexpr const char* kPopulationsSection = "fluid/populations";
// The momentum-exchange body's solid cells (absent from checkpoints of immersed-boundary runs and
// from those written before the section existed: no solid cells).
constexpr const char* kSolidCellsSection = "fluid/solid_cells";
constexpr const char* kCallerValuesSection = "caller/values";
// A run across processes: the manifest's record (processes, step of the parts) and each part's.
constexpr const char* kSplitSection = "parallel/split";
constexpr const char* kPartSection = "parallel/part";
constexpr std::string_view kCallerBlobPrefix = "caller/blob/";

/// One quantity the case fixes: its value (compared exactly) and how to show it to the user.
struct FingerprintEntry {
  std::string name;
  double value = 0.0;
  std::string shown;
};

/// The quantities the saved state only makes sense with: a restart into a simulation that
/// differs in any of them is refused. Run length and output intervals are not among them, so a
/// finished run can be extended.
using Fingerprint = std::vector<FingerprintEntry>;

FingerprintEntry number(std::string name, double value) {
  return {std::move(name), value, fmt::format("{:.17g}", value)};
}

template <class Enum>
FingerprintEntry choice(std::string name, Enum value) {
  return {std::move(name), static_cast<double>(static_cast<int>(value)), lbm::to_string(value)};
}

FingerprintEntry face_entry(std::string name, const std::optional<lbm::Face>& face) {
  return {std::move(name), face ? static_cast<double>(2 * face->axis + face->side) : -1.0,
          face ? lbm::to_string(*face) : "none"};
}

Fingerprint fingerprint_of(const Simulation& sim) {
  const lbm::SolverConfig& c = sim.fluid().config();
  const SimulationSetup& s = sim.setup();
  const body::MassProperties& m = sim.body().mass_properties();
  const std::optional<body::WallContact>& contact = sim.wall_contact();
  const body::ContactParameters wall = contact ? contact->parameters() : body::ContactParameters{};
  return {
      number("grid cells along x", c.nx),
      number("grid cells along y", c.ny),
      number("grid cells along z", c.nz),
      choice("lattice", c.lattice),
      choice("collision", c.collision),
      choice("precision", c.precision),
      choice("boundary along x", c.boundaries[0]),
      choice("boundary along y", c.boundaries[1]),
      choice("boundary along z", c.boundaries[2]),
      number("relaxation time tau", c.tau),
      number("TRT magic parameter", c.magic),
      choice("subgrid model", c.subgrid),
      number("Smagorinsky constant", c.smagorinsky_constant),
      number("fluid body force x (lattice units)", c.body_force.x()),
      number("fluid body force y (lattice units)", c.body_force.y()),
      number("fluid body force z (lattice units)", c.body_force.z()),
      number("dx (m)", sim.units().dx_si()),
      number("dt (s)", sim.units().dt_si()),
      number("fluid density (kg/m^3)", s.fluid_density_si),
      number("gravity x (m/s^2)", s.gravity_si.x()),
      number("gravity y (m/s^2)", s.gravity_si.y()),
      number("gravity z (m/s^2)", s.gravity_si.z()),
      {"particle motion", static_cast<double>(static_cast<int>(s.motion)),
       s.motion == body::MotionKind::free    ? "free"
       : s.motion == body::MotionKind::towed ? "towed"
                                             : "fixed"},
      number("particle mass (kg)", m.mass),
      number("particle volume (m^3)", m.volume),
      {"coupling (numerics.coupling)", static_cast<double>(static_cast<int>(s.coupling)), to_string(s.coupling)},
      {"wall rule (numerics.wall_rule)", static_cast<double>(static_cast<int>(s.wall_rule)),
       lbm::to_string(s.wall_rule)},
      {"covered cells' torque (numerics.covered_cell_torque)", s.covered_cell_torque ? 1.0 : 0.0,
       s.covered_cell_torque ? "true" : "false"},
      number("lattice steps per body step (numerics.lattice_steps_per_body_step)", s.lattice_steps_per_body_step),
      face_entry("inflow face", s.inflow),
      number("inflow velocity x (lattice units)", c.inflow_velocity.x()),
      number("inflow velocity y (lattice units)", c.inflow_velocity.y()),
      number("inflow velocity z (lattice units)", c.inflow_velocity.z()),
      face_entry("outflow face", s.outflow),
      // The entry's name is the file format's, kept from when both couplings spoke of markers: it
      // counts the wall links of a momentum exchange.
      number("surface markers", static_cast<double>(sim.derived().surface_element_count)),
      number("marker retraction (cells)", s.marker_retraction_cells),
      number("delta kernel", static_cast<double>(static_cast<int>(s.kernel))),
      number("forcing iterations", s.forcing_iterations),
      {"moving window (domain.follow_particle)", s.follow_particle ? 1.0 : 0.0, s.follow_particle ? "true" : "false"},
      {"particle-wall contact", contact ? 1.0 : 0.0, contact ? "on" : "off"},
      number("contact restitution", contact ? wall.restitution : 0.0),
      number("contact wet Stokes scale", contact ? wall.wet_stokes_scale : 0.0),
      number("contact collision time (s)", contact ? wall.collision_time_si : 0.0),
      number("contact distance (m)", contact ? wall.contact_distance_si : 0.0),
      number("contact substeps per collision", contact ? wall.substeps_per_collision : 0),
  };
}

std::vector<std::byte> encode_fingerprint(const Fingerprint& fingerprint) {
  RecordWriter out;
  out.u64(fingerprint.size());
  for (const FingerprintEntry& e : fingerprint) {
    out.string(e.name);
    out.f64(e.value);
    out.string(e.shown);
  }
  return out.take();
}

Fingerprint decode_fingerprint(std::span<const std::byte> data) {
  RecordReader in(data, kFingerprintSection);
  Fingerprint fingerprint;
  // No reserve from the stored count: a malformed count fails at the first read past the end.
  for (std::uint64_t n = in.u64(); n > 0; --n) {
    FingerprintEntry e;
    e.name = in.string();
    e.value = in.f64();
    e.shown = in.string();
    fingerprint.push_back(std::move(e));
  }
  in.expect_end();
  return fingerprint;
}

void write_wrench(RecordWriter& out, const body::Wrench& w) {
  out.vec3(w.force_si);
  out.vec3(w.torque_si);
}

body::Wrench read_wrench(RecordReader& in) {
  body::Wrench w;
  w.force_si = in.vec3();
  w.torque_si = in.vec3();
  return w;
}

std::vector<std::byte> encode_body(const body::RigidBodyState& s) {
  RecordWriter out;
  out.vec3(s.position_si);
  out.vec3(s.velocity_si);
  out.u32(static_cast<std::uint32_t>(s.attitude.set()));
  out.vec3(s.attitude.angles());
  out.vec3(s.angular_velocity_b_si);
  return out.take();
}

body::RigidBodyState decode_body(std::span<const std::byte> data) {
  RecordReader in(data, kBodySection);
  body::RigidBodyState s;
  s.position_si = in.vec3();
  s.velocity_si = in.vec3();
  const std::uint32_t set = in.u32();
  if (set != 1 && set != 2)
    throw CheckpointError(fmt::format("checkpoint section '{}': Euler set {}", kBodySection, set));
  const Eigen::Vector3d angles = in.vec3();
  s.attitude = attitude::Attitude(static_cast<attitude::EulerSet>(set), angles);
  s.angular_velocity_b_si = in.vec3();
  in.expect_end();
  if (!s.position_si.allFinite() || !s.velocity_si.allFinite() || !angles.allFinite() ||
      !s.angular_velocity_b_si.allFinite())
    throw CheckpointError(fmt::format("checkpoint section '{}': the body state is not finite", kBodySection));
  return s;
}

std::vector<std::byte> encode_fluid(const lbm::FluidState& f) {
  RecordWriter out;
  const lbm::StateLayout& l = f.layout;
  for (const int n : {l.nx, l.ny, l.nz, l.q}) out.i64(n);
  out.u32(l.element_bytes);
  for (const std::uint64_t n : {l.x_begin, l.sx, l.sxy, l.pop_stride, l.population_elements}) out.u64(n);
  out.i64(f.step_count);
  out.u64(f.forced_cells.size());
  for (const std::uint64_t n : f.forced_cells) out.u64(n);
  for (const double v : f.forced_values) out.f64(v);
  return out.take();
}

/// The fluid record; the populations view is filled in from its own section.
lbm::FluidState decode_fluid(std::span<const std::byte> data) {
  RecordReader in(data, kFluidSection);
  lbm::FluidState f;
  lbm::StateLayout& l = f.layout;
  for (int* n : {&l.nx, &l.ny, &l.nz, &l.q}) *n = static_cast<int>(in.i64());
  l.element_bytes = in.u32();
  for (std::uint64_t* n : {&l.x_begin, &l.sx, &l.sxy, &l.pop_stride, &l.population_elements}) *n = in.u64();
  f.step_count = in.i64();
  for (std::uint64_t n = in.u64(); n > 0; --n) f.forced_cells.push_back(in.u64());
  for (std::size_t k = 0; k < 3 * f.forced_cells.size(); ++k) f.forced_values.push_back(in.f64());
  in.expect_end();
  return f;
}

std::vector<std::byte> encode_solid_cells(const std::vector<std::uint64_t>& cells) {
  RecordWriter out;
  out.u64(cells.size());
  for (const std::uint64_t n : cells) out.u64(n);
  return out.take();
}

std::vector<std::uint64_t> decode_solid_cells(std::span<const std::byte> data) {
  RecordReader in(data, kSolidCellsSection);
  std::vector<std::uint64_t> cells;
  for (std::uint64_t n = in.u64(); n > 0; --n) cells.push_back(in.u64());
  in.expect_end();
  return cells;
}

std::vector<std::byte> encode_values(const std::map<std::string, double>& values) {
  RecordWriter out;
  out.u64(values.size());
  for (const auto& [name, value] : values) {
    out.string(name);
    out.f64(value);
  }
  return out.take();
}

std::map<std::string, double> decode_values(std::span<const std::byte> data) {
  RecordReader in(data, kCallerValuesSection);
  std::map<std::string, double> values;
  for (std::uint64_t n = in.u64(); n > 0; --n) {
    std::string name = in.string();
    values[std::move(name)] = in.f64();
  }
  in.expect_end();
  return values;
}

std::string text_of(std::span<const std::byte> data) {
  return {reinterpret_cast<const char*>(data.data()), data.size()};
}

/// The fingerprint of the simulation must equal the saved one entry by entry.
void check_fingerprint(const Fingerprint& saved, const Fingerprint& current, const std::filesystem::path& file) {
  const auto refuse = [&](const std::string& what) {
    throw CheckpointError(
        fmt::format("{}: the checkpoint was written for another case: {}; restart with the "
                    "resolved case stored in the checkpoint",
                    file.string(), what));
  };
  for (const FingerprintEntry& now : current) {
    const FingerprintEntry* before = nullptr;
    for (const FingerprintEntry& e : saved)
      if (e.name == now.name) before = &e;
    if (!before) refuse(fmt::format("it records no {}", now.name));
    // Exact comparison: the same resolved case on the same build reproduces every value bit for
    // bit, and anything else would not continue the run bit for bit.
    if (!(before->value == now.value))
      refuse(fmt::format("{} is {} in the checkpoint and {} in this simulation", now.name, before->shown, now.shown));
  }
  if (saved.size() != current.size()) refuse("it records quantities this version of settle does not know");
}

/// The name a sub-step is timed under now, for one a checkpoint recorded: a checkpoint written
/// before each coupling named its own sub-steps holds their times under the former names.
const char* current_sub_step_name(const Simulation& sim, const std::string& recorded) {
  const SubStepNames now = sim.coupling().sub_step_names();
  if (recorded == kFormerSubStepNames.place) return now.place;
  if (recorded == kFormerSubStepNames.impose) return now.impose;
  if (recorded == kFormerSubStepNames.measure) return now.measure;
  return recorded.c_str();
}

}  // namespace

/// The private members of Simulation that a checkpoint holds (friend of Simulation).
struct CheckpointAccess {
  static std::vector<std::byte> encode(const Simulation& sim) {
    RecordWriter out;
    out.i64(sim.steps_);
    out.f64(static_cast<double>(sim.steps_) * sim.plan_.units.dt_si());
    out.vec3(sim.frame_.window_origin_si);
    out.f64(sim.frame_.dx_si);
    out.vec3(sim.window_anchor_);
    for (const double v : sim.coupling_->carried_state()) out.f64(v);
    out.vec3(sim.virtual_inertia_.acceleration_si);
    out.vec3(sim.virtual_inertia_.angular_acceleration_b_si);
    write_wrench(out, sim.last_.hydrodynamic);
    write_wrench(out, sim.last_.surface);
    write_wrench(out, sim.last_.internal_rate);
    out.f64(sim.last_.slip_max_si);
    out.f64(sim.last_.slip_rms_si);
    write_wrench(out, sim.last_.contact);
    out.f64(sim.last_.wall_gap_si);
    // The impact speed of each wall's contact in progress (-1: none): it fixes that contact's
    // restitution (body/contact.hpp), so a restart in mid-contact continues the same contact.
    const std::vector<std::optional<double>> impacts =
        sim.contact_ ? sim.contact_->impact_speeds_si() : std::vector<std::optional<double>>{};
    out.u64(impacts.size());
    for (const std::optional<double>& speed : impacts) out.f64(speed.value_or(-1.0));
    out.u64(sim.timers_.entries().size());
    for (const auto& [name, seconds] : sim.timers_.entries()) {
      out.string(name);
      out.f64(seconds);
    }
    return out.take();
  }

  /// The decoded record, applied only after every check has passed.
  struct Saved {
    std::int64_t steps = 0;
    double time_si = 0.0;
    LatticeFrame frame;
    Eigen::Vector3d window_anchor = Eigen::Vector3d::Zero();
    std::array<double, 6> coupling_carried{};
    Eigen::Vector3d acceleration_estimate_si = Eigen::Vector3d::Zero();
    Eigen::Vector3d angular_acceleration_estimate_b_si = Eigen::Vector3d::Zero();
    StepObservation last;
    std::vector<std::optional<double>> impact_speeds_si;
    std::vector<std::pair<std::string, double>> timers;
  };

  static Saved decode(std::span<const std::byte> data) {
    RecordReader in(data, kSimulationSection);
    Saved s;
    s.steps = in.i64();
    s.time_si = in.f64();
    s.frame.window_origin_si = in.vec3();
    s.frame.dx_si = in.f64();
    s.window_anchor = in.vec3();
    for (double& v : s.coupling_carried) v = in.f64();
    s.acceleration_estimate_si = in.vec3();
    s.angular_acceleration_estimate_b_si = in.vec3();
    s.last.hydrodynamic = read_wrench(in);
    s.last.surface = read_wrench(in);
    s.last.internal_rate = read_wrench(in);
    s.last.slip_max_si = in.f64();
    s.last.slip_rms_si = in.f64();
    s.last.contact = read_wrench(in);
    s.last.wall_gap_si = in.f64();
    for (std::uint64_t n = in.u64(); n > 0; --n) {
      const double speed = in.f64();
      s.impact_speeds_si.push_back(speed < 0.0 ? std::nullopt : std::optional<double>(speed));
    }
    for (std::uint64_t n = in.u64(); n > 0; --n) {
      std::string name = in.string();
      s.timers.emplace_back(std::move(name), in.f64());
    }
    in.expect_end();
    if (s.steps < 0)
      throw CheckpointError(fmt::format("checkpoint section '{}': negative step count", kSimulationSection));
    return s;
  }

  static void apply(Simulation& sim, const Saved& s, const body::RigidBodyState& body) {
    sim.body_->set_state(body);
    sim.steps_ = s.steps;
    sim.frame_ = s.frame;
    sim.window_anchor_ = s.window_anchor;
    sim.coupling_->restore_carried_state(s.coupling_carried);
    sim.virtual_inertia_.acceleration_si = s.acceleration_estimate_si;
    sim.virtual_inertia_.angular_acceleration_b_si = s.angular_acceleration_estimate_b_si;
    sim.last_ = s.last;
    if (sim.contact_) sim.contact_->restore_impact_speeds(s.impact_speeds_si);
    sim.timers_ = SubstepTimers{};
    for (const auto& [name, seconds] : s.timers) sim.timers_.add(current_sub_step_name(sim, name), seconds);
  }
};

namespace {

// Which of the checkpoint's sections hold what (write_checkpoint's comment in the header).
void add_identity_sections(CheckpointWriter& writer, const Simulation& sim) {
  RecordWriter version;
  version.string(version_string);
  writer.add_copy(kVersionSection, version.take());
  writer.add_copy(kFingerprintSection, encode_fingerprint(fingerprint_of(sim)));
}

void add_fluid_sections(CheckpointWriter& writer, const lbm::FluidState& fluid) {
  writer.add_copy(kFluidSection, encode_fluid(fluid));
  writer.add_view(kPopulationsSection, fluid.populations);
  if (!fluid.solid_cells.empty()) writer.add_copy(kSolidCellsSection, encode_solid_cells(fluid.solid_cells));
}

/// Everything but the fluid: identical on every rank of a split run, so rank 0 alone writes it.
void add_state_sections(CheckpointWriter& writer, const Simulation& sim, const CheckpointCallerData& caller) {
  writer.add_view(kCaseSection, std::as_bytes(std::span(caller.resolved_case)));
  writer.add_copy(kSimulationSection, CheckpointAccess::encode(sim));
  writer.add_copy(kBodySection, encode_body(sim.body().state()));
  writer.add_copy(kCallerValuesSection, encode_values(caller.values));
  for (const auto& [name, blob] : caller.blobs) writer.add_view(std::string(kCallerBlobPrefix) + name, blob);
}

/// The split record: in the manifest the processes and the step of its parts; in a part also its rank.
std::vector<std::byte> encode_split(const SplitRecord& split) {
  RecordWriter out;
  out.u32(static_cast<std::uint32_t>(split.ranks));
  out.u32(static_cast<std::uint32_t>(split.rank));
  out.i64(split.step);
  return out.take();
}

SplitRecord decode_split(std::span<const std::byte> data, const char* section) {
  RecordReader in(data, section);
  SplitRecord split;
  split.ranks = static_cast<int>(in.u32());
  split.rank = static_cast<int>(in.u32());
  split.step = in.i64();
  in.expect_end();
  if (split.ranks < 2 || split.rank < 0 || split.rank >= split.ranks || split.step < 0)
    throw CheckpointError(fmt::format("checkpoint section '{}': rank {} of {} processes at step {}", section,
                                      split.rank, split.ranks, split.step));
  return split;
}

/// Runs `action` on every rank and fails on every rank if it failed on any: a rank that went on
/// alone would wait for the others' messages forever. The failing rank throws its own error; the
/// others name the first rank that failed, `what` it was doing and its reason (rank 0 reports, and
/// the reason is often on another rank: a part's failed CRC-32, a missing part).
template <class Action>
void on_every_rank(parallel::Communicator& ranks, const std::string& what, Action action) {
  std::exception_ptr failure;
  std::optional<std::string> reason;
  try {
    action();
  } catch (const std::exception& e) {
    failure = std::current_exception();
    reason = e.what();
  } catch (...) {
    failure = std::current_exception();
    reason = "an unknown error";
  }
  const std::optional<parallel::RankFailure> failed = parallel::first_failure(ranks, reason);
  if (failure) std::rethrow_exception(failure);
  if (failed) throw CheckpointError(fmt::format("rank {} failed: {}: {}", failed->rank, what, failed->message));
}

std::filesystem::path part_file(const std::filesystem::path& manifest, std::int64_t step, int rank) {
  return checkpoint_parts_directory(manifest) / fmt::format("step-{:012}", step) / fmt::format("rank-{:05}.bin", rank);
}

// A name of the parts layout: `prefix` followed by exactly `digits` decimal digits, then `suffix`.
bool numbered_name(const std::string& name, std::string_view prefix, std::size_t digits, std::string_view suffix) {
  if (name.size() != prefix.size() + digits + suffix.size() || !name.starts_with(prefix) || !name.ends_with(suffix))
    return false;
  return std::all_of(name.begin() + static_cast<std::ptrdiff_t>(prefix.size()),
                     name.end() - static_cast<std::ptrdiff_t>(suffix.size()),
                     [](char c) { return c >= '0' && c <= '9'; });
}

bool step_folder_name(const std::string& name) { return numbered_name(name, "step-", 12, ""); }

// A part (rank-NNNNN.bin) or its temporary, with a checkpoint's signature (the temporary may be cut
// before it).
bool settle_part_file(const std::filesystem::path& file) {
  const std::string name = file.filename().string();
  if (numbered_name(name, "rank-", 5, ".bin")) return is_checkpoint_file(file);
  return numbered_name(name, "rank-", 5, ".bin.tmp") && is_checkpoint_file(file, true);
}

/// The parts of other steps than `step` (earlier checkpoints, or a later one whose manifest was
/// never written); best effort: what stays behind is removed after the next checkpoint.
void remove_parts_except(const std::filesystem::path& manifest, std::int64_t step) {
  remove_checkpoint_parts(manifest, part_file(manifest, step, 0).parent_path().filename().string());
}

void write_split_checkpoint(const Simulation& sim, const CheckpointCallerData& caller,
                            const std::filesystem::path& file) {
  parallel::Communicator& ranks = sim.communicator();
  const SplitRecord split{ranks.size(), ranks.rank(), sim.steps()};
  const std::filesystem::path part = part_file(file, split.step, split.rank);
  on_every_rank(ranks, fmt::format("writing its part of the checkpoint under {}", part.parent_path().string()), [&] {
    std::error_code error;
    std::filesystem::create_directories(part.parent_path(), error);
    if (error)
      throw CheckpointError(fmt::format("{}: cannot create it: {}", part.parent_path().string(), error.message()));
    const lbm::FluidState fluid = sim.fluid().export_state();
    CheckpointWriter writer;
    add_identity_sections(writer, sim);
    writer.add_copy(kPartSection, encode_split(split));
    add_fluid_sections(writer, fluid);
    writer.write(part);
  });
  // Every part is complete: the manifest may now point to them.
  on_every_rank(ranks, "writing the checkpoint's manifest " + file.string(), [&] {
    if (split.rank != 0) return;
    CheckpointWriter writer;
    add_identity_sections(writer, sim);
    writer.add_copy(kSplitSection, encode_split({split.ranks, 0, split.step}));
    add_state_sections(writer, sim, caller);
    writer.write(file);
  });
  if (split.rank == 0) remove_parts_except(file, split.step);
}

}  // namespace

std::filesystem::path checkpoint_parts_directory(const std::filesystem::path& file) {
  return file.parent_path() / (file.filename().string() + ".parts");
}

std::optional<std::filesystem::path> foreign_entry_in_parts(const std::filesystem::path& file) {
  namespace fs = std::filesystem;
  std::error_code error;
  const fs::path parts = checkpoint_parts_directory(file);
  const fs::file_status status = fs::symlink_status(parts, error);
  if (!fs::exists(status)) return std::nullopt;
  if (!fs::is_directory(status)) return parts;
  for (const auto& step : fs::directory_iterator(parts, error)) {
    if (!step_folder_name(step.path().filename().string()) || !fs::is_directory(step.symlink_status(error)))
      return step.path();
    for (const auto& part : fs::directory_iterator(step.path(), error))
      if (!settle_part_file(part.path())) return part.path();
  }
  if (error) return parts;  // unreadable: nothing in it can be told apart
  return std::nullopt;
}

void remove_checkpoint_parts(const std::filesystem::path& file, const std::string& keep_step_folder) {
  namespace fs = std::filesystem;
  std::error_code error;
  const fs::path parts = checkpoint_parts_directory(file);
  if (!fs::is_directory(fs::symlink_status(parts, error))) return;
  for (const auto& step : fs::directory_iterator(parts, error)) {
    const std::string name = step.path().filename().string();
    if (name == keep_step_folder || !step_folder_name(name) || !fs::is_directory(step.symlink_status(error))) continue;
    for (const auto& part : fs::directory_iterator(step.path(), error))
      if (settle_part_file(part.path())) fs::remove(part.path(), error);
    fs::remove(step.path(), error);  // only when it is now empty
  }
  fs::remove(parts, error);  // only when it is now empty
}

void write_checkpoint(const Simulation& sim, const CheckpointCallerData& caller, const std::filesystem::path& file) {
  if (!sim.between_body_steps())
    throw std::logic_error("write_checkpoint: a body step is half done (the runner waits for its end)");
  if (sim.communicator().size() > 1) return write_split_checkpoint(sim, caller, file);
  const lbm::FluidState fluid = sim.fluid().export_state();
  CheckpointWriter writer;
  add_identity_sections(writer, sim);
  add_state_sections(writer, sim, caller);
  add_fluid_sections(writer, fluid);
  writer.write(file);
}

SimulationCheckpoint::SimulationCheckpoint(const std::filesystem::path& file) : file_(file) {
  // Every record is decoded once here, so that a malformed one is refused before the caller
  // builds a simulation; restore() decodes them again (they are small).
  written_by_ = RecordReader(file_.section(kVersionSection), kVersionSection).string();
  caller_.resolved_case = text_of(file_.section(kCaseSection));
  caller_.values = decode_values(file_.section(kCallerValuesSection));
  for (const std::string& name : file_.section_names())
    if (name.starts_with(kCallerBlobPrefix)) {
      const auto data = file_.section(name);
      caller_.blobs[name.substr(kCallerBlobPrefix.size())] = std::vector<std::byte>(data.begin(), data.end());
    }
  decode_fingerprint(file_.section(kFingerprintSection));
  decode_body(file_.section(kBodySection));
  if (file_.has(kSplitSection))
    split_ = decode_split(file_.section(kSplitSection), kSplitSection);
  else
    decode_fluid(file_.section(kFluidSection));
  const CheckpointAccess::Saved saved = CheckpointAccess::decode(file_.section(kSimulationSection));
  steps_ = saved.steps;
  time_si_ = saved.time_si;
  if (file_.has(kSplitSection) && split_.step != steps_)
    throw CheckpointError(
        fmt::format("checkpoint section '{}': parts of step {}, state of step {}", kSplitSection, split_.step, steps_));
}

namespace {

/// A continued run needs the split the checkpoint was written with: each part holds one block.
void check_process_count(const std::filesystem::path& file, int written_by, int running) {
  if (written_by == running) return;
  const std::string dir = file.parent_path().string();
  const std::string how = written_by == 1
                              ? fmt::format("continue it without mpirun: settle run --restart {}", dir)
                              : fmt::format("continue it with mpirun -n {} settle run --restart {}", written_by, dir);
  throw CheckpointError(fmt::format("{}: the checkpoint was written by {} process{}, this run has {}; {}",
                                    file.string(), written_by, written_by == 1 ? "" : "es", running, how));
}

/// The fluid sections of `file` (the whole checkpoint, or this rank's part) into the simulation.
void restore_fluid(const CheckpointFile& file, Simulation& sim, const std::string& written_by) {
  lbm::FluidState fluid = decode_fluid(file.section(kFluidSection));
  fluid.populations = file.section(kPopulationsSection);
  if (file.has(kSolidCellsSection)) fluid.solid_cells = decode_solid_cells(file.section(kSolidCellsSection));
  if (!(fluid.layout == sim.fluid().export_state().layout))
    throw CheckpointError(
        fmt::format("{}: the fluid's memory layout differs from this build's (written by "
                    "settle {}); restart with the settle that wrote it",
                    file.path().string(), written_by));
  // The solver checks the whole state before it writes anything, so a refusal leaves the fluid
  // unchanged.
  try {
    sim.fluid().import_state(fluid);
  } catch (const std::invalid_argument& e) {
    throw CheckpointError(fmt::format("{}: {}", file.path().string(), e.what()));
  }
}

}  // namespace

void SimulationCheckpoint::restore(Simulation& sim) const {
  parallel::Communicator& ranks = sim.communicator();
  check_process_count(file_.path(), split_.ranks, ranks.size());
  const Fingerprint current = fingerprint_of(sim);
  check_fingerprint(decode_fingerprint(file_.section(kFingerprintSection)), current, file_.path());
  const CheckpointAccess::Saved saved = CheckpointAccess::decode(file_.section(kSimulationSection));
  const body::RigidBodyState body = decode_body(file_.section(kBodySection));
  if (ranks.size() == 1) {
    restore_fluid(file_, sim, written_by_);
  } else {
    // Across processes a refusal may come after other ranks have restored their blocks: the run
    // then ends on every rank, so no simulation continues half restored.
    const std::filesystem::path part = part_file(file_.path(), split_.step, ranks.rank());
    on_every_rank(ranks, "reading its part of the checkpoint under " + part.parent_path().string(), [&] {
      const CheckpointFile piece(part);
      const SplitRecord record = decode_split(piece.section(kPartSection), kPartSection);
      if (record.ranks != split_.ranks || record.rank != ranks.rank() || record.step != split_.step)
        throw CheckpointError(
            fmt::format("{}: holds rank {} of {} at step {}, where the manifest {} needs rank {} of {} "
                        "at step {}",
                        part.string(), record.rank, record.ranks, record.step, file_.path().string(), ranks.rank(),
                        split_.ranks, split_.step));
      check_fingerprint(decode_fingerprint(piece.section(kFingerprintSection)), current, part);
      restore_fluid(piece, sim, written_by_);
    });
  }
  // Nothing after this can fail (the body state was checked finite when it was decoded).
  CheckpointAccess::apply(sim, saved, body);
}

}  // namespace settle::coupling
