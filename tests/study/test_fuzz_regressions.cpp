// Inputs found by fuzzing the study file (tests/fuzz/fuzz_study.cpp, docs/fuzzing.md), kept as
// regression tests. Each input is read from the seed corpus (tests/fuzz/corpus_study/finding_*), as
// the fuzz target reads it: the study file taken to lie in studies/.
#include <gtest/gtest.h>

#include <filesystem>
#include <fstream>
#include <sstream>
#include <string>

#include "common/error.hpp"
#include "io/case.hpp"
#include "io/case_schema.hpp"
#include "io/fluid_presets.hpp"
#include "study/study_directory.hpp"
#include "study/study_spec.hpp"

namespace settle::study {
namespace test_fuzz_regressions {

namespace fs = std::filesystem;

const fs::path kStudyFile = fs::path(SETTLE_SOURCE_DIR) / "studies" / "fuzz_study.toml";

std::string fuzz_input(const std::string& name) {
  std::ifstream in(fs::path(SETTLE_SOURCE_DIR) / "tests/fuzz/corpus_study" / name, std::ios::binary);
  std::stringstream bytes;
  bytes << in.rdbuf();
  EXPECT_TRUE(in.good() || in.eof()) << name;
  return bytes.str();
}

std::string refusal(const std::string& text, const fs::path& file = kStudyFile) {
  try {
    (void)expand(parse_study(text, file));
  } catch (const InputError& e) {
    return e.what();
  }
  return "accepted";
}

// Finding 1: study.name = "x\ny = 1". The name heads each case.toml in a comment line, so its
// newline put "y = 1 (...)" on a line of its own: every case.toml was a TOML syntax error, after
// --dry-run had said "all checked", and the Slurm script (--emit slurm) held the rest of the name
// as a command. The random search found it as a carriage return in a shipped study's name
// (finding_name_with_carriage_return.toml). Now refused, whether the name is given or is the file's
// stem.
TEST(FuzzRegression, AStudyNameWithAControlCharacterIsRefused) {
  const std::string message = refusal(fuzz_input("finding_name_with_newline.toml"));
  EXPECT_NE(message.find("study.name = \"x\\ny = 1\": holds a control character"), std::string::npos) << message;
  const std::string found = refusal(fuzz_input("finding_name_with_carriage_return.toml"));
  EXPECT_NE(found.find("study.name = \"cuboid_o\\rientations\": holds a control character"), std::string::npos)
      << found;

  const std::string unnamed = "[study]\nbase = \"../cases/towed_sphere.toml\"\n[vary]\nrun.end_time = [0.1]\n";
  const std::string from_stem = refusal(unnamed, kStudyFile.parent_path() / "a\tb.toml");
  EXPECT_NE(from_stem.find("the file's stem"), std::string::npos) << from_stem;
  const std::string not_a_string =
      refusal("[study]\nname = 5\nbase = \"../cases/towed_sphere.toml\"\n[vary]\nrun.end_time = [0.1]\n");
  EXPECT_NE(not_a_string.find("study.name = 5: expected a string"), std::string::npos) << not_a_string;
}

// The positive control: a name of spaces, quotes and non-ASCII letters heads a case.toml that
// `settle run` reads back to the case's values.
TEST(FuzzRegression, ACaseFileHeadedByAnUnusualNameReadsBack) {
  const StudySpec spec = parse_study(
      "[study]\nname = 'Kugel \"größer\" # 1'\nbase = \"../cases/towed_sphere.toml\"\n[vary]\nrun.end_time = [0.1]\n",
      kStudyFile);
  const std::vector<StudyCase> cases = expand(spec);
  ASSERT_EQ(cases.size(), 1u);
  const io::CaseValues back = io::load_case_text(case_file_text(spec, cases[0]), "case.toml");
  for (const io::KeySpec& key : io::case_schema().keys()) {
    ASSERT_EQ(back.has(key.path), cases[0].values.has(key.path)) << key.path;
    if (back.has(key.path)) {
      EXPECT_EQ(back.value(key.path), cases[0].values.value(key.path)) << key.path;
    }
  }
}

// Finding 2: a base with fluid.preset = "water" at 20 C and vary.fluid.temperature = [10, 40]. The
// preset was applied to the base before the variation, so both cases ran with water at 20 C (the
// case files said 10 and 40 C, and `settle run` warned that their density and viscosity "replace"
// the preset's). Now each case is what `settle run BASE --set fluid.temperature=T` reads: the
// preset applied after the varied keys. Reference: the tabulated water at 10 and 40 C of
// tests/io/test_fluid_presets.cpp (M. Chaplin, "Water structure and science", data page): 999.7
// and 992.2 kg/m^3, 1.307 and 0.653 mPa s, within that test's tolerances (the table's rounding and
// the formulas' uncertainty: 0.057 kg/m^3, 0.2 %). The base's 20 C water (998.2 kg/m^3, 1.0016
// mPa s) is 25 and more tolerances away from either.
TEST(FuzzRegression, AVariedWaterTemperatureChangesTheFluid) {
  const StudySpec spec = parse_study(fuzz_input("finding_preset_temperature.toml"), kStudyFile);
  const std::vector<StudyCase> cases = expand(spec);
  ASSERT_EQ(cases.size(), 2u);
  EXPECT_NEAR(cases[0].values.real("fluid.density"), 999.7, 0.057);
  EXPECT_NEAR(cases[1].values.real("fluid.density"), 992.2, 0.057);
  EXPECT_NEAR(cases[0].values.real("fluid.dynamic_viscosity") / 1.307e-3, 1.0, 2e-3);
  EXPECT_NEAR(cases[1].values.real("fluid.dynamic_viscosity") / 0.653e-3, 1.0, 2e-3);
  for (const StudyCase& c : cases) {
    io::CaseValues expected = io::parse_case(io::case_schema(), spec.base_case_text, spec.base_origin);
    io::apply_override(expected, "fluid.temperature=" + io::to_toml(c.inputs.at(0).second));
    io::apply_fluid_preset(expected);
    for (const io::KeySpec& key : io::case_schema().keys()) {
      if (expected.has(key.path)) {
        EXPECT_EQ(expected.value(key.path), c.values.value(key.path)) << key.path;
      }
    }
    EXPECT_TRUE(io::fluid_preset_warnings(c.values).empty());
  }
}

// Not a finding of the random search: the base case was read whole, without the case file's bound
// (docs/errors.md: 64 MiB), so study.base = "/dev/zero" (not a regular file) was "no such file" and
// a huge regular file was read into memory. Now it is read as `settle run` reads a case.
TEST(FuzzRegression, AStudysBaseCaseIsReadAsACaseFile) {
  const std::string message = refusal("[study]\nbase = \"/dev/zero\"\n[vary]\nrun.end_time = [0.1]\n");
  EXPECT_NE(message.find("/dev/zero: more than 64 MiB, not a case file"), std::string::npos) << message;
}

}  // namespace test_fuzz_regressions
}  // namespace settle::study
