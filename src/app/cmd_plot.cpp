// `settle plot RUN_DIR [--reference KEY] [--reference-file F] [-o DIR]` (docs/plots.md): PNG
// figures of a `settle run` output directory, drawn by python/settle_plot.py with matplotlib.
// This file only checks the directory, runs the script with a Python that has matplotlib
// (app/python_child.hpp) and passes its exit status on; the figures themselves are the script's.
#include <cstdlib>
#include <filesystem>
#include <memory>
#include <string>
#include <vector>

#include <fmt/core.h>

#include "app/commands.hpp"
#include "app/python_child.hpp"
#include "common/error.hpp"

namespace settle::app {
namespace {

namespace fs = std::filesystem;

constexpr const char* kScriptName = "settle_plot.py";

struct PlotOptions {
  std::string run_dir;
  std::string reference;
  std::string reference_file;
  std::string output_dir;
};

/// Checks here what the script would refuse too, so a wrong directory costs no Python start-up.
void check_run_dir(const std::string& run_dir) {
  std::error_code error;
  if (!fs::is_directory(run_dir, error))
    throw InputError(
        fmt::format("RUN_DIR: '{}' is not a directory (give the output directory of settle run)", run_dir));
  if (!fs::is_regular_file(fs::path(run_dir) / "timeseries.csv", error))
    throw InputError(
        fmt::format("RUN_DIR: '{}' has no timeseries.csv (give the output directory of settle run)", run_dir));
}

void plot(const PlotOptions& options) {
  check_run_dir(options.run_dir);
  const fs::path script = find_script(kScriptName, "settle plot");
  const std::string python = find_python("settle plot");

  std::vector<std::string> arguments;
  if (!options.reference.empty()) arguments.insert(arguments.end(), {"--reference", options.reference});
  if (!options.reference_file.empty()) arguments.insert(arguments.end(), {"--reference-file", options.reference_file});
  if (!options.output_dir.empty()) arguments.insert(arguments.end(), {"--output-dir", options.output_dir});
  arguments.insert(arguments.end(), {"--", options.run_dir});  // a RUN_DIR starting with '-' stays a path
  // The script has already reported any problem itself (exit 2: one the user can fix); its
  // status is passed on unchanged rather than mapped through an exception, which would print
  // a second message.
  if (const int status = run_python_script(python, script, arguments); status != 0) std::exit(status);
}

}  // namespace

void add_plot_command(CLI::App& app) {
  auto options = std::make_shared<PlotOptions>();
  CLI::App* cmd = app.add_subcommand(
      "plot",
      "PNG figures of a settle run output directory: velocity, trajectory (side views and 3D), orientation "
      "(tilt, both Euler sets, active set), forces and torques, and the reference curves when given "
      "(needs python3 with matplotlib: Debian's python3-matplotlib)");
  cmd->add_option("RUN_DIR", options->run_dir, "output directory of settle run")->required();
  cmd->add_option("--reference", options->reference,
                  "reference data set to draw over the simulation, a key of validation/reference-data.json "
                  "(e.g. tenCate2002_E1); default: the `reference` named in summary.json or case.resolved.toml");
  cmd->add_option("--reference-file", options->reference_file,
                  "reference data file (default: validation/reference-data.json of the settle sources)");
  cmd->add_option("-o,--output", options->output_dir, "directory for the PNG files (default RUN_DIR/plots)");
  cmd->footer(
      "Environment: SETTLE_PYTHON (the python to use; default python3 from PATH, then /usr/bin/python3), "
      "SETTLE_PYTHON_DIR (folder of settle_plot.py; default the python/ folder of the sources). "
      "Prints the paths of the files written, one a line.");
  cmd->callback([options] { plot(*options); });
}

}  // namespace settle::app
