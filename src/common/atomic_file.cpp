#include "common/atomic_file.hpp"

#include <fmt/core.h>

#include "common/error.hpp"

namespace settle {

namespace fs = std::filesystem;

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
  std::error_code error;
  fs::rename(temporary_, path_, error);
  if (error) throw InputError(fmt::format("{}: cannot write ({})", path_.string(), error.message()));
  committed_ = true;
}

}  // namespace settle
