#pragma once
// An advisory flock(2) on a lock file, held for the life of the object and released by the kernel
// however the process ends (a killed process leaves no stale lock behind). One `settle run` at a
// time per run directory (DIR/.settle_run.lock, app/run_directory_lock.hpp) and one `settle study
// run` at a time per study directory (DIR/.settle_study.lock).
#include <filesystem>
#include <optional>

namespace settle {

/// The lock files: of a run directory (settle run) and of a study directory (settle study run).
inline constexpr const char* kRunLockFileName = ".settle_run.lock";
inline constexpr const char* kStudyLockFileName = ".settle_study.lock";

class FileLock {
 public:
  /// Creates `file` if needed and takes its lock; none when another process (or another open of
  /// the file) holds it. settle::InputError naming the file when it cannot be created or locked
  /// for another reason.
  static std::optional<FileLock> try_take(const std::filesystem::path& file);
  ~FileLock();
  FileLock(FileLock&& other) noexcept;
  FileLock& operator=(FileLock&& other) noexcept;
  FileLock(const FileLock&) = delete;
  FileLock& operator=(const FileLock&) = delete;

 private:
  explicit FileLock(int fd) : fd_(fd) {}
  int fd_ = -1;
};

/// True when another process holds the lock of `file` (false when the file does not exist).
bool lock_is_held(const std::filesystem::path& file);

}  // namespace settle
