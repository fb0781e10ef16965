#include "study/study_runner.hpp"

#include <fcntl.h>
#include <sys/prctl.h>
#include <sys/wait.h>
#include <unistd.h>

#include <array>
#include <atomic>
#include <cerrno>
#include <chrono>
#include <csignal>
#include <cstring>
#include <map>
#include <thread>

#include <fmt/format.h>

#include "common/error.hpp"
#include "common/file_lock.hpp"
#include "common/stop_signals.hpp"
#include "study/study_directory.hpp"

namespace settle::study {
namespace {

namespace fs = std::filesystem;
using Clock = std::chrono::steady_clock;

std::atomic<int> g_stop_signal{0};

extern "C" void on_stop_signal(int signal_number) { g_stop_signal = signal_number; }

// The stop signals (common/stop_signals.hpp: SIGINT, SIGTERM, SIGHUP, ...) set a flag for the loop
// while run_study runs; the old handlers come back after.
class StopSignals {
 public:
  StopSignals() {
    g_stop_signal = 0;
    struct sigaction action {};
    action.sa_handler = on_stop_signal;
    sigemptyset(&action.sa_mask);
    for (std::size_t i = 0; i < kStopSignals.size(); ++i) sigaction(kStopSignals[i], &action, &previous_[i]);
  }
  ~StopSignals() {
    for (std::size_t i = 0; i < kStopSignals.size(); ++i) sigaction(kStopSignals[i], &previous_[i], nullptr);
  }
  StopSignals(const StopSignals&) = delete;
  StopSignals& operator=(const StopSignals&) = delete;
  static bool raised() { return g_stop_signal != 0; }

 private:
  std::array<struct sigaction, kStopSignals.size()> previous_{};
};

// settle run's arguments for a case: from the checkpoint an earlier attempt left, else afresh,
// replacing what a failed attempt left (--overwrite: the case directory is the study's).
std::vector<std::string> run_arguments(const fs::path& case_dir, const RunnerOptions& options) {
  std::error_code error;
  const std::string threads = std::to_string(options.threads);
  if (fs::is_regular_file(case_dir / "checkpoint.bin", error))
    return {options.settle_executable.string(), "run", "--restart", case_dir.string(), "--threads", threads};
  return {options.settle_executable.string(),
          "run",
          (case_dir / "case.toml").string(),
          "-o",
          case_dir.string(),
          "--overwrite",
          "--threads",
          threads};
}

// Starts a case's run with its console appended to run.log. The child keeps the stop signals at
// their defaults (settle run installs its own), whatever this process does with them, and gets
// SIGTERM when this process dies (PR_SET_PDEATHSIG): a study killed with SIGKILL left its running
// case behind, still writing the case's directory, and the study run again to resume found that
// case's lock held and reported it failed. SIGTERM makes the orphan write its checkpoint and end.
// Between fork and exec only async-signal-safe calls are made.
pid_t spawn_case(const fs::path& case_dir, const RunnerOptions& options) {
  const std::vector<std::string> arguments = run_arguments(case_dir, options);
  std::vector<char*> argv;
  for (const auto& a : arguments) argv.push_back(const_cast<char*>(a.c_str()));
  argv.push_back(nullptr);
  const std::string log = (case_dir / "run.log").string();
  const pid_t parent = ::getpid();
  const pid_t pid = ::fork();
  if (pid < 0) throw std::runtime_error(fmt::format("cannot start {}: fork: {}", arguments[0], std::strerror(errno)));
  if (pid > 0) return pid;
  ::prctl(PR_SET_PDEATHSIG, SIGTERM);
  if (::getppid() != parent) ::_exit(127);  // the study died before the line above took effect
  for (const int signal_number : kStopSignals) ::signal(signal_number, SIG_DFL);
  sigset_t none;
  sigemptyset(&none);
  ::sigprocmask(SIG_SETMASK, &none, nullptr);
  const int fd = ::open(log.c_str(), O_WRONLY | O_CREAT | O_APPEND | O_CLOEXEC, 0644);
  if (fd < 0 || ::dup2(fd, STDOUT_FILENO) < 0 || ::dup2(fd, STDERR_FILENO) < 0) ::_exit(127);
  ::execv(argv[0], argv.data());
  ::_exit(127);
}

// A case an earlier settle run finished (its summary.json, the run's completion mark, which a run
// removes when it starts) while its status still says otherwise (the study that started it was
// killed): marked done rather than run again.
bool mark_done_if_finished(const fs::path& case_dir) {
  std::error_code error;
  if (!fs::is_regular_file(case_dir / "summary.json", error)) return false;
  CaseStatus status = read_case_status(case_dir);
  status.state = CaseState::done;
  status.exit_status = 0;
  write_case_status(case_dir, status);
  return true;
}

// A case whose directory a settle run still holds (a run an earlier study left behind, or started
// by hand) is not started again: its run would be refused by the lock and reported failed.
bool case_run_alive(const fs::path& case_dir) { return lock_is_held(case_dir / kRunLockFileName); }

int exit_status_of(int wait_status) {
  if (WIFEXITED(wait_status)) return WEXITSTATUS(wait_status);
  return WIFSIGNALED(wait_status) ? 128 + WTERMSIG(wait_status) : 1;
}

std::string describe_case(const nlohmann::ordered_json& entry) {
  std::string inputs;
  if (entry.contains("inputs"))
    for (const auto& [name, value] : entry["inputs"].items())
      inputs += (inputs.empty() ? "" : ", ") + name + " = " + value.dump();
  return fmt::format("{} ({})", entry["folder"].get<std::string>(), inputs);
}

std::string minutes(double seconds) {
  return seconds < 120.0 ? fmt::format("{:.0f} s", seconds) : fmt::format("{:.0f} min", seconds / 60.0);
}

struct Running {
  int index;
  fs::path dir;
  CaseStatus status;
  Clock::time_point start;
};

class StudyLoop {
 public:
  StudyLoop(const fs::path& dir, const RunnerOptions& options)
      : dir_(dir), options_(options), plan_(read_plan(dir)), start_(Clock::now()) {
    outcome_.cases = static_cast<int>(plan_["cases"].size());
  }

  StudyOutcome run() {
    for (const auto& entry : plan_["cases"]) {
      const int index = entry["index"].get<int>();
      if (read_case_status(dir_ / case_folder(index)).state == CaseState::done)
        ++outcome_.kept;
      else
        pending_.push_back(index);
    }
    std::size_t next = 0;
    report();
    auto last_report = Clock::now();
    while (next < pending_.size() || !running_.empty() || !waiting_.empty()) {
      start_waiting();
      while (!StopSignals::raised() && next < pending_.size() && static_cast<int>(running_.size()) < options_.jobs)
        start(pending_[next++]);
      if (StopSignals::raised()) stop_all();
      if (reap() || seconds_since(last_report) >= options_.progress_interval_s) {
        report();
        last_report = Clock::now();
      }
      if (StopSignals::raised() && running_.empty()) break;
      std::this_thread::sleep_for(std::chrono::milliseconds(50));
    }
    outcome_.interrupted += static_cast<int>(waiting_.size());  // never started: run again to resume
    outcome_.stop_signal = g_stop_signal;
    return outcome_;
  }

 private:
  static double seconds_since(Clock::time_point t) { return std::chrono::duration<double>(Clock::now() - t).count(); }

  void start(int index) {
    const fs::path case_dir = dir_ / case_folder(index);
    if (case_run_alive(case_dir)) {
      waiting_.push_back(index);
      if (options_.progress)
        options_.progress(
            fmt::format("{}: a settle run started earlier (by an earlier study run?) is still writing "
                        "it; waiting for it to end",
                        case_folder(index)));
      return;
    }
    if (mark_done_if_finished(case_dir)) {
      ++outcome_.done;
      return;
    }
    CaseStatus status = read_case_status(case_dir);
    status.state = CaseState::running;
    ++status.attempts;
    write_case_status(case_dir, status);
    const pid_t pid = spawn_case(case_dir, options_);
    running_.emplace(pid, Running{index, case_dir, status, Clock::now()});
  }

  // The waiting cases whose earlier run has ended: done when it finished (its summary.json), else
  // started (from the checkpoint it left, if any) when a job is free.
  void start_waiting() {
    for (auto it = waiting_.begin(); it != waiting_.end();) {
      const fs::path case_dir = dir_ / case_folder(*it);
      if (case_run_alive(case_dir) || StopSignals::raised()) {
        ++it;
        continue;
      }
      if (static_cast<int>(running_.size()) < options_.jobs) {
        start(*it);  // done at once when the earlier run finished the case
      } else {
        ++it;
        continue;
      }
      it = waiting_.erase(it);
    }
  }

  // settle run writes its checkpoint on SIGTERM; a case already stopping is sent it again harmlessly.
  void stop_all() {
    if (stopping_) return;
    stopping_ = true;
    for (const auto& [pid, r] : running_) ::kill(pid, SIGTERM);
  }

  // Collects the cases that ended; true when any did.
  bool reap() {
    bool any = false;
    for (;;) {
      int wait_status = 0;
      const pid_t pid = ::waitpid(-1, &wait_status, WNOHANG);
      if (pid <= 0) break;
      auto it = running_.find(pid);
      if (it == running_.end()) continue;
      finish(it->second, exit_status_of(wait_status));
      running_.erase(it);
      any = true;
    }
    return any;
  }

  void finish(Running& r, int exit_status) {
    std::error_code error;
    r.status.exit_status = exit_status;
    r.status.wall_seconds += seconds_since(r.start);
    const bool complete = exit_status == 0 && fs::is_regular_file(r.dir / "summary.json", error);
    if (complete) {
      r.status.state = CaseState::done;
      ++outcome_.done;
      finished_seconds_ += seconds_since(r.start);
    } else if (stopping_) {
      r.status.state = CaseState::interrupted;
      ++outcome_.interrupted;
    } else {
      r.status.state = CaseState::failed;
      ++outcome_.failed;
      outcome_.failures.push_back(fmt::format("{}: exit status {}, see {}", describe_case(plan_["cases"][r.index]),
                                              exit_status, (r.dir / "run.log").string()));
    }
    write_case_status(r.dir, r.status);
  }

  void report() {
    if (!options_.progress) return;
    const int finished = outcome_.kept + outcome_.done;
    const int remaining = outcome_.cases - finished - outcome_.failed - outcome_.interrupted;
    std::string eta = "ETA unknown";
    if (outcome_.done > 0) {
      const double per_case = finished_seconds_ / outcome_.done;
      eta = "ETA " + minutes(per_case * remaining / std::max(1, options_.jobs));
    }
    options_.progress(fmt::format("study {}: {}/{} done, {} running, {} failed{}; {} elapsed, {}",
                                  plan_["study"].get<std::string>(), finished, outcome_.cases, running_.size(),
                                  outcome_.failed, stopping_ ? ", stopping" : "", minutes(seconds_since(start_)),
                                  remaining > 0 ? eta : "ETA 0 s"));
  }

  fs::path dir_;
  RunnerOptions options_;
  nlohmann::ordered_json plan_;
  Clock::time_point start_;
  StudyOutcome outcome_;
  std::vector<int> pending_;
  std::vector<int> waiting_;  ///< cases an earlier run still holds (case_run_alive)
  std::map<pid_t, Running> running_;
  double finished_seconds_ = 0.0;
  bool stopping_ = false;
};

void check_options(const RunnerOptions& options) {
  if (options.jobs < 1) throw InputError(fmt::format("--jobs: {} is not >= 1", options.jobs));
  if (options.threads < 1) throw InputError(fmt::format("--threads: {} is not >= 1", options.threads));
}

}  // namespace

StudyOutcome run_study(const fs::path& dir, const RunnerOptions& options) {
  check_options(options);
  StopSignals signals;
  return StudyLoop(dir, options).run();
}

int run_study_case(const fs::path& dir, int index, const RunnerOptions& options) {
  check_options(options);
  const nlohmann::ordered_json plan = read_plan(dir);
  const int count = static_cast<int>(plan["cases"].size());
  if (index < 0 || index >= count)
    throw InputError(fmt::format("--index: {} is not in [0, {}] (the study has {} cases)", index, count - 1, count));
  const fs::path case_dir = dir / case_folder(index);
  CaseStatus status = read_case_status(case_dir);
  if (status.state == CaseState::done) return 0;
  while (case_run_alive(case_dir)) std::this_thread::sleep_for(std::chrono::milliseconds(200));
  if (mark_done_if_finished(case_dir)) return 0;  // the run that held it finished the case
  status = read_case_status(case_dir);
  status.state = CaseState::running;
  ++status.attempts;
  write_case_status(case_dir, status);
  const auto start = Clock::now();
  const pid_t pid = spawn_case(case_dir, options);
  int wait_status = 0;
  while (::waitpid(pid, &wait_status, 0) < 0)
    if (errno != EINTR) throw std::runtime_error(fmt::format("waitpid: {}", std::strerror(errno)));
  status.exit_status = exit_status_of(wait_status);
  status.wall_seconds += std::chrono::duration<double>(Clock::now() - start).count();
  std::error_code error;
  status.state = status.exit_status == 0 && fs::is_regular_file(case_dir / "summary.json", error) ? CaseState::done
                 : status.exit_status >= 128 ? CaseState::interrupted
                                             : CaseState::failed;
  write_case_status(case_dir, status);
  return status.exit_status;
}

}  // namespace settle::study
