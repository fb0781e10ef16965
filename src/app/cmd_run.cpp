// `settle run [CASE.toml] [-o DIR] [--set key=value]... [--threads N] [--max-memory GIB]`
// (docs/architecture.md, "Outputs"): loads and checks the case, runs the preflight checks (io/preflight.hpp,
// docs/errors.md), converts units, runs the coupled simulation and writes DIR/timeseries.csv,
// DIR/summary.json and DIR/case.resolved.toml (docs/coupling.md).
//
// Outputs on failure: every check runs, and the grid is allocated, before DIR is created or
// touched, so a refused case (exit status 2) leaves DIR exactly as it was, or absent. Once the
// run has started, summary.json is the completion mark: it is removed at the start (it would
// describe an earlier run) and written only at the end, so a run that fails or is interrupted
// leaves the rows it reached in timeseries.csv and no summary.json.
#include <omp.h>

#include <cmath>
#include <cstdio>
#include <exception>
#include <filesystem>
#include <memory>
#include <optional>
#include <string>
#include <string_view>
#include <utility>
#include <vector>

#include <fmt/core.h>
#include <nlohmann/json.hpp>

#include "analysis/observables.hpp"
#include "analysis/spectrum.hpp"
#include "analysis/terminal_state.hpp"
#include "analysis/timeseries.hpp"
#include "app/commands.hpp"
#include "app/console.hpp"
#include "app/earlier_run.hpp"
#include "app/flag_values.hpp"
#include "app/output_values.hpp"
#include "app/run_checkpoints.hpp"
#include "app/run_directory_lock.hpp"
#include "app/run_plan.hpp"
#include "app/summary_fields.hpp"
#include "body/surface_triangulation.hpp"
#include "common/atomic_file.hpp"
#include "common/error.hpp"
#include "coupling/health.hpp"
#include "coupling/runner.hpp"
#include "coupling/simulation.hpp"
#include "coupling/time_control.hpp"
#include "io/case.hpp"
#include "io/output_files.hpp"
#include "io/plausibility.hpp"
#include "io/preflight.hpp"
#include "io/pvd.hpp"
#include "io/vtk.hpp"
#include "io/vtk_pieces.hpp"
#include "lbm/config.hpp"
#include "lbm/decomposition.hpp"
#include "lbm/solver.hpp"
#include "parallel/communicator.hpp"
#include "settle/version.hpp"

namespace settle::app {
namespace {

namespace fs = std::filesystem;

struct RunOptions {
  std::string case_file;
  std::string output_dir;
  std::vector<std::string> overrides;
  int threads = 0;  ///< 0: OpenMP's default
  double max_memory_gib = 0.0;
  bool max_memory_given = false;  ///< --max-memory replaces MemAvailable as the budget
  bool quiet = false, verbose = false;
  bool dry_run = false;     ///< --dry-run: print the plan and stop
  std::string restart_dir;  ///< --restart DIR (app/run_checkpoints.hpp)
  bool overwrite = false;   ///< --overwrite: replace another run's results in the directory
};

void check_flags(const RunOptions& options) {
  check_thread_count(options.threads, "--threads");
  if (options.quiet && options.verbose) throw InputError("--quiet and --verbose: choose one");
  if (options.dry_run && !options.restart_dir.empty())
    throw InputError("--dry-run: plans a case file, not a continued run; leave out --restart");
  if (options.overwrite && !options.restart_dir.empty())
    throw InputError("--overwrite and --restart exclude each other: a restart continues the run in its directory");
  if (options.max_memory_given && !(std::isfinite(options.max_memory_gib) && options.max_memory_gib > 0.0))
    throw InputError(fmt::format("--max-memory: must be a finite number of GiB > 0, got {}", options.max_memory_gib));
}

// The earlier run's files in DIR that this run replaces or removes, all recognised as settle's
// (app/earlier_run.hpp); read-only, so that the preflight can refuse before anything changes.
// A fresh run refuses a directory holding another run's results unless --overwrite: the two runs'
// files would mix (an older run's vtk/ and plots/ beside the new series).
EarlierRun survey_run_directory(const fs::path& dir, bool restarted, bool overwrite, const io::CaseValues& values) {
  if (restarted) return survey_restarted_run(dir);
  EarlierRun earlier =
      survey_earlier_run(dir, values.has("particle.file") ? mesh_copy_name(values.string("particle.file")) : "");
  if (!overwrite && !earlier.results.empty()) {
    refuse_if_live_run(dir);  // the clearer reason when a live run writes them
    std::string names;
    for (const std::string& name : earlier.results) names += (names.empty() ? "" : ", ") + name;
    throw InputError(fmt::format(
        "-o {}: holds the results of another run ({}); give --overwrite to replace them (settle removes only the "
        "files it wrote there), choose another -o directory, or continue that run with --restart {}",
        dir.string(), names, dir.string()));
  }
  return earlier;
}

// Without -o the results go to runs/<case name>, the case file's name without its extension:
// "...toml" leaves "..", which would put them in the current directory (and "..toml", ".", in
// runs/ itself).
void check_results_folder_name(const std::string& name, const fs::path& case_path) {
  if (!name.empty() && name != "." && name != "..") return;
  throw InputError(
      fmt::format("{}: the case's name (its file name without .toml) is \"{}\", which cannot name the results "
                  "folder runs/<case name>; rename the case file or give -o DIR",
                  case_path.string(), name));
}

// Called only after every check passed and the grid is allocated (file comment).
// Creates the directory and takes its lock before anything in it changes; the survey is made
// again under the lock (another process may have written DIR since the preflight's).
std::unique_ptr<RunDirectoryLock> prepare_output_directory(const fs::path& dir, bool restarted, bool overwrite,
                                                           const io::CaseValues& values) {
  std::error_code error;
  fs::create_directories(dir, error);
  if (error) throw InputError(fmt::format("-o: cannot create the directory {}: {}", dir.string(), error.message()));
  auto lock = std::make_unique<RunDirectoryLock>(dir);
  remove_earlier_run(survey_run_directory(dir, restarted, overwrite, values));
  return lock;
}

// DIR/run.log, the console's lines (app/console.hpp): appended to by a restart, new otherwise (an
// earlier run's log was removed with its results). nullptr when stderr writes that file already
// (settle study) or it cannot be opened (the run goes on: its log is a convenience; the warning says so).
std::FILE* open_run_log(const fs::path& dir, bool restarted) {
  const fs::path log = dir / kRunLogFileName;
  if (is_standard_error(log)) return nullptr;
  std::FILE* file = std::fopen(log.c_str(), restarted ? "a" : "w");
  if (file == nullptr)
    write_stderr(fmt::format("settle run: warning: cannot write {}; the run goes on without it\n", log.string()));
  return file;
}

// The run directory holds everything needed to read it again (settle analyze, a later restart):
// a mesh is copied beside case.resolved.toml, which names the copy, so that moving or deleting the
// case's directory leaves the run readable.
io::CaseValues with_mesh_copied_into(const io::CaseValues& values, const fs::path& case_base, const fs::path& dir) {
  io::CaseValues resolved = values;
  if (!values.has("particle.file")) return resolved;
  const fs::path source = case_base / values.string("particle.file");
  const fs::path copy_name = mesh_copy_name(source);
  std::error_code error;
  if (!fs::equivalent(source, dir / copy_name, error)) {
    fs::copy_file(source, dir / copy_name, fs::copy_options::overwrite_existing, error);
    if (error)
      throw InputError(fmt::format("particle.file: cannot copy {} into the run directory {}: {}", source.string(),
                                   dir.string(), error.message()));
  }
  resolved.set("particle.file", io::Value(copy_name.string()), "settle run");
  return resolved;
}

std::string motion_name(body::MotionKind kind) {
  switch (kind) {
    case body::MotionKind::towed:
      return "towed";
    case body::MotionKind::fixed:
      return "fixed";
    case body::MotionKind::free:
      break;
  }
  return "free";
}

// The converter's choices, as TOML comments after the resolved keys: the file stays a valid
// case (the schema has no [derived] keys), and a reader sees what the run used.
std::string derived_block(const coupling::Simulation& sim) {
  const auto& d = sim.derived();
  const auto& p = sim.plan();
  const bool markers = sim.coupling().fluid_inside();  // the immersed boundary's
  return fmt::format(
      "\n{} (not read back):\n"
      "# dx = {:.9g}  # m, d_eq / cells_per_diameter\n"
      "# dt = {:.9g}  # s\n"
      "# tau = {:.9g}\n"
      "# cells = [{}, {}, {}]\n"
      "# equivalent_diameter = {:.9g}  # m\n"
      "# expected_speed = {:.9g}  # m/s, the speed dt was chosen for\n"
      "# mach = {:.6g}  # of the expected speed\n"
      "# reynolds = {:.6g}  # expected speed x d_eq / nu\n"
      "# galileo = {:.6g}\n"
      "# {} = {}\n"
      "{}",
      kDerivedBlockTitle, p.units.dx_si(), p.units.dt_si(), p.units.tau(), d.cells[0], d.cells[1], d.cells[2],
      p.equivalent_diameter_si, p.expected_speed_si, p.mach, p.reynolds, p.galileo, markers ? "markers" : "wall_links",
      d.surface_element_count,
      markers ? fmt::format("# marker_retraction = {:.9g}  # cells\n", sim.setup().marker_retraction_cells) : "");
}

// Deprecated, for one release: a sub-step the coupling renamed is repeated under its former name
// (coupling::kFormerSubStepNames; docs/user-guide.md, "summary.json").
void add_former_timing_names(nlohmann::json& timing, const coupling::SubStepNames& now) {
  const coupling::SubStepNames& former = coupling::kFormerSubStepNames;
  for (const auto& [old_name, new_name] : {std::pair{former.place, now.place}, std::pair{former.impose, now.impose},
                                           std::pair{former.measure, now.measure}})
    if (std::string_view(old_name) != new_name && timing.contains(new_name)) timing[old_name] = timing[new_name];
}

// What the run itself reports: the case, the converter's numbers, the loop's figures and timing.
nlohmann::json run_json(const coupling::Simulation& sim, const coupling::RunResult& result,
                        const std::vector<std::string>& warnings) {
  const auto& d = sim.derived();
  const auto& p = sim.plan();
  nlohmann::json j;
  j["settle_version"] = settle::version_string;
  j["settle_commit"] = settle::commit_string;
  j["case"] = sim.setup().name;
  j["motion"] = motion_name(sim.body().motion_kind());
  j["cells"] = d.cells[0] * static_cast<long long>(d.cells[1]) * d.cells[2];
  j["grid"] = {d.cells[0], d.cells[1], d.cells[2]};
  j["dx"] = p.units.dx_si();
  j["dt"] = p.units.dt_si();
  j["tau"] = p.units.tau();
  j["mach"] = p.mach;
  j["cell_reynolds"] = p.cell_reynolds;
  // The model the run used: numerics.subgrid_model = "auto" resolved (lbm::chosen_subgrid_model).
  j["subgrid_model"] = lbm::to_string(p.subgrid_model);
  j["equivalent_diameter"] = p.equivalent_diameter_si;
  j["coupling"] = coupling::to_string(sim.coupling().kind());
  j["surface_elements"] = d.surface_element_count;
  // Deprecated, for one release: surface_elements under its former name (docs/user-guide.md).
  j["markers"] = d.surface_element_count;
  j["steps"] = result.steps;
  j["simulated_time"] = result.simulated_time_si;
  j["stop_reason"] = result.stop_reason;
  j["wall_seconds"] = result.wall_seconds;
  j["mlups"] = result.mlups;
  // How close the run came to the health check's limits (coupling/health.hpp), at the output times.
  const coupling::HealthLimits limits;
  j["fluid_health"] = {{"max_density_deviation", result.extremes.density_deviation},
                       {"density_deviation_limit", limits.max_density_deviation},
                       {"max_lattice_speed", result.extremes.lattice_speed},
                       {"lattice_speed_limit", limits.max_lattice_speed}};
  nlohmann::json timing = nlohmann::json::object();
  for (const auto& [name, seconds] : sim.timers().entries()) timing[name] = seconds;
  add_former_timing_names(timing, sim.coupling().sub_step_names());
  j["timing"] = timing;
  j["warnings"] = warnings;
  return j;
}

// The run loop's averages over the second half (coupling::summarise): the results of fixed and
// towed bodies, and of a free body whose analysis could not be made.
// The dominant frequency of the lift of a fixed or towed body over the averaging window (the
// second half), as a Strouhal number f d_eq / U: the shedding frequency of a wake.
void add_lift_spectrum(nlohmann::json& j, const coupling::Simulation& sim, const coupling::RunResult& result,
                       const coupling::RunSummary& summary) {
  const double speed = summary.mean_relative_flow_si.norm();
  if (!summary.has_coefficients || speed <= 0.0) return;
  const Eigen::Vector3d flow = summary.mean_relative_flow_si / speed;
  std::vector<double> t_si;
  std::vector<std::vector<double>> lift(3);
  for (const coupling::Sample& s : result.samples) {
    if (s.t_si < 0.5 * result.simulated_time_si || s.t_si <= 0.0) continue;
    const Eigen::Vector3d force = s.hydrodynamic.force_si;
    const Eigen::Vector3d normal = force - force.dot(flow) * flow;
    t_si.push_back(s.t_si);
    for (int a = 0; a < 3; ++a) lift[static_cast<std::size_t>(a)].push_back(normal[a]);
  }
  const analysis::SpectralPeak peak = analysis::spectral_peak(t_si, lift);
  j["lift_frequency"] = peak.found ? nlohmann::json(peak.frequency_hz) : nlohmann::json(nullptr);
  j["lift_strouhal"] = peak.found ? nlohmann::json(peak.frequency_hz * sim.plan().equivalent_diameter_si / speed)
                                  : nlohmann::json(nullptr);
  j["lift_spectral_concentration"] = peak.found ? nlohmann::json(peak.concentration) : nlohmann::json(nullptr);
}

void add_run_averages(nlohmann::json& j, const coupling::RunSummary& summary, bool free_body) {
  if (free_body) {
    // No terminal state was detected (the analysis was not made): the second half's mean is
    // given for what it is, and nothing is called terminal.
    j["terminal_velocity"] = nullptr;
    j["terminal_vertical_velocity"] = nullptr;
    j["late_mean_velocity"] = summary.terminal_velocity_si;
    j["late_mean_vertical_velocity"] = summary.terminal_vertical_velocity_si;
  } else {
    // The imposed speed of a towed body (0 for a fixed one), under its former key.
    j["terminal_velocity"] = summary.terminal_velocity_si;
    j["terminal_vertical_velocity"] = summary.terminal_vertical_velocity_si;
  }
  j["reynolds"] = summary.reynolds;
  j["drag_coefficient"] = summary.drag_coefficient;
  j["galileo"] = summary.galileo;
  j["regime"] = summary.regime;
  j["averaged_samples"] = summary.averaged_samples;
  j["mean_force"] = vector_json(summary.mean_force_si);
  j["mean_torque"] = vector_json(summary.mean_torque_si);
  j["mean_relative_flow"] = vector_json(summary.mean_relative_flow_si);
  if (summary.has_coefficients) {
    j["lift_coefficient"] = summary.lift_coefficient;
    j["lift_fluctuation_coefficient"] = summary.lift_fluctuation_coefficient;
    j["torque_coefficient"] = summary.torque_coefficient;
  }
}

// VTK output on its own schedule (run.vtk_interval; docs/vtk.md): DIR/vtk/fluid_NNNNNN.vti with the
// solid fraction, surface_NNNNNN.vtp, and the two .pvd collections ParaView plays as time series.
class VtkOutput {
 public:
  VtkOutput(const coupling::Simulation& sim, const fs::path& dir, double interval_si, io::VtkCompression compression)
      : sim_(sim),
        compression_(compression),
        dir_(dir / "vtk"),
        schedule_(interval_si),
        // Triangles about a cell wide: the surface at the resolution the fluid sees.
        surface_b_(body::surface_triangulation(*sim.setup().shape, sim.units().dx_si())),
        fluid_pvd_(dir_ / "fluid.pvd"),
        surface_pvd_(dir_ / "surface.pvd"),
        lead_(sim.communicator().rank() == 0) {
    if (!lead_) return;
    std::error_code error;
    fs::create_directories(dir_, error);
    if (error) throw InputError(fmt::format("-o: cannot create {}: {}", dir_.string(), error.message()));
  }

  void after_step(double t_si, double dt_si) {
    if (!schedule_.due(t_si, dt_si)) return;
    const std::string index = fmt::format("{:06d}", count_++);
    io::VtkOptions options;
    options.time_si = t_si;
    options.compression = compression_;
    const bool split = sim_.communicator().size() > 1;
    const fs::path fluid_file = dir_ / ("fluid_" + index + (split ? ".pvti" : ".vti"));
    const io::FieldScaling scaling = io::field_scaling(sim_.units(), sim_.frame().window_origin_si);
    if (split) {
      // A piece per rank and the .pvti that joins them (io/vtk_pieces.hpp).
      io::write_fluid_pieces(fluid_file, sim_, scaling, options);
      if (!lead_) return;
    } else {
      const std::vector<io::ScalarPointField> extra{
          {"solid_fraction", io::solid_fraction_field(sim_.fluid(), sim_.current_solid_cells())}};
      io::write_fluid_vti(fluid_file, sim_.fluid(), scaling, options, extra);
    }
    fluid_pvd_.add(t_si, fluid_file);
    const fs::path surface_file = dir_ / ("surface_" + index + ".vtp");
    io::write_surface_vtp(surface_file, surface_b_, io::body_snapshot(sim_.body()), options);
    surface_pvd_.add(t_si, surface_file);
  }

  VtkProgress progress() const { return {schedule_.next_index(), count_}; }
  /// Continues after a restart at t_si: the collections keep the entries up to t_si (later files
  /// are written again under the same names).
  void resume(const VtkProgress& progress, double t_si) {
    schedule_.set_next_index(progress.next_index);
    count_ = progress.files_written;
    fluid_pvd_ = io::PvdCollection::resume(fluid_pvd_.path(), t_si);
    surface_pvd_ = io::PvdCollection::resume(surface_pvd_.path(), t_si);
  }

 private:
  const coupling::Simulation& sim_;
  io::VtkCompression compression_;
  fs::path dir_;
  coupling::OutputSchedule schedule_;
  body::TriangleMesh surface_b_;
  io::PvdCollection fluid_pvd_;
  io::PvdCollection surface_pvd_;
  int count_ = 0;
  bool lead_;
};

// run.stop_at_terminal: the analysis' own detector and criteria (analysis/observables.hpp), fed
// with every output sample, so that the run stops where `settle analyze` finds the terminal state.
std::optional<analysis::TerminalStateDetector> terminal_detector(const io::CaseValues& values,
                                                                 const coupling::Simulation& sim, Console& console) {
  if (!values.boolean("run.stop_at_terminal")) return std::nullopt;
  if (sim.body().motion_kind() != body::MotionKind::free) {
    console.warning("run.stop_at_terminal: applies to free bodies only; this run goes to run.end_time");
    return std::nullopt;
  }
  const analysis::TerminalCriteria criteria = analysis::terminal_criteria(analysis::particle_properties(sim.setup()));
  if (!(criteria.response_time_si > 0.0)) {
    console.warning(
        "run.stop_at_terminal: the particle has no net weight, so no terminal state to detect; this run "
        "goes to run.end_time");
    return std::nullopt;
  }
  console.info(
      fmt::format("stops at the terminal state: window {:.4g} s ({:g} response times of {:.4g} s), "
                  "tolerance {:g}",
                  criteria.window_si(), criteria.window_response_times, criteria.response_time_si, criteria.tolerance));
  return analysis::TerminalStateDetector(criteria);
}

// Free bodies: the analysis of `settle analyze` (terminal state, observables, regime,
// correlations) on the series just written; true when it was added. The run itself succeeded: an
// analysis that cannot be made (too few samples, say) becomes a warning in summary.json rather
// than a failed run.
std::optional<analysis::Analysis> add_analysis(nlohmann::json& summary_document, const coupling::Simulation& sim,
                                               const fs::path& timeseries, Console& console) {
  if (sim.body().motion_kind() != body::MotionKind::free) return std::nullopt;
  try {
    analysis::Analysis result = analyse_timeseries(sim.setup(), timeseries, analysis::AnalysisOptions{});
    const nlohmann::ordered_json fields = analysis_summary_fields(sim.setup(), result);
    for (const auto& [key, value] : fields.items()) summary_document[key] = value;
    return result;
  } catch (const std::exception& e) {
    const std::string warning =
        fmt::format("analysis not made: {} (settle analyze can retry with other options)", e.what());
    console.warning(warning);
    summary_document["warnings"].push_back(warning);
    return std::nullopt;
  }
}

// The run's result in one line, calling a velocity terminal only when the analysis detected the
// terminal state (analysis::velocity_statement).
std::string result_line(const nlohmann::json& summary_document, const std::optional<analysis::Analysis>& analysed,
                        bool free_body) {
  if (!summary_document.contains("reynolds")) return {};
  // No drag coefficient (null) for a body in wall contact over the averaging window.
  const nlohmann::json& drag = summary_document["drag_coefficient"];
  const std::string groups =
      fmt::format("Re = {:.4g}, C_D = {}, regime {}", summary_document["reynolds"].get<double>(),
                  drag.is_number() ? fmt::format("{:.4g}", drag.get<double>()) : "none (wall contact)",
                  summary_document["regime"].get<std::string>());
  if (analysed) return fmt::format("{}; {}", analysis::velocity_statement(*analysed), groups);
  if (free_body)
    return fmt::format("not terminal (not analysed): mean velocity along g over the second half {:.5g} m/s; {}",
                       summary_document["late_mean_vertical_velocity"].get<double>(), groups);
  return groups;
}

void report_end(Console& console, const coupling::Simulation& sim, const coupling::RunResult& result,
                const std::string& result_text, const fs::path& dir) {
  console.info("wall time by sub-step of the coupled step:");
  for (const auto& [name, seconds] : sim.timers().entries())
    console.info(fmt::format("  {:<20} {:8.2f} s  {:5.1f}%", name, seconds,
                             result.wall_seconds > 0.0 ? 100.0 * seconds / result.wall_seconds : 0.0));
  if (!result_text.empty()) console.info(result_text);
  console.info(fmt::format("{} steps in {:.1f} s ({:.1f} MLUPS), {}; results in {}", result.steps, result.wall_seconds,
                           result.mlups, result.stop_reason, dir.string()));
}

// summary.json, the run's completion mark (file comment): the loop's figures, the reference the
// case names, and the results. Each result is computed once: for a free body by the analysis with
// the correlations, otherwise (or when the analysis cannot be made) from the loop's averages.
// Returns the run's result line for the console (result_line).
std::string write_summary(const io::CaseValues& values, const coupling::Simulation& sim,
                          const coupling::RunResult& result, const std::vector<std::string>& warnings,
                          const fs::path& dir, Console& console) {
  nlohmann::json summary_document = run_json(sim, result, warnings);
  // The published case the run reproduces, for `settle plot` (a key of validation/reference-data.json).
  if (values.has("run.reference")) summary_document["reference"] = values.string("run.reference");
  const bool free_body = sim.body().motion_kind() == body::MotionKind::free;
  const std::optional<analysis::Analysis> analysed =
      add_analysis(summary_document, sim, dir / "timeseries.csv", console);
  if (!analysed) {
    const coupling::RunSummary averages = coupling::summarise(sim, result);
    add_run_averages(summary_document, averages, free_body);
    add_lift_spectrum(summary_document, sim, result, averages);
  }
  write_file_atomically(dir / "summary.json", summary_document.dump(2) + "\n");
  return result_line(summary_document, analysed, free_body);
}

void run_case(const RunOptions& options) {
  check_flags(options);
  // --restart DIR: the case, its name and the directory come from DIR/checkpoint.bin (checked here,
  // before anything in DIR changes); relative paths in its resolved case are relative to DIR.
  check_restart_flags(options.restart_dir, options.case_file, options.overrides, options.output_dir);
  std::optional<RestartPoint> restart;
  if (!options.restart_dir.empty()) {
    restart.emplace(options.restart_dir);
    restart->apply_overrides(options.overrides);
  }
  const fs::path case_path = options.case_file;
  const io::CaseValues values = restart ? restart->case_values() : io::load_case(case_path, options.overrides);
  const std::string name = restart ? restart->case_name() : case_path.empty() ? "default" : case_path.stem().string();
  if (!restart && options.output_dir.empty()) check_results_folder_name(name, case_path);
  const fs::path base = restart             ? restart->run_dir()
                        : case_path.empty() ? fs::current_path()
                                            : fs::absolute(case_path).parent_path();
  // Under mpirun every rank runs this function on its block of the lattice (docs/parallel.md);
  // rank 0 alone speaks and writes.
  parallel::Communicator& world = parallel::world();
  const bool split = world.size() > 1, lead = world.rank() == 0;
  Console console(!lead             ? Verbosity::silent
                  : options.quiet   ? Verbosity::quiet
                  : options.verbose ? Verbosity::verbose
                                    : Verbosity::normal);
  std::vector<std::string> warnings = io::unsupported_key_warnings(values);
  if (restart) warnings.insert(warnings.end(), restart->warnings().begin(), restart->warnings().end());
  for (const auto& w : warnings) console.warning(w);

  coupling::SimulationSetup setup = io::simulation_setup(values, base, name);
  for (const std::string& note : setup.shape->notes()) console.info(note);  // a mesh reversed, its shells
  console.info(fmt::format("{}: {}", name, io::physical_properties_text(setup)));
  // Before the preflight: a unit slip would otherwise surface as a grid it refuses.
  for (std::string& w : io::plausibility_warnings(values, setup)) {
    console.warning(w);
    warnings.push_back(std::move(w));
  }
  const fs::path dir = restart                      ? restart->run_dir()
                       : options.output_dir.empty() ? fs::path("runs") / name
                                                    : fs::path(options.output_dir);
  io::PreflightOptions checks;
  checks.output_directory = dir;
  if (options.max_memory_given) checks.memory_budget_bytes = options.max_memory_gib * kBytesPerGiB;
  const io::PreflightReport report = io::preflight(setup, checks);
  for (const auto& w : report.warnings) console.warning(w);
  warnings.insert(warnings.end(), report.warnings.begin(), report.warnings.end());
  if (auto advice =
          missing_checkpoint_advice(values.real("run.checkpoint_interval"), values.real("run.checkpoint_wall_interval"),
                                    report.cell_count * report.steps)) {
    console.warning(*advice);
    warnings.push_back(*advice);
  }
  const std::optional<TerminalOutlook> outlook = terminal_outlook(setup);
  if (outlook && outlook->warning) {
    console.warning(*outlook->warning);
    warnings.push_back(*outlook->warning);
  }
  survey_run_directory(dir, restart.has_value(), options.overwrite, values);  // refuses before anything is touched
  console.info(fmt::format("{}: preflight passed: {}", name, report.summary()));
  if (outlook) console.info(fmt::format("{}: {}", name, outlook->line));
  if (options.dry_run) {
    if (options.threads > 0) omp_set_num_threads(options.threads);
    if (lead) std::fputs(run_plan_text(setup, report).c_str(), stdout);
    return;
  }

  coupling::Simulation sim(std::move(setup), world);
  if (restart) restart->restore(sim);
  if (options.threads > 0)
    omp_set_num_threads(options.threads);
  else if (restart)
    omp_set_num_threads(restart->threads());  // as the run had: bit for bit
  const auto& d = sim.derived();
  const auto& p = sim.plan();
  console.info(
      fmt::format("{}: dx = {:.4g} m, dt = {:.4g} s, tau = {:.4f}, Ma = {:.3g}, Re = {:.4g}, Ga = {:.4g}, "
                  "grid {}x{}x{}, {}, {} {}, {} threads",
                  name, p.units.dx_si(), p.units.dt_si(), p.units.tau(), p.mach, p.reynolds, p.galileo, d.cells[0],
                  d.cells[1], d.cells[2], operator_text(sim.setup(), p), d.surface_element_count,
                  sim.coupling().surface_element_name(), omp_get_max_threads()));

  console.detail("the converter's choices (also at the end of case.resolved.toml):" + derived_block(sim));
  std::unique_ptr<RunDirectoryLock> lock;
  std::string resolved_case;
  std::vector<InputFileFingerprint> inputs;  // the files a restart reads again
  std::optional<io::TimeseriesWriter> timeseries;
  std::exception_ptr failed;
  if (lead) {
    try {
      lock = prepare_output_directory(dir, restart.has_value(), options.overwrite, values);
      console.attach_log(open_run_log(dir, restart.has_value()));
      if (restart) {
        resolved_case = restart->resolved_case();
        inputs = restart->inputs();
      } else {
        const io::CaseValues resolved = with_mesh_copied_into(values, base, dir);
        resolved_case =
            fmt::format("# written by settle {} (commit {})\n", settle::version_string, settle::commit_string) +
            io::write_resolved_toml(resolved) + derived_block(sim);
        inputs = input_files_of(resolved, dir);
      }
      write_file_atomically(dir / "case.resolved.toml", resolved_case);
      timeseries.emplace(restart
                             ? io::TimeseriesWriter::continue_at(dir / "timeseries.csv", restart->timeseries_bytes())
                             : io::TimeseriesWriter(dir / "timeseries.csv"));
    } catch (...) {
      failed = std::current_exception();
    }
  }
  // The other ranks learn whether rank 0 could prepare the directory before the first step's
  // messages, which would otherwise wait for it forever.
  if (split && parallel::sum_in_rank_order(world, {failed ? 1.0 : 0.0})[0] > 0.0 && !failed) {
    throw InputError("the output directory could not be prepared (rank 0 says why)");
  }
  if (failed) std::rethrow_exception(failed);

  coupling::RunCallbacks callbacks;
  callbacks.on_sample = [&](const coupling::Sample& s) {
    if (timeseries) timeseries->write(s);
  };
  callbacks.on_progress = [&console](const std::string& line) { console.progress(line); };
  std::optional<analysis::TerminalStateDetector> terminal = terminal_detector(values, sim, console);
  if (terminal)
    callbacks.stop_after_sample = [&terminal, &sim](const coupling::Sample& s) {
      // As the analysis, the detector sees the free motion only (after particle.release_time).
      if (s.t_si < analysis::released_from(sim.setup().release_time_si)) return std::string();
      terminal->add(s.t_si, s.velocity_si);
      return terminal->reached() ? std::string("terminal_state") : std::string();
    };
  // A restart feeds the detector the samples before the checkpoint, as the run did.
  if (terminal && restart)
    for (const coupling::Sample& s : restart->loop().samples)
      if (s.t_si >= analysis::released_from(sim.setup().release_time_si)) terminal->add(s.t_si, s.velocity_si);
  std::optional<VtkOutput> vtk;
  if (values.real("run.vtk_interval") > 0.0) {
    vtk.emplace(sim, dir, values.real("run.vtk_interval"),
                values.string("run.vtk_compression") == "zlib" ? io::VtkCompression::zlib : io::VtkCompression::none);
    if (restart) vtk->resume(restart->vtk(), restart->time_si());
    callbacks.after_step = [&vtk](double t_si, double dt_si) { vtk->after_step(t_si, dt_si); };
  }
  RunCheckpoints checkpoints(dir, resolved_case, name, std::move(inputs),
                             restart ? restart->series() : SeriesChecksum{});
  callbacks.checkpoint_interval_si = values.real("run.checkpoint_interval");
  callbacks.checkpoint_wall_interval_s = values.real("run.checkpoint_wall_interval");
  std::int64_t last_checkpoint_step = -1;
  callbacks.checkpoint_due = [&](const coupling::RunStart& loop) {
    checkpoints.write(sim, loop, vtk ? vtk->progress() : VtkProgress{});
    last_checkpoint_step = loop.step;
  };
  callbacks.checkpoint_at_end = true;
  const InterruptSignals signals;
  callbacks.interrupted = [&signals] { return signals.raised(); };
  if (restart)
    console.info(fmt::format("{}: continuing from {} at t = {:.6g} s (step {})", name, restart->file().string(),
                             restart->time_si(), restart->loop().step));
  coupling::RunResult result;
  try {
    result = coupling::run(sim, callbacks, restart ? restart->take_loop_state() : coupling::RunStart{},
                           console.progress_interval_s());
  } catch (const std::exception& e) {
    console.warning(
        fmt::format("the run failed after {} steps; {} holds the rows written until then, and no "
                    "summary.json was written",
                    sim.steps(), (dir / "timeseries.csv").string()));
    console.log_only(fmt::format("error: {}", e.what()));  // main() prints it on stderr
    throw;
  }
  if (result.stop_reason == "interrupted") {
    const RunInterrupted error =
        interrupted_error(signals.signal_number_seen_by_any(sim.communicator()), result, dir, checkpoints.file());
    console.log_only(error.what());  // main() prints it on stderr
    throw error;
  }
  if (!lead) return;
  const std::string result_text = write_summary(values, sim, result, warnings, dir, console);
  report_end(console, sim, result, result_text, dir);
  if (last_checkpoint_step == result.steps)
    console.info(
        fmt::format("{}: checkpoint at the end, t = {:.6g} s ({}): settle run --restart {} --set "
                    "run.end_time=T continues from there",
                    name, result.simulated_time_si, checkpoints.file().string(), dir.string()));
}

}  // namespace

void add_run_command(CLI::App& app) {
  auto options = std::make_shared<RunOptions>();
  CLI::App* run = app.add_subcommand("run", "Run a case (without CASE: the built-in default case)");
  CLI::Option* case_file = run->add_option("case", options->case_file, "case file (TOML, SI units)");
  run->add_option("-o,--output", options->output_dir, "output directory (default ./runs/<case name>)");
  run->add_flag("--overwrite", options->overwrite,
                "replace another run's results in the output directory (only the files settle wrote are removed); "
                "without it such a directory is refused");
  run->add_option("--set", options->overrides, "override a case key, e.g. --set run.end_time=0.1 (repeatable)")
      ->take_all()
      ->allow_extra_args(false);
  run->add_option("--threads", options->threads, "OpenMP threads (default: all)");
  run->add_flag("-q,--quiet", options->quiet, "print warnings and errors only");
  run->add_flag("--dry-run", options->dry_run,
                "check the case and print its plan (grid, time step, steps, memory, an estimate of the wall time) "
                "without running it or writing anything");
  run->add_flag("-v,--verbose", options->verbose,
                "also print every derived value of the unit conversion; progress more often in a log");
  CLI::Option* max_memory = run->add_option(
      "--max-memory", options->max_memory_gib,
      "memory budget in GiB for the preflight check (default: MemAvailable of /proc/meminfo); a case whose estimate "
      "exceeds it is refused before anything is allocated");
  CLI::Option* restart =
      run->add_option("--restart", options->restart_dir,
                      "continue the run in DIR from DIR/checkpoint.bin (written every run.checkpoint_interval and on "
                      "SIGINT/SIGTERM); takes no case file or -o, and --set only for run.end_time (a later end)")
          ->type_name("DIR");
  run->callback([options, max_memory, case_file, restart] {
    options->max_memory_given = max_memory->count() > 0;
    // An empty argument (an unset shell variable: settle run "$CASE") must not mean "none given",
    // which runs the built-in default case (or a fresh run instead of a restart).
    if (case_file->count() > 0 && options->case_file.empty())
      throw InputError(
          "CASE: the case file's path is empty (an unset shell variable?); give a case file, or leave CASE out "
          "for the built-in default case");
    if (restart->count() > 0 && options->restart_dir.empty())
      throw InputError("--restart: the run directory's path is empty (an unset shell variable?)");
    run_case(*options);
  });
}

}  // namespace settle::app
