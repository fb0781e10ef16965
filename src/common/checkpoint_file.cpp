#include "common/checkpoint_file.hpp"

#include <fcntl.h>
#include <sys/mman.h>
#include <sys/stat.h>
#include <unistd.h>

#include <algorithm>
#include <array>
#include <cerrno>
#include <cstring>
#include <fstream>
#include <ostream>
#include <stdexcept>
#include <utility>

#include <fmt/core.h>

#include "common/atomic_file.hpp"

namespace settle {
namespace {

constexpr std::array<char, 8> kMagic{'S', 'E', 'T', 'T', 'L', 'E', 'C', 'K'};
constexpr std::array<char, 8> kTrailer{'S', 'E', 'T', 'T', 'L', 'E', 'N', 'D'};
constexpr std::uint32_t kHeaderBytes = 32;

using CrcTables = std::array<std::array<std::uint32_t, 256>, 8>;

// Table k advances the CRC over a byte followed by k zero bytes, so eight table look-ups consume
// eight bytes at once (slicing-by-8).
constexpr CrcTables make_crc_tables() {
  CrcTables t{};
  for (std::uint32_t i = 0; i < 256; ++i) {
    std::uint32_t c = i;
    for (int bit = 0; bit < 8; ++bit) c = (c & 1u) ? (c >> 1) ^ 0xEDB88320u : c >> 1;
    t[0][i] = c;
  }
  for (std::size_t k = 1; k < 8; ++k)
    for (std::size_t i = 0; i < 256; ++i) t[k][i] = (t[k - 1][i] >> 8) ^ t[0][t[k - 1][i] & 0xFFu];
  return t;
}
constexpr CrcTables kCrcTables = make_crc_tables();

class FileDescriptor {
 public:
  explicit FileDescriptor(int fd) : fd_(fd) {}
  ~FileDescriptor() {
    if (fd_ >= 0) ::close(fd_);
  }
  FileDescriptor(const FileDescriptor&) = delete;
  FileDescriptor& operator=(const FileDescriptor&) = delete;
  int get() const { return fd_; }

 private:
  int fd_;
};

void put(std::ostream& out, std::span<const std::byte> data) {
  out.write(reinterpret_cast<const char*>(data.data()), static_cast<std::streamsize>(data.size()));
}

template <class T>
std::span<const std::byte> bytes_of(const T& value) {
  return std::as_bytes(std::span<const T>(&value, 1));
}

template <class T>
T load(const std::byte* p) {
  T value;
  std::memcpy(&value, p, sizeof value);
  return value;
}

}  // namespace

std::uint32_t crc32(std::span<const std::byte> data, std::uint32_t crc) {
  const auto& t = kCrcTables;
  crc = ~crc;
  const std::byte* p = data.data();
  std::size_t n = data.size();
  for (; n >= 8; n -= 8, p += 8) {
    const std::uint32_t low = load<std::uint32_t>(p) ^ crc;
    const std::uint32_t high = load<std::uint32_t>(p + 4);
    crc = t[7][low & 0xFFu] ^ t[6][(low >> 8) & 0xFFu] ^ t[5][(low >> 16) & 0xFFu] ^ t[4][low >> 24] ^
          t[3][high & 0xFFu] ^ t[2][(high >> 8) & 0xFFu] ^ t[1][(high >> 16) & 0xFFu] ^ t[0][high >> 24];
  }
  for (; n > 0; --n, ++p) crc = (crc >> 8) ^ t[0][(crc ^ std::to_integer<std::uint32_t>(*p)) & 0xFFu];
  return ~crc;
}

std::uint32_t crc32_of_file(const std::filesystem::path& file, std::uintmax_t offset, std::uintmax_t bytes,
                            std::uint32_t crc) {
  std::ifstream in(file, std::ios::binary);
  if (!in) throw InputError(fmt::format("{}: cannot read it: {}", file.string(), system_error_text()));
  in.seekg(static_cast<std::streamoff>(offset));
  std::vector<std::byte> buffer(std::size_t{1} << 20);
  while (bytes > 0) {
    const auto chunk = static_cast<std::size_t>(std::min<std::uintmax_t>(bytes, buffer.size()));
    in.read(reinterpret_cast<char*>(buffer.data()), static_cast<std::streamsize>(chunk));
    if (static_cast<std::size_t>(in.gcount()) != chunk)
      throw InputError(fmt::format("{}: ends before byte {}", file.string(), offset + chunk));
    crc = crc32(std::span(buffer).first(chunk), crc);
    offset += chunk;
    bytes -= chunk;
  }
  return crc;
}

// ---------------------------------------------------------------- writing

void CheckpointWriter::add_copy(std::string name, std::vector<std::byte> data) {
  sections_.push_back({std::move(name), std::move(data), {}});
  sections_.back().data = sections_.back().owned;
}

void CheckpointWriter::add_view(std::string name, std::span<const std::byte> data) {
  sections_.push_back({std::move(name), {}, data});
}

void CheckpointWriter::write(const std::filesystem::path& file) const {
  for (std::size_t i = 0; i < sections_.size(); ++i) {
    if (sections_[i].name.empty()) throw std::invalid_argument("checkpoint: empty section name");
    for (std::size_t j = 0; j < i; ++j)
      if (sections_[j].name == sections_[i].name)
        throw std::invalid_argument("checkpoint: section '" + sections_[i].name + "' added twice");
  }
  std::uint64_t file_bytes = kHeaderBytes + kTrailer.size();
  for (const Section& s : sections_) file_bytes += 4 + s.name.size() + 8 + s.data.size() + 4;

  // The file layer (common/atomic_file.hpp) writes <file>.tmp, flushes it to the disk, renames it
  // over the target and flushes the directory entry.
  try {
    AtomicFile out(file);
    std::ostream& stream = out.stream();
    std::array<std::byte, kHeaderBytes> header{};
    std::memcpy(header.data(), kMagic.data(), kMagic.size());
    const auto section_count = static_cast<std::uint32_t>(sections_.size());
    std::memcpy(header.data() + 8, &kCheckpointFormatVersion, 4);
    std::memcpy(header.data() + 12, &kHeaderBytes, 4);
    std::memcpy(header.data() + 16, &file_bytes, 8);
    std::memcpy(header.data() + 24, &section_count, 4);
    const std::uint32_t header_crc = crc32(std::span(header).first(28));
    std::memcpy(header.data() + 28, &header_crc, 4);
    put(stream, header);

    for (const Section& s : sections_) {
      const auto name_bytes = static_cast<std::uint32_t>(s.name.size());
      const std::uint64_t data_bytes = s.data.size();
      const auto name = std::as_bytes(std::span(s.name));
      std::uint32_t crc = crc32(bytes_of(name_bytes));
      crc = crc32(name, crc);
      crc = crc32(bytes_of(data_bytes), crc);
      crc = crc32(s.data, crc);
      put(stream, bytes_of(name_bytes));
      put(stream, name);
      put(stream, bytes_of(data_bytes));
      put(stream, s.data);
      put(stream, bytes_of(crc));
    }
    put(stream, std::as_bytes(std::span(kTrailer)));
    out.commit();
  } catch (const CheckpointError&) {
    throw;
  } catch (const InputError& e) {
    throw CheckpointError(fmt::format("cannot write the checkpoint: {}", e.what()));
  }
}

bool is_checkpoint_file(const std::filesystem::path& file, bool cut_allowed) {
  return file_starts_with(file, std::string_view(kMagic.data(), kMagic.size()), cut_allowed);
}

// ---------------------------------------------------------------- reading

CheckpointFile::CheckpointFile(const std::filesystem::path& file) : path_(file) {
  const std::string name = file.string();
  const FileDescriptor in(::open(file.c_str(), O_RDONLY | O_CLOEXEC));
  if (in.get() < 0) throw CheckpointError(fmt::format("{}: cannot open the checkpoint: {}", name, system_error_text()));
  struct stat info {};
  if (::fstat(in.get(), &info) != 0)
    throw CheckpointError(fmt::format("{}: cannot read the checkpoint: {}", name, system_error_text()));
  const auto size = static_cast<std::size_t>(info.st_size);
  if (size < kHeaderBytes + kTrailer.size())
    throw CheckpointError(
        fmt::format("{}: {} bytes is too short for a settle checkpoint (truncated or not a "
                    "checkpoint)",
                    name, size));
  void* map = ::mmap(nullptr, size, PROT_READ, MAP_PRIVATE, in.get(), 0);
  if (map == MAP_FAILED)
    throw CheckpointError(fmt::format("{}: cannot map the checkpoint: {}", name, system_error_text()));
  map_ = static_cast<const std::byte*>(map);
  map_bytes_ = size;
  ::madvise(map, size, MADV_SEQUENTIAL);  // a hint only: its failure changes nothing

  try {
    const std::byte* p = map_;
    if (std::memcmp(p, kMagic.data(), kMagic.size()) != 0)
      throw CheckpointError(fmt::format("{}: not a settle checkpoint (no SETTLECK signature)", name));
    const auto header_crc = load<std::uint32_t>(p + 28);
    if (crc32(std::span(p, 28)) != header_crc)
      throw CheckpointError(fmt::format("{}: the checkpoint header fails its CRC-32 check: the file is corrupt", name));
    version_ = load<std::uint32_t>(p + 8);
    if (version_ != kCheckpointFormatVersion)
      throw CheckpointError(fmt::format("{}: checkpoint format version {}; this settle reads version {} only", name,
                                        version_, kCheckpointFormatVersion));
    const auto header_bytes = load<std::uint32_t>(p + 12);
    const auto file_bytes = load<std::uint64_t>(p + 16);
    const auto section_count = load<std::uint32_t>(p + 24);
    if (header_bytes != kHeaderBytes)
      throw CheckpointError(fmt::format("{}: header of {} bytes, version {} has {}: the file is corrupt", name,
                                        header_bytes, version_, kHeaderBytes));
    if (size < file_bytes)
      throw CheckpointError(
          fmt::format("{}: truncated: the file holds {} of the {} bytes its header announces (was "
                      "the write interrupted?)",
                      name, size, file_bytes));
    if (size > file_bytes)
      throw CheckpointError(
          fmt::format("{}: {} bytes where the header announces {}: the file is corrupt", name, size, file_bytes));

    const std::size_t body_end = size - kTrailer.size();
    std::size_t offset = kHeaderBytes;
    // Lengths are read before the section's CRC-32 can be checked, so each is bounded first.
    const auto need = [&](std::uint64_t bytes, std::uint32_t index) {
      if (bytes > body_end - offset)
        throw CheckpointError(
            fmt::format("{}: section {} runs past the end of the file: the file is corrupt", name, index));
    };
    for (std::uint32_t i = 0; i < section_count; ++i) {
      const std::size_t start = offset;
      need(4, i);
      const auto name_bytes = load<std::uint32_t>(p + offset);
      offset += 4;
      need(name_bytes, i);
      std::string section_name(reinterpret_cast<const char*>(p + offset), name_bytes);
      offset += name_bytes;
      need(8, i);
      const auto data_bytes = load<std::uint64_t>(p + offset);
      offset += 8;
      need(data_bytes, i);
      const std::span<const std::byte> data(p + offset, static_cast<std::size_t>(data_bytes));
      offset += static_cast<std::size_t>(data_bytes);
      need(4, i);
      const auto stored = load<std::uint32_t>(p + offset);
      const std::uint32_t computed = crc32(std::span(p + start, offset - start));
      offset += 4;
      if (computed != stored)
        throw CheckpointError(
            fmt::format("{}: section '{}' fails its CRC-32 check (stored {:08x}, computed {:08x}): "
                        "the file is corrupt",
                        name, section_name, stored, computed));
      entries_.push_back({std::move(section_name), data});
    }
    if (offset != body_end || std::memcmp(p + body_end, kTrailer.data(), kTrailer.size()) != 0)
      throw CheckpointError(fmt::format("{}: no end marker after the last section: the file is corrupt", name));
  } catch (...) {
    unmap();
    throw;
  }
}

CheckpointFile::~CheckpointFile() { unmap(); }

CheckpointFile::CheckpointFile(CheckpointFile&& other) noexcept
    : path_(std::move(other.path_)),
      map_(std::exchange(other.map_, nullptr)),
      map_bytes_(std::exchange(other.map_bytes_, 0)),
      version_(other.version_),
      entries_(std::move(other.entries_)) {}

CheckpointFile& CheckpointFile::operator=(CheckpointFile&& other) noexcept {
  if (this != &other) {
    unmap();
    path_ = std::move(other.path_);
    map_ = std::exchange(other.map_, nullptr);
    map_bytes_ = std::exchange(other.map_bytes_, 0);
    version_ = other.version_;
    entries_ = std::move(other.entries_);
  }
  return *this;
}

void CheckpointFile::unmap() noexcept {
  if (map_) ::munmap(const_cast<std::byte*>(map_), map_bytes_);
  map_ = nullptr;
  map_bytes_ = 0;
}

std::vector<std::string> CheckpointFile::section_names() const {
  std::vector<std::string> names;
  for (const Entry& e : entries_) names.push_back(e.name);
  return names;
}

bool CheckpointFile::has(std::string_view name) const {
  return std::any_of(entries_.begin(), entries_.end(), [&](const Entry& e) { return e.name == name; });
}

std::span<const std::byte> CheckpointFile::section(std::string_view name) const {
  for (const Entry& e : entries_)
    if (e.name == name) return e.data;
  throw CheckpointError(fmt::format("{}: the checkpoint has no section '{}' (written by another version of settle?)",
                                    path_.string(), name));
}

// ---------------------------------------------------------------- records

void RecordWriter::string(std::string_view text) {
  u64(text.size());
  raw(text.data(), text.size());
}

void RecordWriter::raw(const void* data, std::size_t bytes) {
  const auto* p = static_cast<const std::byte*>(data);
  bytes_.insert(bytes_.end(), p, p + bytes);
}

std::string RecordReader::string() {
  const std::uint64_t length = u64();
  if (length > data_.size() - offset_)
    throw CheckpointError(
        fmt::format("checkpoint section '{}': a string of {} bytes runs past the section's end", section_, length));
  std::string text(static_cast<std::size_t>(length), '\0');
  raw(text.data(), text.size());
  return text;
}

void RecordReader::raw(void* out, std::size_t bytes) {
  if (bytes > data_.size() - offset_)
    throw CheckpointError(fmt::format("checkpoint section '{}' ends early ({} bytes; reading {} at {})", section_,
                                      data_.size(), bytes, offset_));
  if (bytes > 0) std::memcpy(out, data_.data() + offset_, bytes);
  offset_ += bytes;
}

void RecordReader::expect_end() const {
  if (offset_ != data_.size())
    throw CheckpointError(
        fmt::format("checkpoint section '{}' holds {} bytes, {} expected", section_, data_.size(), offset_));
}

}  // namespace settle
