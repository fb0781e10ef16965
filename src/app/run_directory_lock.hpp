#pragma once
// One `settle run` at a time per output directory: a second run or restart into a directory that a
// live run is writing would interleave two time series and overwrite each other's checkpoints
// (seen on 2026-11-26: docs/notes.md). An advisory flock(2) on DIR/.settle_run.lock
// (common/file_lock.hpp), held for the process's life and released by the kernel however the
// process ends, so a killed run leaves no stale lock behind.
#include <filesystem>
#include <optional>

#include "common/file_lock.hpp"

namespace settle::app {

class RunDirectoryLock {
 public:
  /// Takes the lock of `dir` (which must exist); settle::InputError naming the directory when
  /// another process holds it.
  explicit RunDirectoryLock(const std::filesystem::path& dir);

  static constexpr const char* kFileName = kRunLockFileName;

 private:
  std::optional<FileLock> lock_;
};

/// The same refusal, read-only (nothing is created): before a survey of `dir` whose files a live
/// run is writing.
void refuse_if_live_run(const std::filesystem::path& dir);

}  // namespace settle::app
