#pragma once
// `settle run --dry-run`: the plan of a case (coupling/case_plan.hpp) as the preflight checked it,
// with an estimate of the wall time, printed without running and without writing anything.
#include <optional>
#include <string>

#include "coupling/case_plan.hpp"
#include "coupling/setup.hpp"
#include "io/preflight.hpp"

namespace settle::app {

/// The plan's lines: units, grid, steps, the body on the grid, memory, and the wall time the
/// fluid kernel alone would take at the throughput measured now on this machine.
/// The collision operator and the subgrid model the run uses, e.g. "trt + smagorinsky (C_S 0.1,
/// auto: cell Re 70.7 > 20)": the plan's choice, with the reason when "auto" made it.
std::string operator_text(const coupling::SimulationSetup& setup, const coupling::CasePlan& plan);

/// When a free body's terminal state can first be detected (analysis/terminal_state.hpp: two
/// windows of 5 response times after the release): a line for the console and the plan, and a
/// warning when run.end_time comes before it. Empty for towed and fixed bodies and without net
/// weight (no response time).
struct TerminalOutlook {
  std::string line;
  std::optional<std::string> warning;
};
std::optional<TerminalOutlook> terminal_outlook(const coupling::SimulationSetup& setup);

std::string run_plan_text(const coupling::SimulationSetup& setup, const io::PreflightReport& report);

}  // namespace settle::app
