#include "app/slurm_script.hpp"

#include <array>
#include <regex>
#include <string_view>

#include <fmt/core.h>

#include "common/error.hpp"

namespace settle::app {
namespace {

// The options the script sets from the study: a user's value would break the one-task-a-case plan.
constexpr std::array<std::string_view, 4> kOptionsTheScriptSets{"array", "ntasks", "cpus-per-task", "output"};

// POSIX shell single quotes: nothing inside is expanded; a quote is closed, escaped and reopened.
std::string shell_quoted(const std::string& text) {
  std::string quoted = "'";
  for (const char c : text) quoted += c == '\'' ? std::string("'\\''") : std::string(1, c);
  return quoted + "'";
}

}  // namespace

void check_sbatch_option(const std::string& option) {
  static const std::regex form("([a-z][a-z0-9-]*)=([^\"'\\n\\r]+)");
  std::smatch parts;
  if (!std::regex_match(option, parts, form))
    throw InputError(fmt::format(
        "--sbatch: \"{}\" is not KEY=VALUE with KEY a Slurm option's long name and VALUE one line without quotes "
        "(e.g. --sbatch time=04:00:00 --sbatch partition=cpu)",
        option));
  for (const std::string_view key : kOptionsTheScriptSets)
    if (parts[1].str() == key)
      throw InputError(
          fmt::format("--sbatch: {} is set by the script from the study (array, ntasks, cpus-per-task and output are; "
                      "--threads sets cpus-per-task)",
                      key));
}

std::string slurm_array_script(const SlurmArray& a) {
  const std::string dir = a.study_dir.string();
  if (dir.find_first_of("\"\n\r") != std::string::npos)
    throw InputError(
        fmt::format("-o {}: a Slurm directive cannot hold a path with a double quote or a line break; "
                    "choose another directory for the study",
                    dir));
  std::string options;
  for (const std::string& option : a.sbatch_options) options += fmt::format("#SBATCH --{}\n", option);
  // sbatch reads a double-quoted value of a directive whole, spaces included.
  return fmt::format(
      "#!/bin/bash\n"
      "# The study {} as a Slurm job array, one task a case (written by `settle study run --emit slurm`).\n"
      "# Submit from any folder: sbatch {}. Each task runs its case in {}/case_NNNN as\n"
      "# `settle study run` would (resuming from a checkpoint); gather with `settle study collect {}`.\n"
      "#SBATCH --job-name=\"settle-{}\"\n"
      "#SBATCH --array=0-{}\n"
      "#SBATCH --ntasks=1\n"
      "#SBATCH --cpus-per-task={}\n"
      "#SBATCH --output=\"{}/slurm_%A_%a.log\"\n"
      "{}"
      "set -euo pipefail\n"
      "export OMP_PROC_BIND=close OMP_PLACES=cores\n"
      "exec {} study task {} --index \"${{SLURM_ARRAY_TASK_ID}}\" --threads \"${{SLURM_CPUS_PER_TASK:-{}}}\"\n",
      a.study_name, shell_quoted((a.study_dir / "slurm_array.sh").string()), dir, shell_quoted(dir), a.study_name,
      a.cases - 1, a.threads, dir, options, shell_quoted(a.executable.string()), shell_quoted(dir), a.threads);
}

}  // namespace settle::app
