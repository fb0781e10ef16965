#pragma once
// The properties the fuzz targets of tests/fuzz check on a case that was accepted (docs/fuzzing.md).
// A broken property is a finding: the target prints it and aborts, which libFuzzer reports with the
// input.
#include <cstdio>
#include <cstdlib>
#include <filesystem>
#include <string>
#include <string_view>

#include "common/error.hpp"
#include "io/case.hpp"
#include "io/case_schema.hpp"
#include "io/preflight.hpp"
#include "io/schema.hpp"

namespace settle::fuzz {

[[noreturn]] inline void finding(std::string_view target, const std::string& what) {
  std::fprintf(stderr, "%.*s finding: %s\n", static_cast<int>(target.size()), target.data(), what.c_str());
  std::abort();
}

/// The first key whose presence or value differs between two cases of one schema, "" when none;
/// `skipped` (a key path) is not compared.
inline std::string first_differing_key(const io::CaseValues& a, const io::CaseValues& b,
                                       std::string_view skipped = {}) {
  for (const io::KeySpec& key : a.schema().keys()) {
    if (key.path == skipped) continue;
    if (a.has(key.path) != b.has(key.path) || (a.has(key.path) && !(a.value(key.path) == b.value(key.path))))
      return key.path;
  }
  return {};
}

/// The resolved case (io::write_resolved_toml, what `settle run` writes to case.resolved.toml and
/// `settle run --restart` reads back from the checkpoint) reads back to exactly the same values.
inline void check_resolved_case_reads_back(std::string_view target, const io::CaseValues& values) {
  const std::string resolved = io::write_resolved_toml(values);
  io::CaseValues again(values.schema());
  try {
    again = io::parse_case(values.schema(), resolved, "resolved case");
  } catch (const InputError& e) {
    finding(target, std::string("the resolved case does not read back: ") + e.what() + "\n" + resolved);
  }
  if (const std::string key = first_differing_key(values, again); !key.empty())
    finding(target, "the resolved case reads back a different " + key + ":\n" + resolved);
}

/// What `settle run` does with a loaded case before it allocates the grid: the warnings, the set-up
/// (shape factory; relative mesh paths from `base_directory`) and the preflight, with a fixed 2 GiB
/// memory budget so that the outcome does not depend on the machine. InputError for a bad case.
inline void setup_and_preflight(const io::CaseValues& values, const std::filesystem::path& base_directory) {
  (void)io::unsupported_key_warnings(values);  // the fluid preset's warnings included
  const auto setup = io::simulation_setup(values, base_directory, "fuzz");
  io::PreflightOptions options;
  options.memory_budget_bytes = 2.0 * 1024 * 1024 * 1024;
  (void)io::preflight(setup, options).summary();
}

}  // namespace settle::fuzz
