#pragma once
// Child processes of the front end: running one and waiting for it, and the Python with matplotlib
// and the script that `settle plot` and `settle study collect` draw their figures with.
#include <filesystem>
#include <optional>
#include <string>
#include <vector>

namespace settle::app {

/// How a child process ended: its exit status, or std::nullopt (errno set) if it could not be
/// started. A child killed by a signal reports 128 + the signal number, as shells do. `quiet`
/// sends its output to /dev/null.
std::optional<int> run_child(const std::vector<std::string>& arguments, bool quiet);

/// The first of $SETTLE_PYTHON, else python3 from PATH and /usr/bin/python3, that imports
/// matplotlib and numpy. InputError naming the Debian packages when none does; `command` names
/// the settle command that needs it.
std::string find_python(const std::string& command);

/// python/`script_name`: from $SETTLE_PYTHON_DIR when set, else the installed folder beside the
/// binary (<prefix>/bin/settle -> <prefix>/share/settle/python) when there is one, else the source
/// tree this binary was built from (compiled in, so a fresh clone's build finds it without
/// installing anything).
std::filesystem::path find_script(const std::string& script_name, const std::string& command);

/// Runs `python script arguments...` with stdout and stderr flushed first; returns its exit status.
int run_python_script(const std::string& python, const std::filesystem::path& script,
                      const std::vector<std::string>& arguments);

}  // namespace settle::app
