// `settle analyze RUN_DIR [--json] [--window N] [--tolerance TOL] [--response-time S]`:
// recomputes the analysis of a finished free-settling run from its files
// (timeseries.csv, case.resolved.toml, summary.json), merges the analysis fields into
// summary.json (every other field kept; temporary file and rename) and prints a short report,
// or the analysis fields as JSON with --json. A run without summary.json (failed, stopped) is
// analysed as far as its series goes, and nothing is written. Definitions: docs/analysis.md.
#include <cmath>
#include <filesystem>
#include <fstream>
#include <iostream>
#include <memory>
#include <optional>
#include <sstream>
#include <string>

#include <fmt/core.h>
#include <nlohmann/json.hpp>

#include "analysis/observables.hpp"
#include "analysis/timeseries.hpp"
#include "app/commands.hpp"
#include "app/flag_values.hpp"
#include "app/summary_fields.hpp"
#include "common/atomic_file.hpp"
#include "common/error.hpp"
#include "coupling/simulation.hpp"
#include "io/case.hpp"
#include "io/case_schema.hpp"
#include "io/output_files.hpp"
#include "io/schema.hpp"

namespace settle::app {
namespace {

namespace fs = std::filesystem;
using json = nlohmann::ordered_json;

struct AnalyzeOptions {
  std::string run_dir;
  bool json_output = false;
  std::optional<std::string> window, tolerance, response_time;
};

analysis::AnalysisOptions analysis_options(const AnalyzeOptions& o) {
  analysis::AnalysisOptions options;
  if (o.window) {
    options.window_response_times = parse_number(*o.window, "--window");
    if (!(options.window_response_times > 0.0))
      throw InputError(fmt::format("--window: must be > 0 (response times), got {}", *o.window));
  }
  if (o.tolerance) {
    options.tolerance = parse_number(*o.tolerance, "--tolerance");
    if (!(options.tolerance > 0.0 && options.tolerance < 1.0))
      throw InputError(fmt::format("--tolerance: must be in (0, 1), got {}", *o.tolerance));
  }
  if (o.response_time) {
    options.response_time_si = parse_number(*o.response_time, "--response-time");
    if (!(*options.response_time_si > 0.0))
      throw InputError(fmt::format("--response-time: must be > 0 (s), got {}", *o.response_time));
  }
  return options;
}

fs::path required_file(const fs::path& dir, const char* name) {
  const fs::path path = dir / name;
  if (!fs::is_regular_file(path))
    throw InputError(fmt::format("{}: missing (RUN_DIR must be an output directory of settle run)", path.string()));
  return path;
}

json read_summary(const fs::path& path) {
  std::ifstream in(path);
  if (!in) throw InputError(fmt::format("{}: cannot open the file", path.string()));
  json summary;
  try {
    summary = json::parse(in);
  } catch (const json::parse_error& e) {
    throw InputError(fmt::format("{}: not valid JSON: {}", path.string(), e.what()));
  }
  if (!summary.is_object()) throw InputError(fmt::format("{}: expected a JSON object", path.string()));
  return summary;
}

std::string read_text(const fs::path& path) {
  std::ifstream in(path);
  if (!in) throw InputError(fmt::format("{}: cannot open the file", path.string()));
  std::stringstream text;
  text << in.rdbuf();
  return text.str();
}

coupling::SimulationSetup run_setup(const fs::path& dir, const json& summary) {
  const fs::path case_path = required_file(dir, "case.resolved.toml");
  const std::string name = summary.contains("case") && summary["case"].is_string() ? summary["case"].get<std::string>()
                                                                                   : dir.filename().string();
  const io::CaseValues values = io::parse_case(io::case_schema(), read_text(case_path), case_path.string());
  // Relative mesh paths of the resolved case are taken relative to the run directory.
  coupling::SimulationSetup setup = io::simulation_setup(values, dir, name);
  if (setup.motion != body::MotionKind::free)
    throw InputError(
        fmt::format("{}: particle.motion is not \"free\": settle analyze applies to free-settling bodies "
                    "(towed and fixed runs carry their force coefficients in summary.json)",
                    case_path.string()));
  return setup;
}

std::string optional_text(const std::optional<double>& value, const char* format_unit) {
  return value ? fmt::format(fmt::runtime(format_unit), *value) : std::string("-");
}

void print_report(const fs::path& dir, const analysis::Analysis& a, std::ostream& out) {
  out << fmt::format("settle analyze: {}\n", dir.string());
  if (a.terminal.reached)
    out << fmt::format(
        "  terminal state   reached at t = {:.4g} s (detected at {:.4g} s; window {:.4g} s = {:.3g} "
        "response times of {:.4g} s, tolerance {:.3g})\n",
        a.terminal.terminal_time_si, a.terminal.detected_at_si, a.criteria.window_si(),
        a.criteria.window_response_times, a.criteria.response_time_si, a.criteria.tolerance);
  else
    out << fmt::format(
        "  terminal state   not reached (window {:.4g} s = {:.3g} response times of {:.4g} s, "
        "tolerance {:.3g})\n",
        a.criteria.window_si(), a.criteria.window_response_times, a.criteria.response_time_si, a.criteria.tolerance);
  if (a.time_to_95_percent_si)
    out << fmt::format("  approach         95% of the terminal vertical velocity at t = {:.4g} s after the start\n",
                       *a.time_to_95_percent_si);
  if (a.fitted_time_to_95_percent_si)
    out << fmt::format(
        "  exponential fit  u = {:.5g} m/s (1 - exp(-3 t / {:.4g} s)) over the whole record, rms residual {:.3g} "
        "m/s\n",
        *a.fitted_terminal_velocity_si, *a.fitted_time_to_95_percent_si, *a.fit_rms_residual_si);
  out << fmt::format("  averaged over    t = {:.4g} .. {:.4g} s ({} samples, {})\n", a.window_start_si, a.window_end_si,
                     a.window_samples, a.averaged_over_terminal_window ? "terminal window" : "second half of the run");
  out << fmt::format("  velocity         |U| = {:.5g} m/s, along g {:.5g} m/s, path {:.3g} deg from vertical\n",
                     a.terminal_speed_si, a.vertical_velocity_si, a.path_angle_deg);
  out << fmt::format("  result           {}\n", analysis::velocity_statement(a));
  if (a.drift_azimuth_deg)
    out << fmt::format(
        "  drift            azimuth {:.4g} deg (from x, counter-clockwise from above), turning {} deg/s\n",
        *a.drift_azimuth_deg, optional_text(a.drift_turn_rate_deg_per_s, "{:.3g}"));
  out << fmt::format(
      "  groups           Re = {:.4g}, Ga = {:.4g}, Ar = {:.4g}, St = {:.4g}, rho_p/rho_f = {:.4g}, "
      "I* = {}\n",
      a.reynolds, a.galileo, a.archimedes, a.stokes_number, a.density_ratio,
      optional_text(a.dimensionless_inertia, "{:.4g}"));
  if (a.wall_contact_samples > 0)
    out << "  drag             none: the particle touches a wall in the window (warning below)\n";
  else
    out << fmt::format(
        "  drag             C_D = {:.4g} (d_eq), {} (projected area {} m^2), {:.4g} from the mean force\n",
        a.drag_coefficient, optional_text(a.drag_coefficient_projected_area, "{:.4g}"),
        optional_text(a.projected_area_si, "{:.4g}"), a.drag_coefficient_from_force);
  out << fmt::format("  lateral motion   amplitude {:.3g} m/s, f = {} Hz, Sr = {}\n", a.lateral_amplitude_si,
                     optional_text(a.lateral_frequency_hz, "{:.4g}"), optional_text(a.lateral_strouhal, "{:.3g}"));
  if (a.axis.kind != analysis::AxisKind::none)
    out << fmt::format("  tilt of the axis mean {:.3g} deg, mean axis {} deg, amplitude {} deg, f = {} Hz\n",
                       a.tilt_mean_deg, optional_text(a.mean_axis_tilt_deg, "{:.3g}"),
                       optional_text(a.tilt_amplitude_deg, "{:.3g}"), optional_text(a.tilt_frequency_hz, "{:.4g}"));
  if (a.regime_window_start_si > a.window_start_si)
    out << fmt::format(
        "  regime judged    over t = {:.4g} .. {:.4g} s ({} samples), after an oscillation that dies away over the "
        "earlier part\n",
        a.regime_window_start_si, a.window_end_si, a.regime_window_samples);
  out << fmt::format("  regime           {}: {}\n", analysis::regime_name(a.regime.regime), a.regime.reason);
  for (const std::string& warning : a.warnings) out << fmt::format("  warning: {}\n", warning);
}

void analyze(const AnalyzeOptions& options) {
  const analysis::AnalysisOptions analysis_opts = analysis_options(options);
  const fs::path dir = options.run_dir;
  if (!fs::is_directory(dir)) throw InputError(fmt::format("{}: not a directory", dir.string()));
  // Everything is read and computed before summary.json is touched: an error writes nothing.
  const fs::path series_path = required_file(dir, "timeseries.csv");
  // A run that failed or was stopped has no summary.json (its completion mark): its rows are
  // analysed as they are, and no summary.json is written, which would mark the run finished.
  const fs::path summary_path = dir / "summary.json";
  const bool finished = fs::exists(summary_path);
  if (!finished)
    std::cerr << fmt::format(
        "settle analyze: warning: {}: missing: the run did not finish (or still runs); its time series is analysed "
        "as far as it goes, and no summary.json is written\n",
        summary_path.string());
  json summary = finished ? read_summary(required_file(dir, "summary.json")) : json::object();
  const coupling::SimulationSetup setup = run_setup(dir, summary);
  const analysis::Analysis result = analyse_timeseries(setup, series_path, analysis_opts);

  const json fields = analysis_summary_fields(setup, result);
  for (const auto& [key, value] : fields.items()) summary[key] = value;
  if (finished) write_file_atomically(summary_path, summary.dump(2) + "\n");
  if (options.json_output)
    std::cout << fields.dump(2) << "\n";
  else
    print_report(dir, result, std::cout);
}

}  // namespace

void add_analyze_command(CLI::App& app) {
  auto options = std::make_shared<AnalyzeOptions>();
  CLI::App* cmd = app.add_subcommand(
      "analyze", "Terminal state, observables and regime of a free-settling run; updates RUN_DIR/summary.json");
  cmd->add_option("RUN_DIR", options->run_dir, "output directory of settle run")->required();
  cmd->add_flag("--json", options->json_output, "print the analysis fields as JSON instead of the report");
  cmd->add_option("--window", options->window, "terminal-state window in particle response times (default 5)")
      ->type_name("N");
  cmd->add_option("--tolerance", options->tolerance,
                  "largest relative change of the window mean velocity at the terminal state (default 0.01)")
      ->type_name("TOL");
  cmd->add_option("--response-time", options->response_time,
                  "particle response time in s (default: estimated from the Schiller-Naumann terminal speed)")
      ->type_name("S");
  cmd->callback([options] { analyze(*options); });
}

}  // namespace settle::app
