#pragma once
// What `settle run` tells the user on stderr, by verbosity: --quiet keeps warnings only (and the
// errors main() prints), the default adds the start-up lines, the progress and the end-of-run
// report, --verbose adds the preflight details and the sub-step timing. On a terminal the progress
// line is rewritten in place; in a log (CI, a batch job) it is printed as a new line each time.
#include <unistd.h>

#include <cstdio>
#include <string>

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

  void warning(const std::string& text) {
    if (verbosity_ != Verbosity::silent) line("warning: " + text);
  }
  void info(const std::string& text) {
    if (verbosity_ != Verbosity::quiet && verbosity_ != Verbosity::silent) line(text);
  }
  void detail(const std::string& text) {
    if (verbosity_ == Verbosity::verbose) line(text);
  }
  void progress(const std::string& text) {
    if (verbosity_ == Verbosity::quiet || verbosity_ == Verbosity::silent) return;
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

  Verbosity verbosity_;
  bool terminal_;
  bool progress_open_ = false;
};

}  // namespace settle::app
