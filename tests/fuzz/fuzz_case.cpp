// libFuzzer target for the case parser: arbitrary bytes as a case file go through
// everything `settle run` does before it allocates the grid: the schema check (io::parse_case),
// the fluid preset, the set-up (shape factory, mesh files relative to cases/) and the preflight
// checks (units, net weight, grid and memory, the particle in the domain, markers and steps).
//
// Expected outcome for bad input: settle::InputError, caught here. A finding is anything else:
// another exception type (libFuzzer reports it as a deadly signal), a crash, a sanitizer report,
// a hang, or a broken oracle below (abort with a message):
//   - the resolved case (io::write_resolved_toml, what `settle run` writes to
//     case.resolved.toml) reads back to the same values; `settle run --restart` relies on it.
// Build and run: scripts/fuzz.sh (docs/fuzzing.md).
#include <cstddef>
#include <cstdint>
#include <cstdio>
#include <cstdlib>
#include <string>
#include <string_view>

#include "common/error.hpp"
#include "io/case.hpp"
#include "io/case_schema.hpp"
#include "io/fluid_presets.hpp"
#include "io/preflight.hpp"

namespace {

[[noreturn]] void finding(const std::string& what) {
  std::fprintf(stderr, "fuzz_case finding: %s\n", what.c_str());
  std::abort();
}

void check_resolved_case_reads_back(const settle::io::CaseValues& values) {
  using namespace settle::io;
  const std::string resolved = write_resolved_toml(values);
  CaseValues again(values.schema());
  try {
    again = parse_case(values.schema(), resolved, "resolved case");
  } catch (const settle::InputError& e) {
    finding(std::string("the resolved case does not read back: ") + e.what() + "\n" + resolved);
  }
  for (const KeySpec& key : values.schema().keys()) {
    if (values.has(key.path) != again.has(key.path) ||
        (values.has(key.path) && !(values.value(key.path) == again.value(key.path)))) {
      finding("the resolved case reads back a different " + key.path + ":\n" + resolved);
    }
  }
}

void setup_and_preflight(settle::io::CaseValues values) {
  using namespace settle::io;
  apply_fluid_preset(values);
  (void)unsupported_key_warnings(values);
  const auto setup = simulation_setup(values, SETTLE_FUZZ_CASE_DIR, "fuzz");
  PreflightOptions options;
  options.memory_budget_bytes = 2.0 * 1024 * 1024 * 1024;  // fixed: the outcome must not depend on the machine
  (void)preflight(setup, options).summary();
}

}  // namespace

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  const std::string_view text(reinterpret_cast<const char*>(data), size);
  try {
    const settle::io::CaseValues values = settle::io::parse_case(settle::io::case_schema(), text, "fuzz");
    check_resolved_case_reads_back(values);
    setup_and_preflight(values);
  } catch (const settle::InputError&) {
    // The expected outcome for bad input.
  }
  return 0;
}
