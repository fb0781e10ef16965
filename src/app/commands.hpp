#pragma once
// Each subcommand of the `settle` front end lives in its own cmd_*.cpp and registers itself
// here. A command's callback throws settle::InputError for problems the user can fix.
#include <CLI/CLI.hpp>

namespace settle::app {

void add_attitude_command(CLI::App& app);
void add_shape_command(CLI::App& app);
void add_bench_command(CLI::App& app);
void add_schema_command(CLI::App& app);
void add_run_command(CLI::App& app);
void add_predict_command(CLI::App& app);
void add_analyze_command(CLI::App& app);
void add_plot_command(CLI::App& app);
void add_study_command(CLI::App& app);

}  // namespace settle::app
