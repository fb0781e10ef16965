#pragma once
// Errors that the user can fix (bad flag, bad case key, unreadable file): the front end prints
// the message and exits with status 2. A run that diverged: status 3. A run stopped by a signal:
// 128 + the signal. Everything else is a bug and exits with 1.
#include <stdexcept>
#include <string>

namespace settle {

/// A problem with the user's input. The message names the flag, key or file at fault and
/// says what is allowed, e.g. "--dt: must be > 0, got -1".
class InputError : public std::runtime_error {
 public:
  explicit InputError(const std::string& message) : std::runtime_error(message) {}
};

/// A run stopped because its numbers went bad (NaN, Mach or density out of range). The message
/// names the measured value, the likely cause and the setting to change.
class NumericalError : public std::runtime_error {
 public:
  explicit NumericalError(const std::string& message) : std::runtime_error(message) {}
};

/// A run stopped by a signal (SIGINT, SIGTERM) after it wrote a checkpoint: not a failure. The
/// message says how to continue; the front end exits with 128 + the signal's number, the status
/// a shell reports for a process that signal ended (130 for SIGINT, 143 for SIGTERM).
class RunInterrupted : public std::runtime_error {
 public:
  RunInterrupted(const std::string& message, int signal_number)
      : std::runtime_error(message), signal_number_(signal_number) {}
  int exit_status() const { return 128 + signal_number_; }

 private:
  int signal_number_;
};

}  // namespace settle
