#pragma once
// The Slurm job array that `settle study run --emit slurm` writes (docs/studies.md): task i runs
// case i of a prepared study directory with `settle study task`.
#include <cstddef>
#include <filesystem>
#include <string>
#include <vector>

namespace settle::app {

struct SlurmArray {
  std::filesystem::path study_dir;   ///< absolute
  std::filesystem::path executable;  ///< the settle binary the tasks run
  std::string study_name;
  std::size_t cases = 0;
  int threads = 1;
  /// Scheduler options from `--sbatch KEY=VALUE`, each written as `#SBATCH --KEY=VALUE`.
  std::vector<std::string> sbatch_options;
};

/// Checks one `--sbatch` value: KEY=VALUE, KEY a Slurm long option's name (lower case letters,
/// digits and dashes) that the script does not set itself, VALUE one line without quotes.
/// Throws InputError naming the flag and what is allowed.
void check_sbatch_option(const std::string& option);

/// The script's text. Paths are quoted, so a study directory may contain spaces.
std::string slurm_array_script(const SlurmArray& array);

}  // namespace settle::app
