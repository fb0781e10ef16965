#pragma once
// Files that appear whole or not at all, and that survive a crash once written: the one way
// settle writes its results (summary.json, case.resolved.toml, VTK files and collections,
// checkpoints).
//
// The content goes to "<path>.tmp" beside the target. commit() flushes it to the disk (fsync),
// renames it over the target (atomic within one POSIX file system) and flushes the directory
// entry too (fsync of the directory), so a reader never sees half a file, and after commit()
// returns neither a crash nor a power cut can bring back the old file or leave an empty one.
// Until the rename the previous file stays complete and untouched.
#include <filesystem>
#include <fstream>
#include <string>
#include <string_view>

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

/// Writes `text` to `path` through an AtomicFile.
void write_file_atomically(const std::filesystem::path& path, std::string_view text);

/// Flushes a file's data that is already written (e.g. by a stream) to the disk (fsync).
/// settle::InputError naming the file when it cannot.
void sync_file_to_disk(const std::filesystem::path& file);

/// True when `file` is a regular file whose first bytes are `signature` (how settle recognises a
/// file it wrote before it replaces or removes it: docs/errors.md, "Promises"). With
/// `cut_allowed`, also when the whole file is a shorter prefix of the signature: a temporary
/// file cut off before its first bytes reached the disk, empty or not.
bool file_starts_with(const std::filesystem::path& file, std::string_view signature, bool cut_allowed = false);

/// The operating system's reason for the last failed call (strerror(errno)), for messages.
std::string system_error_text();

}  // namespace settle
