#include "app/run_directory_lock.hpp"

#include <fcntl.h>
#include <sys/file.h>
#include <unistd.h>

#include <cerrno>
#include <cstring>

#include <fmt/core.h>

#include "common/error.hpp"

namespace settle::app {

RunDirectoryLock::RunDirectoryLock(const std::filesystem::path& dir) {
  const std::filesystem::path file = dir / kFileName;
  fd_ = ::open(file.c_str(), O_RDWR | O_CREAT | O_CLOEXEC, 0644);
  if (fd_ < 0) throw InputError(fmt::format("-o: cannot create {}: {}", file.string(), std::strerror(errno)));
  if (::flock(fd_, LOCK_EX | LOCK_NB) != 0) {
    const int error = errno;
    ::close(fd_);
    fd_ = -1;
    if (error == EWOULDBLOCK)
      throw InputError(
          fmt::format("{}: another settle run is writing this directory; wait for it to end, or stop it "
                      "(SIGINT or SIGTERM writes its checkpoint) before restarting",
                      dir.string()));
    throw InputError(fmt::format("-o: cannot lock {}: {}", file.string(), std::strerror(error)));
  }
}

RunDirectoryLock::~RunDirectoryLock() {
  if (fd_ >= 0) ::close(fd_);  // closing releases the lock
}

}  // namespace settle::app
