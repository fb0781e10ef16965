// `settle run [CASE.toml] [-o DIR] [--set key=value]... [--threads N] [--max-memory GIB]`
// (DESIGN.md section 3): loads and checks the case, runs the preflight checks (io/preflight.hpp,
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
#include <string>
#include <vector>

#include <fmt/core.h>
#include <nlohmann/json.hpp>

#include "app/commands.hpp"
#include "common/error.hpp"
#include "coupling/runner.hpp"
#include "coupling/simulation.hpp"
#include "io/case.hpp"
#include "io/output_files.hpp"
#include "io/preflight.hpp"
#include "lbm/config.hpp"

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
};

constexpr double kBytesPerGiB = 1024.0 * 1024.0 * 1024.0;

void check_flags(const RunOptions& options) {
  if (options.threads < 0)
    throw InputError(fmt::format("--threads: must be >= 1 (or 0 for OpenMP's default), got {}", options.threads));
  if (options.max_memory_given && !(std::isfinite(options.max_memory_gib) && options.max_memory_gib > 0.0))
    throw InputError(fmt::format("--max-memory: must be a finite number of GiB > 0, got {}", options.max_memory_gib));
}

// Called only after every check passed and the grid is allocated (file comment).
void prepare_output_directory(const fs::path& dir) {
  std::error_code error;
  fs::create_directories(dir, error);
  if (error) throw InputError(fmt::format("-o: cannot create the directory {}: {}", dir.string(), error.message()));
  fs::remove(dir / "summary.json", error);
  if (error)
    throw InputError(fmt::format("-o: cannot remove the earlier run's {}: {}", (dir / "summary.json").string(),
                                 error.message()));
}

std::string motion_name(body::MotionKind kind) {
  switch (kind) {
    case body::MotionKind::towed: return "towed";
    case body::MotionKind::fixed: return "fixed";
    case body::MotionKind::free: break;
  }
  return "free";
}

// The converter's choices, as TOML comments after the resolved keys: the file stays a valid
// case (the schema has no [derived] keys), and a reader sees what the run used.
std::string derived_block(const coupling::Simulation& sim) {
  const auto& d = sim.derived();
  return fmt::format(
      "\n# [derived] chosen by settle run (not read back):\n"
      "# dx = {:.9g}  # m, d_eq / cells_per_diameter\n"
      "# dt = {:.9g}  # s\n"
      "# tau = {:.9g}\n"
      "# cells = [{}, {}, {}]\n"
      "# equivalent_diameter = {:.9g}  # m\n"
      "# expected_speed = {:.9g}  # m/s, the speed dt was chosen for\n"
      "# mach = {:.6g}  # of the expected speed\n"
      "# reynolds = {:.6g}  # expected speed x d_eq / nu\n"
      "# galileo = {:.6g}\n"
      "# markers = {}\n",
      d.dx_si, d.dt_si, d.tau, d.cells[0], d.cells[1], d.cells[2], d.equivalent_diameter_si, d.expected_speed_si,
      d.mach, d.reynolds, d.galileo, d.marker_count);
}

nlohmann::json vector_json(const Eigen::Vector3d& v) { return nlohmann::json::array({v[0], v[1], v[2]}); }

nlohmann::json summary_json(const coupling::Simulation& sim, const coupling::RunResult& result,
                            const coupling::RunSummary& summary, const std::vector<std::string>& warnings) {
  const auto& d = sim.derived();
  nlohmann::json j;
  j["case"] = sim.setup().name;
  j["motion"] = motion_name(sim.body().motion_kind());
  j["terminal_velocity"] = summary.terminal_velocity_si;
  j["terminal_vertical_velocity"] = summary.terminal_vertical_velocity_si;
  j["reynolds"] = summary.reynolds;
  j["drag_coefficient"] = summary.drag_coefficient;
  j["galileo"] = summary.galileo;
  j["regime"] = summary.regime;
  j["cells"] = d.cells[0] * static_cast<long long>(d.cells[1]) * d.cells[2];
  j["grid"] = {d.cells[0], d.cells[1], d.cells[2]};
  j["dx"] = d.dx_si;
  j["dt"] = d.dt_si;
  j["tau"] = d.tau;
  j["mach"] = d.mach;
  j["equivalent_diameter"] = d.equivalent_diameter_si;
  j["markers"] = d.marker_count;
  j["steps"] = result.steps;
  j["simulated_time"] = result.simulated_time_si;
  j["stop_reason"] = result.stop_reason;
  j["wall_seconds"] = result.wall_seconds;
  j["mlups"] = result.mlups;
  nlohmann::json timing = nlohmann::json::object();
  for (const auto& [name, seconds] : sim.timers().entries()) timing[name] = seconds;
  j["timing"] = timing;
  j["averaged_samples"] = summary.averaged_samples;
  j["mean_force"] = vector_json(summary.mean_force_si);
  j["mean_torque"] = vector_json(summary.mean_torque_si);
  j["mean_relative_flow"] = vector_json(summary.mean_relative_flow_si);
  if (summary.has_coefficients) {
    j["lift_coefficient"] = summary.lift_coefficient;
    j["torque_coefficient"] = summary.torque_coefficient;
  }
  j["warnings"] = warnings;
  return j;
}

void run_case(const RunOptions& options) {
  check_flags(options);
  const fs::path case_path = options.case_file;
  const io::CaseValues values = io::load_case(case_path, options.overrides);
  const std::string name = case_path.empty() ? "default" : case_path.stem().string();
  const fs::path base = case_path.empty() ? fs::current_path() : fs::absolute(case_path).parent_path();
  std::vector<std::string> warnings = io::unsupported_key_warnings(values);
  for (const auto& w : warnings) fmt::print(stderr, "settle run: warning: {}\n", w);

  coupling::SimulationSetup setup = io::simulation_setup(values, base, name);
  const fs::path dir = options.output_dir.empty() ? fs::path("runs") / name : fs::path(options.output_dir);
  io::PreflightOptions checks;
  checks.output_directory = dir;
  if (options.max_memory_given) checks.memory_budget_bytes = options.max_memory_gib * kBytesPerGiB;
  const io::PreflightReport report = io::preflight(setup, checks);
  for (const auto& w : report.warnings) fmt::print(stderr, "settle run: warning: {}\n", w);
  warnings.insert(warnings.end(), report.warnings.begin(), report.warnings.end());
  fmt::print(stderr, "settle run: {}: preflight passed: {}\n", name, report.summary());

  coupling::Simulation sim(std::move(setup));
  if (options.threads > 0) omp_set_num_threads(options.threads);
  const auto& d = sim.derived();
  fmt::print(stderr,
             "settle run: {}: dx = {:.4g} m, dt = {:.4g} s, tau = {:.4f}, Ma = {:.3g}, Re = {:.4g}, Ga = {:.4g}, "
             "grid {}x{}x{}, {} markers, {} threads\n",
             name, d.dx_si, d.dt_si, d.tau, d.mach, d.reynolds, d.galileo, d.cells[0], d.cells[1], d.cells[2],
             d.marker_count, omp_get_max_threads());

  prepare_output_directory(dir);
  io::write_file_atomically(dir / "case.resolved.toml", io::write_resolved_toml(values) + derived_block(sim));

  io::TimeseriesWriter timeseries(dir / "timeseries.csv");
  coupling::RunCallbacks callbacks;
  callbacks.on_sample = [&](const coupling::Sample& s) { timeseries.write(s); };
  callbacks.on_progress = [](const std::string& line) { fmt::print(stderr, "settle run: {}\n", line); };
  coupling::RunResult result;
  try {
    result = coupling::run(sim, callbacks);
  } catch (const std::exception&) {
    fmt::print(stderr, "settle run: the run failed after {} steps; {} holds the rows written until then, and no "
               "summary.json was written\n", sim.steps(), (dir / "timeseries.csv").string());
    throw;
  }
  const coupling::RunSummary summary = coupling::summarise(sim, result);
  io::write_file_atomically(dir / "summary.json", summary_json(sim, result, summary, warnings).dump(2) + "\n");
  fmt::print(stderr, "settle run: {} steps in {:.1f} s ({:.1f} MLUPS), {}; results in {}\n", result.steps,
             result.wall_seconds, result.mlups, result.stop_reason, dir.string());
}

}  // namespace

void add_run_command(CLI::App& app) {
  auto options = std::make_shared<RunOptions>();
  CLI::App* run = app.add_subcommand("run", "Run a case (without CASE: the built-in default case)");
  run->add_option("case", options->case_file, "case file (TOML, SI units)");
  run->add_option("-o,--output", options->output_dir, "output directory (default ./runs/<case name>)");
  run->add_option("--set", options->overrides, "override a case key, e.g. --set run.end_time=0.1 (repeatable)")
      ->take_all()
      ->allow_extra_args(false);
  run->add_option("--threads", options->threads, "OpenMP threads (default: all)");
  CLI::Option* max_memory = run->add_option(
      "--max-memory", options->max_memory_gib,
      "memory budget in GiB for the preflight check (default: MemAvailable of /proc/meminfo); a case whose estimate "
      "exceeds it is refused before anything is allocated");
  run->callback([options, max_memory] {
    options->max_memory_given = max_memory->count() > 0;
    run_case(*options);
  });
}

}  // namespace settle::app
