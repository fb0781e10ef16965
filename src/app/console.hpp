#pragma once
// What `settle run` tells the user on stderr, by verbosity: --quiet keeps warnings only (and the
// errors main() prints), the default adds the start-up lines, the progress and the end-of-run
// report, --verbose adds the preflight details and the sub-step timing. On a terminal the progress
// line is rewritten in place; in a log (CI, a batch job) it is printed as a new line each time.
#include <unistd.h>

#include <chrono>
#include <cstdio>
#include <string>
#include <vector>

#include <fmt/core.h>

namespace settle::app {

/// Writes to stderr and ignores a failure: after SIGHUP the terminal is gone (EIO), after SIGPIPE
/// the pipe (EPIPE), and the run must still reach its checkpoint (fmt::print would throw).
inline void write_stderr(const std::string& text) { std::fputs(text.c_str(), stderr); }

/// silent: nothing at all (the ranks other than 0 of a run across processes).
enum class Verbosity { silent, quiet, normal, verbose };

class Console {
 public:
  explicit Console(Verbosity verbosity) : verbosity_(verbosity), terminal_(isatty(fileno(stderr)) == 1) {}

  Console(const Console&) = delete;
  Console& operator=(const Console&) = delete;
  ~Console() {
    if (log_ != nullptr) std::fclose(log_);
  }

  void warning(const std::string& text) {
    if (verbosity_ == Verbosity::silent) return;
    line("warning: " + text);
    record("warning: " + text);
  }
  void info(const std::string& text) {
    if (verbosity_ == Verbosity::silent) return;
    if (verbosity_ != Verbosity::quiet) line(text);
    record(text);  // the log keeps the default verbosity's lines under --quiet too
  }
  void detail(const std::string& text) {
    if (verbosity_ != Verbosity::verbose) return;
    line(text);
    record(text);
  }
  /// A line for the log alone (the error main() prints on stderr when the run fails).
  void log_only(const std::string& text) {
    if (verbosity_ != Verbosity::silent) record(text);
  }
  /// Starts writing the lines to `log` (run.log), the ones said so far first; the console keeps
  /// ownership and closes it. nullptr: no log (stderr is that file already, as under settle study).
  void attach_log(std::FILE* log) {
    log_ = log;
    if (log_ == nullptr) return;
    for (const std::string& text : pending_) write_log(text);
    pending_.clear();
  }
  void progress(const std::string& text) {
    if (verbosity_ == Verbosity::silent) return;
    const auto now = std::chrono::steady_clock::now();
    if (now - last_logged_progress_ >= kLogProgressInterval) {
      record(text);
      last_logged_progress_ = now;
    }
    if (verbosity_ == Verbosity::quiet) return;
    if (!terminal_) return line(text);
    // \r and clear to the end of the line (ANSI EL): a shorter line leaves nothing behind.
    write_stderr(fmt::format("\rsettle run: {}\x1b[K", text));
    std::fflush(stderr);
    progress_open_ = true;
  }
  /// Wall seconds between progress reports: often in place on a terminal, sparingly in a log.
  double progress_interval_s() const {
    if (terminal_) return 1.0;
    return verbosity_ == Verbosity::verbose ? 2.0 : 10.0;
  }

 private:
  void line(const std::string& text) {
    if (progress_open_) write_stderr("\n");
    progress_open_ = false;
    write_stderr(fmt::format("settle run: {}\n", text));
  }

  // The log's progress every 10 s of wall time, as in a batch job's stderr.
  static constexpr std::chrono::seconds kLogProgressInterval{10};

  void record(const std::string& text) {
    if (log_ == nullptr) {
      pending_.push_back(text);
      return;
    }
    write_log(text);
  }
  // Flushed line by line: a run killed by SIGKILL keeps its log up to its last line.
  void write_log(const std::string& text) {
    std::fputs(fmt::format("settle run: {}\n", text).c_str(), log_);
    std::fflush(log_);
  }

  Verbosity verbosity_;
  bool terminal_;
  bool progress_open_ = false;
  std::FILE* log_ = nullptr;
  std::vector<std::string> pending_;
  std::chrono::steady_clock::time_point last_logged_progress_{};
};

}  // namespace settle::app
