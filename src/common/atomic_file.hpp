#pragma once
// Files that appear whole or not at all: the content goes to "<path>.tmp" beside the target and
// commit() renames it over the target (atomic within one POSIX file system), so a reader never
// sees half a file. Until the rename the previous file stays complete and untouched.
#include <filesystem>
#include <fstream>

namespace settle {

/// A file written through a stream and published by commit(). Destroying it uncommitted removes
/// the temporary. Errors raise settle::InputError naming the target path.
class AtomicFile {
 public:
  explicit AtomicFile(std::filesystem::path path);
  AtomicFile(const AtomicFile&) = delete;
  AtomicFile& operator=(const AtomicFile&) = delete;
  ~AtomicFile();

  std::ostream& stream() { return out_; }
  void commit();

 private:
  std::filesystem::path path_;
  std::filesystem::path temporary_;
  std::ofstream out_;
  bool committed_ = false;
};

}  // namespace settle
