#pragma once
// Runs a prepared study directory (study_directory.hpp): each case as its own `settle run`
// process, `jobs` at a time, its output in its folder and its console in run.log there
// (docs/studies.md, "Running").
#include <filesystem>
#include <functional>
#include <string>
#include <vector>

namespace settle::study {

struct RunnerOptions {
  std::filesystem::path settle_executable;           ///< the `settle` binary that runs each case
  int jobs = 1;                                      ///< cases at a time
  int threads = 1;                                   ///< OpenMP threads of each case (settle run --threads)
  double progress_interval_s = 30.0;                 ///< a progress line at least this often, and at every change
  std::function<void(const std::string&)> progress;  ///< one line each time
};

struct StudyOutcome {
  int cases = 0;
  int kept = 0;  ///< done before this call and left as they were
  int done = 0;  ///< finished in this call
  int failed = 0;
  int interrupted = 0;                ///< stopped by SIGINT or SIGTERM; run again to resume them
  int stop_signal = 0;                ///< the signal that stopped the study (0: none)
  std::vector<std::string> failures;  ///< "case_0003 (reynolds = 50): exit status 2, see .../run.log"
};

/// Runs every case of `dir` that is not done: from its checkpoint when an earlier attempt left one
/// (settle run --restart), else from the start. One case's failure does not stop the others. On
/// SIGINT or SIGTERM the running cases are stopped (each writes its checkpoint) and the rest are
/// not started.
StudyOutcome run_study(const std::filesystem::path& dir, const RunnerOptions& options);

/// Runs case `index` of `dir` as run_study would (a Slurm array task); returns settle run's exit
/// status (0 when the case was already done).
int run_study_case(const std::filesystem::path& dir, int index, const RunnerOptions& options);

}  // namespace settle::study
