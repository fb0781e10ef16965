#include "app/run_directory_lock.hpp"

#include <fmt/core.h>

#include "common/error.hpp"

namespace settle::app {

namespace {

[[noreturn]] void refuse_live_run(const std::filesystem::path& dir) {
  throw InputError(
      fmt::format("{}: another settle run is writing this directory; wait for it to end, or stop it "
                  "(SIGINT or SIGTERM writes its checkpoint) before restarting",
                  dir.string()));
}

}  // namespace

RunDirectoryLock::RunDirectoryLock(const std::filesystem::path& dir) {
  try {
    lock_ = FileLock::try_take(dir / kFileName);
  } catch (const InputError& e) {
    throw InputError(fmt::format("-o: {}", e.what()));
  }
  if (!lock_) refuse_live_run(dir);
}

void refuse_if_live_run(const std::filesystem::path& dir) {
  if (lock_is_held(dir / RunDirectoryLock::kFileName)) refuse_live_run(dir);
}

}  // namespace settle::app
