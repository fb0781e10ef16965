// `settle plot RUN_DIR [--reference KEY] [--reference-file F] [-o DIR]` (docs/plots.md): PNG
// figures of a `settle run` output directory, drawn by python/settle_plot.py with matplotlib.
// This file only finds a Python that can import matplotlib and numpy, finds the script, runs it
// and passes its exit status on; the figures themselves are the script's.
#include <fcntl.h>
#include <spawn.h>
#include <sys/wait.h>
#include <unistd.h>

#include <cerrno>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <filesystem>
#include <memory>
#include <optional>
#include <stdexcept>
#include <string>
#include <vector>

#include <fmt/core.h>

#include "app/commands.hpp"
#include "common/error.hpp"

extern char** environ;

#ifndef SETTLE_PYTHON_DIR
#error "SETTLE_PYTHON_DIR (the python/ folder of the sources) must be defined by src/app/CMakeLists.txt"
#endif

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

/// How a child process ended: its exit status, or std::nullopt (errno set) if it could not be
/// started. A child killed by a signal reports 128 + the signal number, as shells do.
std::optional<int> run_child(const std::vector<std::string>& arguments, bool quiet) {
  std::vector<char*> argv;
  argv.reserve(arguments.size() + 1);
  for (const auto& a : arguments) argv.push_back(const_cast<char*>(a.c_str()));
  argv.push_back(nullptr);

  posix_spawn_file_actions_t actions;
  posix_spawn_file_actions_init(&actions);
  if (quiet) {
    posix_spawn_file_actions_addopen(&actions, STDOUT_FILENO, "/dev/null", O_WRONLY, 0);
    posix_spawn_file_actions_addopen(&actions, STDERR_FILENO, "/dev/null", O_WRONLY, 0);
  }
  pid_t pid = 0;
  // posix_spawnp searches PATH for a bare name, like a shell would.
  const int spawn_error = posix_spawnp(&pid, argv[0], &actions, nullptr, argv.data(), environ);
  posix_spawn_file_actions_destroy(&actions);
  if (spawn_error != 0) {
    errno = spawn_error;
    return std::nullopt;
  }

  int status = 0;
  while (waitpid(pid, &status, 0) < 0) {
    if (errno != EINTR) return std::nullopt;
  }
  if (WIFEXITED(status)) return WEXITSTATUS(status);
  // The status of an exec failure inside the child (posix_spawnp may report it this way, 127).
  return WIFSIGNALED(status) ? 128 + WTERMSIG(status) : 1;
}

/// The Python interpreters to try, in order: $SETTLE_PYTHON alone when set (the user's explicit
/// choice), otherwise `python3` from PATH and then Debian's /usr/bin/python3, which is where
/// python3-matplotlib installs (a pyenv or conda python3 earlier in PATH often lacks it).
std::vector<std::string> python_candidates() {
  if (const char* chosen = std::getenv("SETTLE_PYTHON"); chosen != nullptr && *chosen != '\0') return {chosen};
  return {"python3", "/usr/bin/python3"};
}

/// The first candidate that imports matplotlib and numpy. Throws InputError naming the Debian
/// packages when none does.
std::string find_python() {
  const std::vector<std::string> candidates = python_candidates();
  bool any_started = false;
  for (const auto& python : candidates) {
    const std::optional<int> status = run_child({python, "-c", "import matplotlib, numpy"}, true);
    if (!status) continue;
    // 127: the shell convention for "command not found", which posix_spawnp's child may use.
    if (*status == 127) continue;
    any_started = true;
    if (*status == 0) return python;
  }
  std::string tried;
  for (const auto& python : candidates) tried += (tried.empty() ? "" : ", ") + python;
  if (!any_started)
    throw InputError(
        fmt::format("settle plot needs python3 (tried {}): install Debian's python3 and "
                    "python3-matplotlib (apt-get install python3 python3-matplotlib), or set SETTLE_PYTHON",
                    tried));
  throw InputError(
      fmt::format("matplotlib or numpy is not importable by {}: install Debian's python3-matplotlib "
                  "(apt-get install python3-matplotlib python3-numpy), or set SETTLE_PYTHON to a python "
                  "that has them",
                  tried));
}

/// python/settle_plot.py: from $SETTLE_PYTHON_DIR when set, else the source tree this binary was
/// built from (compiled in, so a fresh clone's build finds it without installing anything).
fs::path find_script() {
  const char* override_dir = std::getenv("SETTLE_PYTHON_DIR");
  const bool overridden = override_dir != nullptr && *override_dir != '\0';
  const fs::path dir = overridden ? fs::path(override_dir) : fs::path(SETTLE_PYTHON_DIR);
  const fs::path script = dir / kScriptName;
  std::error_code error;
  if (!fs::is_regular_file(script, error))
    throw InputError(fmt::format("{}: no {} in {}; set SETTLE_PYTHON_DIR to the python/ folder of the settle sources",
                                 overridden ? "SETTLE_PYTHON_DIR" : "settle plot", kScriptName, dir.string()));
  return script;
}

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
  const fs::path script = find_script();
  const std::string python = find_python();

  std::vector<std::string> arguments{python, script.string()};
  if (!options.reference.empty()) arguments.insert(arguments.end(), {"--reference", options.reference});
  if (!options.reference_file.empty()) arguments.insert(arguments.end(), {"--reference-file", options.reference_file});
  if (!options.output_dir.empty()) arguments.insert(arguments.end(), {"--output-dir", options.output_dir});
  arguments.insert(arguments.end(), {"--", options.run_dir});  // a RUN_DIR starting with '-' stays a path

  std::fflush(stdout);  // keep our output before the child's
  std::fflush(stderr);
  const std::optional<int> status = run_child(arguments, false);
  if (!status) throw std::runtime_error(fmt::format("cannot start {}: {}", python, std::strerror(errno)));
  // The script has already reported any problem itself (exit 2: one the user can fix); its
  // status is passed on unchanged rather than mapped through an exception, which would print
  // a second message.
  if (*status != 0) std::exit(*status);
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
