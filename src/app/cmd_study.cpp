// `settle study run|collect|task` (docs/studies.md): many runs of one base case. The study module
// reads and expands the study file, prepares its directory, runs the cases as processes and builds
// the table and its analyses; this file parses the flags, prints, writes the collected files and
// draws the figures with python/settle_study_plot.py.
#include <unistd.h>

#include <algorithm>
#include <cstdio>
#include <filesystem>
#include <memory>
#include <optional>
#include <string>
#include <thread>
#include <vector>

#include <fmt/core.h>

#include "app/commands.hpp"
#include "app/flag_values.hpp"
#include "app/python_child.hpp"
#include "app/slurm_script.hpp"
#include "common/atomic_file.hpp"
#include "common/build_info.hpp"
#include "common/error.hpp"
#include "common/file_lock.hpp"
#include "study/study_directory.hpp"
#include "study/study_runner.hpp"
#include "study/study_spec.hpp"
#include "study/study_table.hpp"

namespace settle::app {
namespace {

namespace fs = std::filesystem;

constexpr const char* kPlotScript = "settle_study_plot.py";
constexpr int kExitSomeCasesFailed = 3;  // documented in docs/studies.md

struct StudyRunOptions {
  std::string study_file;
  std::string output_dir;
  int jobs = 1;
  int threads = 0;  // 0: the cores shared out among the jobs
  bool dry_run = false;
  std::string emit;
  std::vector<std::string> sbatch_options;  // KEY=VALUE, with --emit slurm
};

struct StudyTaskOptions {
  std::string dir;
  int index = -1;
  int threads = 1;
};

struct StudyCollectOptions {
  std::string dir;
  bool plots = true;
};

fs::path this_executable() {
  std::error_code error;
  const fs::path self = fs::read_symlink("/proc/self/exe", error);
  if (error) throw std::runtime_error("cannot find the settle executable (/proc/self/exe): " + error.message());
  return self;
}

int default_threads(int jobs) {
  const int cores = static_cast<int>(std::max(1u, std::thread::hardware_concurrency()));
  return std::max(1, cores / std::max(1, jobs));
}

// One `settle study run` at a time per study directory: two would each start the cases the other
// is running, find their run locks held and report them failed (both exiting 3), and write the
// same status files. Taken before the directory is prepared, held until the command ends.
FileLock take_study_lock(const fs::path& dir) {
  std::error_code error;
  fs::create_directories(dir, error);
  if (error) throw InputError(fmt::format("-o: cannot create the directory {}: {}", dir.string(), error.message()));
  std::optional<FileLock> lock = FileLock::try_take(dir / kStudyLockFileName);
  if (!lock)
    throw InputError(fmt::format(
        "-o {}: another settle study run is running this study ({} is locked); wait for it to end, or stop it "
        "(SIGINT or SIGTERM) and run the command again to resume",
        dir.string(), (dir / kStudyLockFileName).string()));
  return std::move(*lock);
}

// A -march=native binary may stop with an illegal instruction on a cluster node of another CPU.
void warn_if_tuned_to_this_cpu() {
  if (!build_info().native_cpu) return;
  std::fprintf(stderr,
               "settle study: warning: %s is built for this machine's CPU (-march=native); on cluster nodes of "
               "another CPU it may stop with an illegal instruction: build the release preset on the cluster, or "
               "the native preset on a node like those the jobs run on\n",
               this_executable().string().c_str());
}

void print_plan(const std::vector<study::StudyCase>& cases) {
  for (const study::StudyCase& c : cases)
    std::printf("%s  %s\n", study::case_folder(c.index).c_str(), study::describe_inputs(c.inputs).c_str());
}

void run_study_command(const StudyRunOptions& o) {
  if (o.jobs < 1) throw InputError(fmt::format("--jobs: {} is not >= 1", o.jobs));
  check_thread_count(o.threads, "--threads");
  if (!o.emit.empty() && o.emit != "slurm") throw InputError(fmt::format("--emit: \"{}\" is not slurm", o.emit));
  if (!o.sbatch_options.empty() && o.emit != "slurm") throw InputError("--sbatch: only with --emit slurm");
  for (const std::string& option : o.sbatch_options) check_sbatch_option(option);
  const study::StudySpec spec = study::read_study(o.study_file);
  const std::vector<study::StudyCase> cases = study::expand(spec);  // every case checked before anything runs
  const int threads = o.threads > 0 ? o.threads : default_threads(o.jobs);
  if (o.dry_run) {
    std::fprintf(stderr, "settle study: %s: %zu cases, all checked\n", spec.name.c_str(), cases.size());
    print_plan(cases);
    return;
  }
  if (o.output_dir.empty()) throw InputError("-o: required (the study's directory)");
  const fs::path dir = o.output_dir;
  study::check_study_directory(spec, cases, dir);  // refuses another study's directory, touching nothing
  // The script is built (and its path checked) before anything is written.
  const std::string script_text = o.emit == "slurm"
                                      ? slurm_array_script({fs::absolute(dir), this_executable(), spec.name,
                                                            cases.size(), threads, o.sbatch_options})
                                      : std::string();
  const FileLock lock = take_study_lock(dir);
  study::prepare_study_directory(spec, cases, dir);
  if (o.emit == "slurm") {
    const fs::path script = dir / "slurm_array.sh";
    write_file_atomically(script, script_text);
    warn_if_tuned_to_this_cpu();
    fs::permissions(script, fs::perms::owner_exec | fs::perms::group_exec, fs::perm_options::add);
    std::printf("%s\n", script.string().c_str());
    return;
  }
  study::RunnerOptions runner{this_executable(), o.jobs, threads, 30.0,
                              [](const std::string& line) { std::fprintf(stderr, "%s\n", line.c_str()); }};
  const study::StudyOutcome outcome = study::run_study(dir, runner);
  for (const std::string& failure : outcome.failures)
    std::fprintf(stderr, "settle study: failed: %s\n", failure.c_str());
  if (outcome.stop_signal != 0)
    throw RunInterrupted(fmt::format("study interrupted: {} cases stopped (each writes its checkpoint); run the same "
                                     "command again to resume",
                                     outcome.interrupted),
                         outcome.stop_signal);
  if (outcome.failed > 0) {
    std::fprintf(stderr, "settle study: %d of %d cases failed; run the same command again to retry them\n",
                 outcome.failed, outcome.cases);
    std::exit(kExitSomeCasesFailed);
  }
  std::fprintf(stderr, "settle study: all %d cases done (%d kept from before); collect with: settle study collect %s\n",
               outcome.cases, outcome.kept, dir.string().c_str());
}

void task_command(const StudyTaskOptions& o) {
  check_thread_count(o.threads, "--threads");
  study::RunnerOptions runner{this_executable(), 1, o.threads, 30.0, {}};
  const int status = study::run_study_case(o.dir, o.index, runner);
  if (status != 0) std::exit(status);
}

void collect_command(const StudyCollectOptions& o) {
  const fs::path dir = o.dir;
  const study::StudyTable table = study::collect_table(dir);
  nlohmann::ordered_json document;
  document["study"] = table.study;
  document["inputs"] = table.inputs;
  document["rows"] = table.rows;
  document["analyses"] = study::study_analyses(table);
  write_file_atomically(dir / "study.csv", study::table_csv(table));
  write_file_atomically(dir / "study_results.json", document.dump(2) + "\n");
  std::printf("%s\n%s\n", (dir / "study.csv").string().c_str(), (dir / "study_results.json").string().c_str());
  for (const auto& fit : document["analyses"]["coefficient_fits"])
    std::fprintf(stderr, "fit %s %s: %s = %s, rms residual %.4g, max %.4g\n", fit["inputs"].dump().c_str(),
                 fit["figure"].get<std::string>().c_str(), fit["form"].get<std::string>().c_str(),
                 fit["coefficients"].dump().c_str(), fit["rms_residual"].get<double>(),
                 fit["max_residual"].get<double>());
  for (const auto& g : document["analyses"]["grid_convergence"])
    std::fprintf(stderr, "grid convergence %s %s: order %s, extrapolated %s, GCI %s%s\n", g["inputs"].dump().c_str(),
                 g["figure"].get<std::string>().c_str(), g["observed_order"].dump().c_str(),
                 g["extrapolated"].dump().c_str(), g["gci_fine"].dump().c_str(),
                 g["order_confirmed"].get<bool>() ? ""
                 : g["oscillatory"].get<bool>()
                     ? " (oscillatory: the order is not confirmed; GCI with safety factor 3)"
                     : " (the order is not the scheme's 2: not confirmed; GCI with safety factor 3)");
  if (!o.plots) return;
  const fs::path script = find_script(kPlotScript, "settle study collect");
  const std::string python = find_python("settle study collect (or --no-plots)");
  if (const int status = run_python_script(python, script, {"--", dir.string()}); status != 0) std::exit(status);
}

void add_run(CLI::App& study) {
  auto o = std::make_shared<StudyRunOptions>();
  CLI::App* cmd = study.add_subcommand("run",
                                       "check every case of a study, then run them, N at a time; run again "
                                       "to resume (done cases are kept, the others run again)");
  cmd->add_option("STUDY", o->study_file, "study file (TOML, docs/studies.md)")->required();
  cmd->add_option("-o,--output", o->output_dir, "the study's directory (required unless --dry-run)");
  cmd->add_option("-j,--jobs", o->jobs, "cases run at a time (default 1)");
  cmd->add_option("--threads", o->threads, "OpenMP threads per case (default: the cores divided among the jobs)");
  cmd->add_flag("--dry-run", o->dry_run, "check the study and list its cases; run nothing, write nothing");
  cmd->add_option("--emit", o->emit,
                  "slurm: prepare the directory and write DIR/slurm_array.sh (a job array, one task a case) "
                  "instead of running");
  cmd->add_option("--sbatch", o->sbatch_options,
                  "with --emit slurm: a scheduler option KEY=VALUE written as #SBATCH --KEY=VALUE "
                  "(repeat it: --sbatch time=04:00:00 --sbatch partition=cpu --sbatch account=lab --sbatch mem=8G)")
      ->expected(1)
      ->multi_option_policy(CLI::MultiOptionPolicy::TakeAll);
  cmd->callback([o] { run_study_command(*o); });
}

void add_task(CLI::App& study) {
  auto o = std::make_shared<StudyTaskOptions>();
  CLI::App* cmd = study.add_subcommand("task", "run one case of a prepared study directory (a Slurm array task)");
  cmd->add_option("DIR", o->dir, "the study's directory")->required();
  cmd->add_option("--index", o->index, "the case's index (0-based; SLURM_ARRAY_TASK_ID)")->required();
  cmd->add_option("--threads", o->threads, "OpenMP threads (default 1)");
  cmd->callback([o] { task_command(*o); });
}

void add_collect(CLI::App& study) {
  auto o = std::make_shared<StudyCollectOptions>();
  CLI::App* cmd = study.add_subcommand(
      "collect",
      "gather a study's results: DIR/study.csv and DIR/study_results.json (rows, grid convergence, "
      "coefficient fits, ensemble statistics) and PNG figures in DIR/plots");
  cmd->add_option("DIR", o->dir, "the study's directory")->required();
  cmd->add_flag("!--no-plots", o->plots, "skip the figures (no Python needed)");
  cmd->callback([o] { collect_command(*o); });
}

}  // namespace

void add_study_command(CLI::App& app) {
  CLI::App* study = app.add_subcommand("study",
                                       "studies of many runs: coefficient maps, orientation ensembles, "
                                       "grid convergence (docs/studies.md)");
  study->require_subcommand(1);
  add_run(*study);
  add_task(*study);
  add_collect(*study);
}

}  // namespace settle::app
