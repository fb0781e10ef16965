// libFuzzer target for the study file: arbitrary bytes as a study TOML go through what
// `settle study run STUDY --dry-run` does: study::parse_study (its tables, ranges, derived inputs,
// the base case) and study::expand (every case built and checked by io::simulation_setup). The study
// file is taken to lie in the source tree's studies/ (it need not exist there), so that
// study.base = "../cases/towed_sphere.toml" reads a shipped case as the shipped studies do.
//
// Expected outcome for bad input: settle::InputError, caught here. A finding is anything else:
// another exception type, a crash, a sanitizer report, a hang, or a broken property of an accepted
// study (abort with a message):
//   - each case's case.toml (study::case_file_text, what `settle study run` writes and each case's
//     `settle run` reads) reads back to the case's values;
//   - a case made of case keys alone is the base case with each of them given by --set, as
//     `settle run BASE --set key=value ...` reads it (the overrides, then the fluid preset).
// Studies of more than kMaxExpandedCases cases are read but not expanded: expanding checks every
// case as a run would (a shape each), linear in the cases, and 100 000 of them (the bound
// read_study allows) take minutes under the sanitizers without reaching any other code.
// Build and run: scripts/fuzz.sh (docs/fuzzing.md).
#include <cstddef>
#include <cstdint>
#include <string>
#include <string_view>
#include <vector>

#include "case_oracle.hpp"
#include "common/error.hpp"
#include "io/case.hpp"
#include "io/case_schema.hpp"
#include "io/fluid_presets.hpp"
#include "study/derived_inputs.hpp"
#include "study/study_directory.hpp"
#include "study/study_spec.hpp"

namespace {

using namespace settle;

constexpr std::size_t kMaxExpandedCases = 32;
constexpr std::string_view kTarget = "fuzz_study";

std::size_t case_count(const study::StudySpec& spec) {
  std::size_t count = spec.orientations.count > 0 ? static_cast<std::size_t>(spec.orientations.count) : 1;
  for (const study::Variation& v : spec.variations) {
    count *= v.values.size();
    if (count > kMaxExpandedCases) return count;  // stops before the product can overflow
  }
  return count;
}

void check_case_file_reads_back(const study::StudySpec& spec, const study::StudyCase& c) {
  const std::string text = study::case_file_text(spec, c);
  io::CaseValues again(io::case_schema());
  try {
    again = io::load_case_text(text, "case.toml");
  } catch (const InputError& e) {
    fuzz::finding(kTarget,
                  "case " + std::to_string(c.index) + ": its case.toml does not read back: " + e.what() + "\n" + text);
  }
  // particle.file is made absolute in case.toml (the case file no longer lies beside the mesh).
  if (const std::string key = fuzz::first_differing_key(c.values, again, "particle.file"); !key.empty())
    fuzz::finding(kTarget,
                  "case " + std::to_string(c.index) + ": its case.toml reads back a different " + key + "\n" + text);
}

bool only_case_keys(const study::StudyCase& c) {
  for (const auto& [name, value] : c.inputs)
    if (name == study::kOrientationInput || study::is_derived_input(name)) return false;
  return true;
}

void check_case_is_the_base_with_its_keys_set(const study::StudySpec& spec, const study::StudyCase& c) {
  io::CaseValues expected = io::parse_case(io::case_schema(), spec.base_case_text, spec.base_origin);
  std::string assignments;
  try {
    for (const auto& input : c.inputs) {
      const std::string assignment = input.first + "=" + io::to_toml(c.values.value(input.first));
      assignments += " --set " + assignment;
      io::apply_override(expected, assignment);
    }
    io::apply_fluid_preset(expected);
  } catch (const InputError& e) {
    fuzz::finding(kTarget, "case " + std::to_string(c.index) + ": settle run BASE" + assignments +
                               " refuses what the study accepted: " + e.what());
  }
  if (const std::string key = fuzz::first_differing_key(expected, c.values); !key.empty())
    fuzz::finding(kTarget,
                  "case " + std::to_string(c.index) + ": " + key + " differs from settle run BASE" + assignments);
}

}  // namespace

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  const std::string_view text(reinterpret_cast<const char*>(data), size);
  try {
    const study::StudySpec spec = study::parse_study(text, SETTLE_FUZZ_STUDY_FILE);
    if (case_count(spec) > kMaxExpandedCases) return 0;
    for (const study::StudyCase& c : study::expand(spec)) {
      check_case_file_reads_back(spec, c);
      if (only_case_keys(c)) check_case_is_the_base_with_its_keys_set(spec, c);
    }
  } catch (const InputError&) {
    // The expected outcome for bad input.
  }
  return 0;
}
