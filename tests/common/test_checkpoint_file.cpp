// The checkpoint file format (common/checkpoint_file.hpp): CRC-32 against its published check values and
// an independent bitwise implementation, exact round trip of sections, atomic replacement, and
// refusal of every truncation and every single-bit corruption of a file.
#include <fcntl.h>
#include <gtest/gtest.h>
#include <unistd.h>

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <iterator>
#include <random>
#include <string>
#include <vector>

#include "common/checkpoint_file.hpp"

namespace settle {
namespace test_checkpoint_file {

namespace fs = std::filesystem;

std::span<const std::byte> bytes(std::string_view text) { return std::as_bytes(std::span(text)); }

std::vector<std::byte> random_bytes(std::size_t count, unsigned seed) {
  std::mt19937 rng(seed);
  std::vector<std::byte> data(count);
  for (auto& b : data) b = static_cast<std::byte>(rng() & 0xFFu);
  return data;
}

// The CRC-32 of the definition, one bit at a time (no tables), to check the sliced version.
std::uint32_t bitwise_crc32(std::span<const std::byte> data) {
  std::uint32_t crc = 0xFFFFFFFFu;
  for (const std::byte b : data) {
    crc ^= std::to_integer<std::uint32_t>(b);
    for (int bit = 0; bit < 8; ++bit) crc = (crc & 1u) ? (crc >> 1) ^ 0xEDB88320u : crc >> 1;
  }
  return ~crc;
}

std::vector<std::byte> read_all(const fs::path& file) {
  std::ifstream in(file, std::ios::binary);
  std::vector<char> chars((std::istreambuf_iterator<char>(in)), std::istreambuf_iterator<char>());
  std::vector<std::byte> data(chars.size());
  std::memcpy(data.data(), chars.data(), chars.size());
  return data;
}

void write_all(const fs::path& file, std::span<const std::byte> data) {
  std::ofstream out(file, std::ios::binary | std::ios::trunc);
  out.write(reinterpret_cast<const char*>(data.data()), static_cast<std::streamsize>(data.size()));
}

// A fresh directory per test, removed afterwards.
class CheckpointFileTest : public ::testing::Test {
 protected:
  void SetUp() override {
    dir_ = fs::temp_directory_path() / ("settle_checkpoint_" + std::to_string(::getpid()) + "_" +
                                        ::testing::UnitTest::GetInstance()->current_test_info()->name());
    fs::remove_all(dir_);
    fs::create_directories(dir_);
  }
  void TearDown() override { fs::remove_all(dir_); }

  // A small file of three sections: a text, an empty one and 300 random bytes.
  fs::path write_small(const std::vector<std::byte>& payload) {
    CheckpointWriter writer;
    writer.add_copy("text", std::vector<std::byte>(bytes("hello").begin(), bytes("hello").end()));
    writer.add_copy("empty", {});
    writer.add_view("payload", payload);
    const fs::path file = dir_ / "checkpoint.bin";
    writer.write(file);
    return file;
  }

  fs::path dir_;
};

TEST(Crc32, PublishedCheckValues) {
  // The check value of CRC-32 (the "123456789" test of the CRC catalogue: Williams 1993, "A
  // painless guide to CRC error detection algorithms"; the value zlib's crc32 returns): exact.
  EXPECT_EQ(crc32(bytes("123456789")), 0xCBF43926u);
  // Widely quoted value of the pangram (zlib.crc32 gives the same): exact.
  EXPECT_EQ(crc32(bytes("The quick brown fox jumps over the lazy dog")), 0x414FA339u);
  EXPECT_EQ(crc32({}), 0u);
}

TEST(Crc32, SlicedEqualsBitwiseAtEveryLengthAndContinues) {
  const std::vector<std::byte> data = random_bytes(1000, 7);
  // Every length 0..1000 covers all alignments of the 8-byte loop and its tail: exact.
  for (std::size_t n = 0; n <= data.size(); ++n)
    ASSERT_EQ(crc32(std::span(data).first(n)), bitwise_crc32(std::span(data).first(n))) << "length " << n;
  // Continuation: crc(a + b) = crc(b, crc(a)) at every split point: exact.
  const std::uint32_t whole = crc32(data);
  for (std::size_t split = 0; split <= data.size(); split += 37)
    ASSERT_EQ(crc32(std::span(data).subspan(split), crc32(std::span(data).first(split))), whole) << split;
}

TEST_F(CheckpointFileTest, RoundTripKeepsEverySectionExactly) {
  const std::vector<std::byte> large = random_bytes(3'000'017, 11);
  CheckpointWriter writer;
  writer.add_copy("first", std::vector<std::byte>(bytes("abc").begin(), bytes("abc").end()));
  writer.add_copy("empty", {});
  writer.add_view("large", large);
  const fs::path file = dir_ / "checkpoint.bin";
  writer.write(file);
  EXPECT_FALSE(fs::exists(dir_ / "checkpoint.bin.tmp"));

  const CheckpointFile read(file);
  EXPECT_EQ(read.version(), kCheckpointFormatVersion);
  EXPECT_EQ(read.section_names(), (std::vector<std::string>{"first", "empty", "large"}));
  const auto first = read.section("first");
  EXPECT_EQ(std::string(reinterpret_cast<const char*>(first.data()), first.size()), "abc");
  EXPECT_TRUE(read.section("empty").empty());
  const auto back = read.section("large");
  ASSERT_EQ(back.size(), large.size());
  EXPECT_TRUE(std::equal(back.begin(), back.end(), large.begin()));
  EXPECT_FALSE(read.has("missing"));
  EXPECT_THROW((void)read.section("missing"), CheckpointError);
}

TEST_F(CheckpointFileTest, MovedFileKeepsItsSections) {
  const std::vector<std::byte> payload = random_bytes(300, 3);
  CheckpointFile moved = CheckpointFile(write_small(payload));
  CheckpointFile target = std::move(moved);
  const auto back = target.section("payload");
  EXPECT_TRUE(std::equal(back.begin(), back.end(), payload.begin(), payload.end()));
}

TEST_F(CheckpointFileTest, RewriteReplacesThePreviousFile) {
  const fs::path file = write_small(random_bytes(300, 1));
  const std::vector<std::byte> second = random_bytes(500, 2);
  CheckpointWriter writer;
  writer.add_view("payload", second);
  writer.write(file);
  const CheckpointFile read(file);
  EXPECT_EQ(read.section_names(), std::vector<std::string>{"payload"});
  EXPECT_EQ(read.section("payload").size(), second.size());
}

TEST_F(CheckpointFileTest, FailedWriteLeavesThePreviousCheckpointWhole) {
  const std::vector<std::byte> payload = random_bytes(300, 1);
  const fs::path file = write_small(payload);
  // A directory where the temporary file must go makes the new write fail before the rename.
  fs::create_directory(dir_ / "checkpoint.bin.tmp");
  CheckpointWriter writer;
  writer.add_copy("other", random_bytes(10, 2));
  EXPECT_THROW(writer.write(file), CheckpointError);
  const CheckpointFile read(file);
  const auto back = read.section("payload");
  EXPECT_TRUE(std::equal(back.begin(), back.end(), payload.begin(), payload.end()));
}

TEST_F(CheckpointFileTest, UnwritableDirectoryNamesThePath) {
  CheckpointWriter writer;
  writer.add_copy("a", {});
  try {
    writer.write(dir_ / "no_such_dir" / "checkpoint.bin");
    FAIL() << "no exception";
  } catch (const CheckpointError& e) {
    EXPECT_NE(std::string(e.what()).find("no_such_dir"), std::string::npos) << e.what();
  }
}

TEST_F(CheckpointFileTest, RepeatedSectionNameIsABug) {
  CheckpointWriter writer;
  writer.add_copy("a", {});
  writer.add_copy("a", {});
  EXPECT_THROW(writer.write(dir_ / "x.bin"), std::invalid_argument);
}

TEST_F(CheckpointFileTest, EveryTruncationIsRefused) {
  const fs::path file = write_small(random_bytes(64, 5));
  const auto size = fs::file_size(file);
  // Cut the file shorter and shorter in place: every length from size - 1 down to 0.
  for (auto n = size; n-- > 0;) {
    fs::resize_file(file, n);
    try {
      CheckpointFile read(file);
      FAIL() << "a file cut to " << n << " of " << size << " bytes was accepted";
    } catch (const CheckpointError& e) {
      // The message says what happened, so that the user picks another file.
      EXPECT_NE(std::string(e.what()).find("truncated"), std::string::npos) << e.what();
    }
  }
}

TEST_F(CheckpointFileTest, EverySingleBitCorruptionIsRefused) {
  const fs::path file = write_small(random_bytes(64, 9));
  const std::vector<std::byte> whole = read_all(file);
  // Each flip is written in place (one byte, then restored), which keeps the 1500 trials fast.
  const int fd = ::open(file.c_str(), O_RDWR);
  ASSERT_GE(fd, 0);
  const auto put = [&](std::size_t at, std::byte value) {
    ASSERT_EQ(::pwrite(fd, &value, 1, static_cast<off_t>(at)), 1);
  };
  // CRC-32 detects every single-bit error in the data it covers; the magic, the trailer and the
  // header fields are covered by their own checks, so no flip anywhere may pass.
  for (std::size_t byte = 0; byte < whole.size(); ++byte) {
    for (int bit = 0; bit < 8; ++bit) {
      put(byte, whole[byte] ^ static_cast<std::byte>(1u << bit));
      EXPECT_THROW(CheckpointFile read(file), CheckpointError) << "byte " << byte << " bit " << bit;
    }
    put(byte, whole[byte]);
  }
  ::close(fd);
  EXPECT_NO_THROW(CheckpointFile read(file));  // restored: the trials changed nothing else
}

TEST_F(CheckpointFileTest, CorruptSectionIsNamed) {
  const fs::path file = write_small(random_bytes(300, 9));
  std::vector<std::byte> data = read_all(file);
  data[data.size() - 100] ^= std::byte{0x10};  // inside the 300-byte payload, the last section
  write_all(file, data);
  try {
    CheckpointFile read(file);
    FAIL() << "accepted";
  } catch (const CheckpointError& e) {
    const std::string message = e.what();
    EXPECT_NE(message.find("'payload'"), std::string::npos) << message;
    EXPECT_NE(message.find("corrupt"), std::string::npos) << message;
  }
}

TEST_F(CheckpointFileTest, OtherFormatVersionIsRefused) {
  const fs::path file = write_small(random_bytes(30, 9));
  std::vector<std::byte> data = read_all(file);
  const std::uint32_t version = kCheckpointFormatVersion + 1;
  std::memcpy(data.data() + 8, &version, 4);
  const std::uint32_t header_crc = crc32(std::span(data).first(28));  // a well-formed newer file
  std::memcpy(data.data() + 28, &header_crc, 4);
  write_all(file, data);
  try {
    CheckpointFile read(file);
    FAIL() << "accepted";
  } catch (const CheckpointError& e) {
    // Names the file's version and the one this build reads.
    EXPECT_NE(std::string(e.what()).find("format version " + std::to_string(version)), std::string::npos) << e.what();
    EXPECT_NE(std::string(e.what()).find("reads version " + std::to_string(kCheckpointFormatVersion)),
              std::string::npos)
        << e.what();
  }
}

TEST_F(CheckpointFileTest, MissingAndForeignFilesAreRefused) {
  EXPECT_THROW(CheckpointFile read(dir_ / "absent.bin"), CheckpointError);
  const std::string text(100, 'x');
  write_all(dir_ / "text.bin", bytes(text));
  try {
    CheckpointFile read(dir_ / "text.bin");
    FAIL() << "accepted";
  } catch (const CheckpointError& e) {
    EXPECT_NE(std::string(e.what()).find("not a settle checkpoint"), std::string::npos) << e.what();
  }
}

TEST(CheckpointRecords, RoundTripIsBitExactAndBoundsAreChecked) {
  RecordWriter out;
  out.u32(7);
  out.i64(-3);
  out.f64(-0.0);
  out.f64(0.1);
  out.vec3(Eigen::Vector3d(1.0 / 3.0, -2.5e-300, 4.0e300));
  out.string("name");
  const std::vector<std::byte> record = out.take();

  RecordReader in(record, "test");
  EXPECT_EQ(in.u32(), 7u);
  EXPECT_EQ(in.i64(), -3);
  EXPECT_TRUE(std::signbit(in.f64()));  // -0.0 keeps its sign: bits, not text
  EXPECT_EQ(in.f64(), 0.1);
  const Eigen::Vector3d v = in.vec3();
  EXPECT_EQ(v, Eigen::Vector3d(1.0 / 3.0, -2.5e-300, 4.0e300));
  EXPECT_EQ(in.string(), "name");
  in.expect_end();
  EXPECT_THROW(in.u32(), CheckpointError);

  RecordReader short_reader{std::span(record).first(3), "short"};
  EXPECT_THROW(short_reader.u32(), CheckpointError);
  RecordReader long_reader(record, "long");
  (void)long_reader.u32();
  EXPECT_THROW(long_reader.expect_end(), CheckpointError);
}

}  // namespace test_checkpoint_file
}  // namespace settle
