// `settle run [CASE.toml] [-o DIR] [--set key=value]... [--threads N]` (DESIGN.md section 3):
// loads and checks the case, converts units, runs the coupled simulation and writes
// DIR/timeseries.csv, DIR/summary.json and DIR/case.resolved.toml (docs/coupling.md).
#include <omp.h>

#include <cstdio>
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
#include "lbm/config.hpp"

namespace settle::app {
namespace {

namespace fs = std::filesystem;

struct RunOptions {
  std::string case_file;
  std::string output_dir;
  std::vector<std::string> overrides;
  int threads = 0;  ///< 0: OpenMP's default
};

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
  if (options.threads < 0) throw InputError(fmt::format("--threads: must be >= 1, got {}", options.threads));
  const fs::path case_path = options.case_file;
  const io::CaseValues values = io::load_case(case_path, options.overrides);
  const std::string name = case_path.empty() ? "default" : case_path.stem().string();
  const fs::path base = case_path.empty() ? fs::current_path() : fs::absolute(case_path).parent_path();
  const std::vector<std::string> warnings = io::unsupported_key_warnings(values);
  for (const auto& w : warnings) fmt::print(stderr, "settle run: warning: {}\n", w);

  coupling::Simulation sim(io::simulation_setup(values, base, name));
  if (options.threads > 0) omp_set_num_threads(options.threads);
  const auto& d = sim.derived();
  fmt::print(stderr,
             "settle run: {}: dx = {:.4g} m, dt = {:.4g} s, tau = {:.4f}, Ma = {:.3g}, Re = {:.4g}, Ga = {:.4g}, "
             "grid {}x{}x{}, {} markers, {} threads\n",
             name, d.dx_si, d.dt_si, d.tau, d.mach, d.reynolds, d.galileo, d.cells[0], d.cells[1], d.cells[2],
             d.marker_count, omp_get_max_threads());

  const fs::path dir = options.output_dir.empty() ? fs::path("runs") / name : fs::path(options.output_dir);
  std::error_code error;
  fs::create_directories(dir, error);
  if (error) throw InputError(fmt::format("-o: cannot create the directory {}: {}", dir.string(), error.message()));
  io::write_file_atomically(dir / "case.resolved.toml", io::write_resolved_toml(values) + derived_block(sim));

  io::TimeseriesWriter timeseries(dir / "timeseries.csv");
  coupling::RunCallbacks callbacks;
  callbacks.on_sample = [&](const coupling::Sample& s) { timeseries.write(s); };
  callbacks.on_progress = [](const std::string& line) { fmt::print(stderr, "settle run: {}\n", line); };
  const coupling::RunResult result = coupling::run(sim, callbacks);
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
  run->callback([options] { run_case(*options); });
}

}  // namespace settle::app
