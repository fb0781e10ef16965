#include "common/atomic_file.hpp"

#include <fcntl.h>
#include <unistd.h>

#include <cerrno>
#include <cstring>
#include <string>

#include <fmt/core.h>

#include "common/error.hpp"

namespace settle {
namespace {

namespace fs = std::filesystem;

// Opens `path` read-only (enough for fsync on Linux) and flushes it; false with errno set when
// either fails.
bool fsync_path(const fs::path& path, int flags) {
  const int fd = ::open(path.empty() ? "." : path.c_str(), O_RDONLY | O_CLOEXEC | flags);
  if (fd < 0) return false;
  const bool synced = ::fsync(fd) == 0;
  const int saved = errno;
  ::close(fd);
  errno = saved;
  return synced;
}

std::string system_error_text() { return std::strerror(errno); }

}  // namespace

AtomicFile::AtomicFile(fs::path path) : path_(std::move(path)), temporary_(path_) {
  temporary_ += ".tmp";
  out_.open(temporary_, std::ios::binary | std::ios::trunc);
  if (!out_) throw InputError(fmt::format("{}: cannot write (cannot create {})", path_.string(), temporary_.string()));
}

AtomicFile::~AtomicFile() {
  if (committed_) return;
  out_.close();
  std::error_code ignored;
  fs::remove(temporary_, ignored);
}

void AtomicFile::commit() {
  out_.flush();
  const bool written = static_cast<bool>(out_);
  out_.close();
  if (!written || out_.fail()) throw InputError(fmt::format("{}: cannot write (write failed)", path_.string()));
  if (!fsync_path(temporary_, 0))
    throw InputError(
        fmt::format("{}: cannot flush {} to the disk ({})", path_.string(), temporary_.string(), system_error_text()));
  std::error_code error;
  fs::rename(temporary_, path_, error);
  if (error) throw InputError(fmt::format("{}: cannot write ({})", path_.string(), error.message()));
  committed_ = true;
  // Without this a power cut after the rename can bring back the old name.
  if (!fsync_path(path_.parent_path(), O_DIRECTORY))
    throw InputError(
        fmt::format("{}: cannot flush its directory to the disk ({})", path_.string(), system_error_text()));
}

void write_file_atomically(const fs::path& path, std::string_view text) {
  AtomicFile file(path);
  file.stream() << text;
  file.commit();
}

void sync_file_to_disk(const fs::path& file) {
  if (!fsync_path(file, 0))
    throw InputError(fmt::format("{}: cannot flush it to the disk ({})", file.string(), system_error_text()));
}

}  // namespace settle
