#pragma once
// The checkpoint file: a small header, named sections of bytes, each guarded by a CRC-32, written
// atomically. The file knows nothing of what the sections mean (coupling/checkpoint_state.hpp
// fills them), so the run loop can add sections of its own next to the simulation's.
//
// Layout (all integers little-endian; docs/checkpoints.md has the table):
//   header   "SETTLECK" (8 bytes), format version u32, header bytes u32 (= 32),
//            file bytes u64 (the whole file, trailer included), section count u32,
//            CRC-32 of the preceding 28 header bytes u32
//   sections, each: name bytes u32, name (UTF-8, no terminator), data bytes u64, data,
//            CRC-32 of the section's name length, name, data length and data u32
//   trailer  "SETTLEND" (8 bytes)
// A truncated file is caught by the file size the header announces, a corrupt one by the CRC-32
// of the header or of the section it falls in (CRC-32 detects every burst error up to 32 bits
// and any other corruption with probability 1 - 2^-32).
//
// Writes are atomic: the file is written as <file>.tmp next to the target, flushed to the disk
// (fsync), renamed over the target and the directory entry flushed too. Until the rename the
// previous checkpoint stays complete and untouched; after it the new one is. A crash at any moment
// leaves one complete checkpoint (and at worst a stale .tmp, overwritten next time).
//
// Reading maps the file into memory (mmap) and verifies every checksum before any section is
// handed out; sections are views into the mapping, so a fluid of many gigabytes is not copied twice.
#include <bit>
#include <cstddef>
#include <cstdint>
#include <filesystem>
#include <span>
#include <string>
#include <string_view>
#include <vector>

#include <Eigen/Core>

#include "common/error.hpp"

namespace settle {

static_assert(std::endian::native == std::endian::little,
              "checkpoints store integers and floating-point values in little-endian byte order");

/// Version of the file layout and of the meaning of the sections settle writes. A reader refuses
/// every other version. 2: the simulation record holds the last step's accelerations (the
/// corrector's virtual-mass estimate, coupling/simulation.hpp) after the internal fluid momentum.
inline constexpr std::uint32_t kCheckpointFormatVersion = 3;

/// A checkpoint that cannot be used: unreadable, truncated, corrupt, of another format version or
/// written for another case. The user can fix it (choose another checkpoint or the right case), so
/// the front end reports it like any input error (exit status 2).
class CheckpointError : public InputError {
 public:
  explicit CheckpointError(const std::string& message) : InputError(message) {}
};

/// CRC-32 (the IEEE 802.3 / zlib / PNG polynomial 0x04C11DB7, reflected, initial and final value
/// 0xFFFFFFFF), continued from `crc` (0 for a fresh start): crc32(b, crc32(a)) == crc32(a + b).
/// Slicing-by-8 (Kounavis and Berry 2008, "Novel table lookup-based algorithms for high-performance
/// CRC generation", IEEE Trans. Computers 57, 1550, doi:10.1109/TC.2008.85).
std::uint32_t crc32(std::span<const std::byte> data, std::uint32_t crc = 0);

/// crc32 of `bytes` bytes of `file` from `offset` on, continued from `crc`. settle::InputError naming
/// the file when it cannot be read or ends before.
std::uint32_t crc32_of_file(const std::filesystem::path& file, std::uintmax_t offset, std::uintmax_t bytes,
                            std::uint32_t crc = 0);

/// Collects sections and writes them as one checkpoint file.
class CheckpointWriter {
 public:
  /// Adds a section that the writer copies (small records).
  void add_copy(std::string name, std::vector<std::byte> data);
  /// Adds a section the writer only points to (large arrays such as the fluid's populations): the
  /// data must stay alive and unchanged until write() returns.
  void add_view(std::string name, std::span<const std::byte> data);

  /// Writes the file atomically (file comment). Throws CheckpointError naming the path on any I/O
  /// failure, std::invalid_argument for a repeated or empty section name.
  void write(const std::filesystem::path& file) const;

 private:
  struct Section {
    std::string name;
    std::vector<std::byte> owned;  ///< the data of add_copy
    std::span<const std::byte> data;
  };
  std::vector<Section> sections_;
};

/// True when `file` is a regular file that starts with a checkpoint's signature (SETTLECK); with
/// `cut_allowed` also when it is a shorter prefix of it (a <file>.tmp cut off before its header
/// was written). How a fresh run recognises a checkpoint of an earlier run before removing it.
bool is_checkpoint_file(const std::filesystem::path& file, bool cut_allowed = false);

/// A checkpoint file opened and verified. Move-only: the sections are views into its mapping.
class CheckpointFile {
 public:
  /// Maps `file`, checks magic, version, size and every CRC-32. Throws CheckpointError with a
  /// message naming the file and what is wrong (missing, truncated, corrupt section, version).
  explicit CheckpointFile(const std::filesystem::path& file);
  ~CheckpointFile();
  CheckpointFile(CheckpointFile&& other) noexcept;
  CheckpointFile& operator=(CheckpointFile&& other) noexcept;
  CheckpointFile(const CheckpointFile&) = delete;
  CheckpointFile& operator=(const CheckpointFile&) = delete;

  const std::filesystem::path& path() const { return path_; }
  std::uint32_t version() const { return version_; }
  /// Section names in file order.
  std::vector<std::string> section_names() const;
  bool has(std::string_view name) const;
  /// The data of a section (a view valid while this object lives). Throws CheckpointError when
  /// the file has no such section.
  std::span<const std::byte> section(std::string_view name) const;

 private:
  struct Entry {
    std::string name;
    std::span<const std::byte> data;
  };
  void unmap() noexcept;

  std::filesystem::path path_;
  const std::byte* map_ = nullptr;
  std::size_t map_bytes_ = 0;
  std::uint32_t version_ = 0;
  std::vector<Entry> entries_;
};

/// Appends fixed-size little-endian values to a byte record (a section's contents).
class RecordWriter {
 public:
  void u32(std::uint32_t value) { raw(&value, sizeof value); }
  void u64(std::uint64_t value) { raw(&value, sizeof value); }
  void i64(std::int64_t value) { raw(&value, sizeof value); }
  /// The exact bits of the double (restores bit for bit, NaN payloads included).
  void f64(double value) { raw(&value, sizeof value); }
  void vec3(const Eigen::Vector3d& v) {
    for (int a = 0; a < 3; ++a) f64(v[a]);
  }
  /// Length (u64) then the bytes.
  void string(std::string_view text);
  void raw(const void* data, std::size_t bytes);
  std::vector<std::byte> take() { return std::move(bytes_); }

 private:
  std::vector<std::byte> bytes_;
};

/// Reads what RecordWriter wrote, checking every read against the record's end (a record shorter
/// than its reader expects throws CheckpointError naming the section).
class RecordReader {
 public:
  RecordReader(std::span<const std::byte> data, std::string section) : data_(data), section_(std::move(section)) {}
  std::uint32_t u32() { return value<std::uint32_t>(); }
  std::uint64_t u64() { return value<std::uint64_t>(); }
  std::int64_t i64() { return value<std::int64_t>(); }
  double f64() { return value<double>(); }
  Eigen::Vector3d vec3() {
    Eigen::Vector3d v;
    for (int a = 0; a < 3; ++a) v[a] = f64();
    return v;
  }
  std::string string();
  void raw(void* out, std::size_t bytes);
  /// Throws CheckpointError unless every byte was read (a record longer than its reader expects).
  void expect_end() const;

 private:
  template <class T>
  T value() {
    T v;
    raw(&v, sizeof v);
    return v;
  }
  std::span<const std::byte> data_;
  std::size_t offset_ = 0;
  std::string section_;
};

}  // namespace settle
