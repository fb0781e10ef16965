// Inputs found by fuzzing the case parser (tests/fuzz/fuzz_case.cpp, docs/fuzzing.md), kept as
// regression tests: each must now give settle::InputError or parse correctly, and the resolved
// case (what `settle run` writes to case.resolved.toml and a restart reads back) must read back
// to the same values.
#include <gtest/gtest.h>

#include <fstream>
#include <sstream>
#include <string>

#include "common/error.hpp"
#include "io/case_schema.hpp"
#include "io/schema.hpp"

namespace settle::io {
namespace test_fuzz_regressions {

std::string fuzz_input(const std::string& name) {
  std::ifstream in(std::string(SETTLE_SOURCE_DIR) + "/tests/fuzz/corpus_case/" + name, std::ios::binary);
  std::stringstream bytes;
  bytes << in.rdbuf();
  EXPECT_TRUE(in.good() || in.eof()) << name;
  return bytes.str();
}

// Exact equality of every value: the resolved case is a lossless copy of the case.
void expect_resolved_case_reads_back(const CaseValues& values) {
  const std::string resolved = write_resolved_toml(values);
  CaseValues back(values.schema());
  ASSERT_NO_THROW(back = parse_case(values.schema(), resolved, "resolved")) << resolved;
  for (const KeySpec& k : values.schema().keys()) {
    ASSERT_EQ(values.has(k.path), back.has(k.path)) << k.path;
    if (values.has(k.path)) {
      EXPECT_EQ(values.value(k.path), back.value(k.path)) << k.path << "\n" << resolved;
    }
  }
}

// Finding 1: a string value holding a control character (here run.reference = "a\nb", written
// with TOML's escape) was written raw into the resolved case, which TOML then refuses ("unescaped
// control characters ... are explicitly prohibited"): the run's case.resolved.toml was unreadable.
TEST(FuzzRegression, StringWithAnEscapedNewlineReadsBackFromTheResolvedCase) {
  const CaseValues values = parse_case(case_schema(), fuzz_input("finding_string_control_character.toml"), "case");
  EXPECT_EQ(values.string("run.reference"), "a\nb");
  expect_resolved_case_reads_back(values);
}

// Every character TOML requires escaping in a basic string (U+0000-U+001F, U+007F, '"', '\'),
// next to ones it does not (non-ASCII UTF-8), survives the round trip in both string keys
// without choices.
TEST(FuzzRegression, EveryControlCharacterSurvivesTheResolvedCase) {
  std::string text = "\"\\ caf\xC3\xA9 ";
  for (char c = 0; c < 0x20; ++c) text += c;
  text += '\x7F';
  CaseValues values = parse_case(case_schema(), "", "case");
  values.set("run.reference", Value(text), "test");
  values.set("particle.file", Value(text + ".stl"), "test");
  expect_resolved_case_reads_back(values);
}

}  // namespace test_fuzz_regressions
}  // namespace settle::io
