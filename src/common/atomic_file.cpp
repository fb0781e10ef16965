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

}  // namespace

std::string system_error_text() { return std::strerror(errno); }

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
  errno = 0;
  out_.flush();
  const bool written = static_cast<bool>(out_);
  out_.close();
  // The stream keeps no reason; errno holds the failed write's (ENOSPC, EFBIG under a file-size
  // limit) when the stream failed in this call, else an earlier write's, or 0.
  if (!written || out_.fail())
    throw InputError(fmt::format("{}: cannot write (write failed{})", path_.string(),
                                 errno != 0 ? ": " + system_error_text() : std::string()));
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

bool file_starts_with(const fs::path& file, std::string_view signature, bool cut_allowed) {
  std::error_code error;
  if (!fs::is_regular_file(fs::symlink_status(file, error))) return false;
  std::ifstream in(file, std::ios::binary);
  std::string head(signature.size(), '\0');
  in.read(head.data(), static_cast<std::streamsize>(head.size()));
  head.resize(static_cast<std::size_t>(in.gcount()));
  if (head.size() == signature.size()) return head == signature;
  return cut_allowed && in.eof() && signature.substr(0, head.size()) == head;
}

void sync_file_to_disk(const fs::path& file) {
  if (!fsync_path(file, 0))
    throw InputError(fmt::format("{}: cannot flush it to the disk ({})", file.string(), system_error_text()));
}

}  // namespace settle
