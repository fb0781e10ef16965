#include "app/run_plan.hpp"

#include <omp.h>

#include <chrono>

#include <fmt/core.h>

#include "analysis/observables.hpp"
#include "analysis/terminal_state.hpp"
#include "app/output_values.hpp"
#include "coupling/body_coupling.hpp"
#include "lbm/config.hpp"
#include "lbm/solver.hpp"

namespace settle::app {
namespace {

// Throughput (cell updates per second) of the fluid kernel alone with the case's lattice,
// collision model and precision, on a periodic grid of 96^3 cells: larger than the caches, so
// bound by memory as a real case is. Ten timed steps after two that touch every page.
double measured_kernel_updates_per_second(const coupling::SimulationSetup& s, const coupling::CasePlan& plan) {
  constexpr int kSide = 96, kWarmSteps = 2, kTimedSteps = 10;
  lbm::SolverConfig config;
  config.lattice = s.lattice;
  config.collision = s.collision;
  config.subgrid = plan.subgrid_model;
  config.smagorinsky_constant = s.smagorinsky_constant;
  config.precision = s.precision;
  config.nx = config.ny = config.nz = kSide;
  config.boundaries = {lbm::Boundary::periodic, lbm::Boundary::periodic, lbm::Boundary::periodic};
  config.tau = plan.units.tau();
  const auto solver = lbm::make_solver(config);
  solver->initialise([](int, int, int) { return lbm::CellState{}; });
  solver->run(kWarmSteps);
  const auto start = std::chrono::steady_clock::now();
  solver->run(kTimedSteps);
  const double seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
  return static_cast<double>(kSide) * kSide * kSide * kTimedSteps / seconds;
}

std::string duration_text(double seconds) {
  if (seconds < 120.0) return fmt::format("{:.0f} s", seconds);
  if (seconds < 7200.0) return fmt::format("{:.0f} min", seconds / 60.0);
  return fmt::format("{:.1f} h", seconds / 3600.0);
}

}  // namespace

std::string operator_text(const coupling::SimulationSetup& s, const coupling::CasePlan& p) {
  if (p.subgrid_model == lbm::SubgridModel::none) return lbm::to_string(s.collision);
  const std::string reason =
      s.subgrid_model == lbm::SubgridModel::automatic
          ? fmt::format(", auto: cell Re {:.1f} > {:g}", p.cell_reynolds, lbm::kTrtStableCellReynolds)
          : "";
  return fmt::format("{} + {} (C_S {:g}{})", lbm::to_string(s.collision), lbm::to_string(p.subgrid_model),
                     s.smagorinsky_constant, reason);
}

std::optional<TerminalOutlook> terminal_outlook(const coupling::SimulationSetup& s) {
  if (s.motion != body::MotionKind::free) return std::nullopt;
  // The criteria the analysis and run.stop_at_terminal use, with their default window and tolerance.
  const analysis::TerminalCriteria criteria = analysis::terminal_criteria(analysis::particle_properties(s));
  if (!(criteria.response_time_si > 0.0)) return std::nullopt;
  const double earliest_si = s.release_time_si + criteria.earliest_detection_si();
  TerminalOutlook outlook;
  outlook.line =
      fmt::format("terminal state: detectable from t = {:.4g} s on (two windows of {:g} response times of {:.4g} s{})",
                  earliest_si, criteria.window_response_times, criteria.response_time_si,
                  s.release_time_si > 0.0 ? fmt::format(" after the release at {:.4g} s", s.release_time_si) : "");
  if (s.end_time_si < earliest_si)
    outlook.warning = fmt::format(
        "run.end_time: {:.4g} s is too short to detect a terminal state, which needs t >= {:.4g} s (two windows of "
        "{:g} "
        "response times of {:.4g} s); the run will report the mean of its second half, not a terminal velocity; "
        "raise run.end_time above {:.4g} s",
        s.end_time_si, earliest_si, criteria.window_response_times, criteria.response_time_si, earliest_si);
  return outlook;
}

std::string run_plan_text(const coupling::SimulationSetup& s, const io::PreflightReport& r) {
  const coupling::CasePlan& p = r.plan;
  const double rate = measured_kernel_updates_per_second(s, p);
  const double wall_s = r.steps * r.cell_count / rate;
  std::string text = fmt::format("plan of {} (--dry-run: nothing was run or written)\n", s.name);
  text += fmt::format("  units     dx = {:.4g} m ({:g} cells per d_eq = {:.4g} m), dt = {:.4g} s, tau = {:.4f}\n",
                      p.units.dx_si(), s.cells_per_diameter, p.equivalent_diameter_si, p.units.dt_si(), p.units.tau());
  text += fmt::format("  flow      expected speed {:.4g} m/s: Ma = {:.3g}, Re = {:.4g}, Ga = {:.4g}\n",
                      p.expected_speed_si, p.mach, p.reynolds, p.galileo);
  text += fmt::format("  grid      {}x{}x{} = {:.3g} cells, {}, {}, {}\n", r.cells[0], r.cells[1], r.cells[2],
                      r.cell_count, lbm::to_string(s.lattice), operator_text(s, p), lbm::to_string(s.precision));
  text += fmt::format("  run       end time {:.4g} s = {:.0f} steps\n", s.end_time_si, r.steps);
  if (const auto outlook = terminal_outlook(s)) text += fmt::format("            {}\n", outlook->line);
  text += fmt::format("  body      {}, {}\n", coupling::to_string(s.coupling), r.surface_text());
  const std::string budget =
      r.memory_budget_bytes
          ? fmt::format("{:.3g} GiB available ({})", *r.memory_budget_bytes / kBytesPerGiB, r.memory_budget_source)
          : std::string("available memory unknown");
  text += fmt::format("  memory    about {:.3g} GiB; {}\n", r.memory.total_bytes() / kBytesPerGiB, budget);
  const int threads = omp_get_max_threads();
  text += fmt::format(
      "  wall time about {} on {} thread{} for the fluid alone, at {:.0f} million cell updates per "
      "second measured just now on 96^3 cells; the coupling and the outputs add to it\n",
      duration_text(wall_s), threads, threads == 1 ? "" : "s", rate / 1e6);
  return text;
}

}  // namespace settle::app
