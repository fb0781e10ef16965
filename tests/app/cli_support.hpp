#pragma once
// Running the real `settle` binary (SETTLE_BINARY, set by CTest) from case tests.
#include <sys/wait.h>
#include <unistd.h>

#include <algorithm>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <sstream>
#include <stdexcept>
#include <string>
#include <vector>

namespace settle::test {

/// Exit status (-1 when killed by a signal) and the captured output of one command.
struct CliResult {
  int status = -1;
  std::string out;
  std::string err;
};

inline std::string read_text(const std::filesystem::path& path) {
  std::ifstream file(path);
  std::stringstream text;
  text << file.rdbuf();
  return text.str();
}

/// A file name in the temporary directory, unique to this test process.
inline std::filesystem::path scratch(const std::string& name) {
  return std::filesystem::temp_directory_path() / ("settle_cli_" + std::to_string(::getpid()) + "_" + name);
}

/// Writes a case text to a scratch file `<name>.toml` and returns its path.
inline std::filesystem::path write_scratch_case(const std::string& name, const std::string& text) {
  const std::filesystem::path path = scratch(name + ".toml");
  std::ofstream(path) << text;
  return path;
}

/// Runs `settle <subcommand> <arguments>` through the shell and captures stdout and stderr. With
/// SETTLE_LAUNCHER set (e.g. "mpirun -n 2", as tests/app/CMakeLists.txt does for the malformed
/// inputs), the command runs under it.
/// With `working_directory`, the command runs there; `shell_prefix` (e.g. "ulimit -f 200;") runs
/// in the same shell before it.
inline CliResult run_settle(const std::string& subcommand, const std::string& arguments,
                            const std::filesystem::path& working_directory = {}, const std::string& shell_prefix = "") {
  const char* binary = std::getenv("SETTLE_BINARY");
  if (binary == nullptr) throw std::runtime_error("SETTLE_BINARY is not set");
  const char* launcher = std::getenv("SETTLE_LAUNCHER");
  const std::filesystem::path out = scratch("stdout"), err = scratch("stderr");
  const std::string command =
      shell_prefix + (working_directory.empty() ? std::string() : "cd '" + working_directory.string() + "' && ") +
      (launcher ? std::string(launcher) + " " : std::string()) + binary + " " + subcommand + " " + arguments + " > " +
      out.string() + " 2> " + err.string();
  const int raw = std::system(command.c_str());
  CliResult result{WIFEXITED(raw) ? WEXITSTATUS(raw) : -1, read_text(out), read_text(err)};
  std::filesystem::remove(out);
  std::filesystem::remove(err);
  return result;
}

/// Rows of a CSV file of numbers (timeseries.csv) after its header line, which goes to `header`.
inline std::vector<std::vector<double>> read_rows(const std::filesystem::path& csv_path,
                                                  std::vector<std::string>& header) {
  std::ifstream csv(csv_path);
  std::string line;
  std::getline(csv, line);
  header.clear();
  for (std::stringstream cells(line); std::getline(cells, line, ',');) header.push_back(line);
  std::vector<std::vector<double>> rows;
  while (std::getline(csv, line)) {
    std::vector<double> row;
    std::stringstream cells(line);
    for (std::string cell; std::getline(cells, cell, ',');) row.push_back(std::stod(cell));
    rows.push_back(std::move(row));
  }
  return rows;
}

/// Index of the column `name` in `header` (header.size() when it is absent).
inline std::size_t column(const std::vector<std::string>& header, const std::string& name) {
  return static_cast<std::size_t>(std::find(header.begin(), header.end(), name) - header.begin());
}

}  // namespace settle::test
