#include "app/python_child.hpp"

#include <fcntl.h>
#include <spawn.h>
#include <sys/wait.h>
#include <unistd.h>

#include <cerrno>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <stdexcept>

#include <fmt/core.h>

#include "common/error.hpp"

extern char** environ;

#ifndef SETTLE_PYTHON_DIR
#error "SETTLE_PYTHON_DIR (the python/ folder of the sources) must be defined by src/app/CMakeLists.txt"
#endif
#ifndef SETTLE_INSTALLED_PYTHON_DIR
#error "SETTLE_INSTALLED_PYTHON_DIR (the installed scripts' folder from bin/) must be defined by src/app/CMakeLists.txt"
#endif

namespace settle::app {

namespace fs = std::filesystem;

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
namespace {

std::vector<std::string> python_candidates() {
  if (const char* chosen = std::getenv("SETTLE_PYTHON"); chosen != nullptr && *chosen != '\0') return {chosen};
  return {"python3", "/usr/bin/python3"};
}

}  // namespace

/// The first candidate that imports matplotlib and numpy. Throws InputError naming the Debian
/// packages when none does.
std::string find_python(const std::string& command) {
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
        fmt::format("{} needs python3 (tried {}): install Debian's python3 and "
                    "python3-matplotlib (apt-get install python3 python3-matplotlib), or set SETTLE_PYTHON",
                    command, tried));
  throw InputError(
      fmt::format("matplotlib or numpy is not importable by {}: install Debian's python3-matplotlib "
                  "(apt-get install python3-matplotlib python3-numpy), or set SETTLE_PYTHON to a python "
                  "that has them",
                  tried));
}

namespace {

// The folder of this process's executable (Linux: /proc/self/exe); empty when it cannot be read.
fs::path executable_folder() {
  std::error_code error;
  const fs::path executable = fs::read_symlink("/proc/self/exe", error);
  return error ? fs::path() : executable.parent_path();
}

// An installed binary (<prefix>/bin/settle) has its scripts at <prefix>/share/settle/python (the
// install rules, CMakeLists.txt); a binary in the build tree has no such folder beside it and uses
// the source tree it was built from (compiled in, so a fresh clone's build finds them without
// installing anything). The folder decides, not the script, so that an installed binary never
// mixes in scripts from a source tree that may be of another version.
fs::path default_python_folder() {
  const fs::path folder = executable_folder();
  std::error_code error;
  if (!folder.empty()) {
    const fs::path installed = (folder / SETTLE_INSTALLED_PYTHON_DIR).lexically_normal();
    if (fs::is_directory(installed, error)) return installed;
  }
  return fs::path(SETTLE_PYTHON_DIR);
}

}  // namespace

/// python/settle_plot.py: from $SETTLE_PYTHON_DIR when set, else the installed folder beside the
/// binary (../share/settle/python), else the source tree this binary was built from.
fs::path find_script(const std::string& script_name, const std::string& command) {
  const char* override_dir = std::getenv("SETTLE_PYTHON_DIR");
  const bool overridden = override_dir != nullptr && *override_dir != '\0';
  const fs::path dir = overridden ? fs::path(override_dir) : default_python_folder();
  const fs::path script = dir / script_name;
  std::error_code error;
  if (!fs::is_regular_file(script, error))
    throw InputError(fmt::format("{}: no {} in {}; set SETTLE_PYTHON_DIR to the python/ folder of the settle sources",
                                 overridden ? "SETTLE_PYTHON_DIR" : command, script_name, dir.string()));
  return script;
}

int run_python_script(const std::string& python, const fs::path& script, const std::vector<std::string>& arguments) {
  std::vector<std::string> command{python, script.string()};
  command.insert(command.end(), arguments.begin(), arguments.end());
  std::fflush(stdout);  // keep our output before the child's
  std::fflush(stderr);
  const std::optional<int> status = run_child(command, false);
  if (!status) throw std::runtime_error(fmt::format("cannot start {}: {}", python, std::strerror(errno)));
  return *status;
}

}  // namespace settle::app
