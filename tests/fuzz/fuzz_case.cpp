// libFuzzer target for the case parser: arbitrary bytes as a case file go through
// everything `settle run` does before it allocates the grid: the schema check (io::parse_case),
// the fluid preset, the set-up (shape factory, mesh files relative to cases/) and the preflight
// checks (units, net weight, grid and memory, the particle in the domain, markers and steps).
//
// Expected outcome for bad input: settle::InputError, caught here. A finding is anything else:
// another exception type (libFuzzer reports it as a deadly signal), a crash, a sanitizer report,
// a hang, or a broken property (case_oracle.hpp; abort with a message): the resolved case
// (io::write_resolved_toml, what `settle run` writes to case.resolved.toml) reads back to the same
// values; `settle run --restart` relies on it.
// Build and run: scripts/fuzz.sh (docs/fuzzing.md).
#include <cstddef>
#include <cstdint>
#include <string_view>

#include "case_oracle.hpp"
#include "common/error.hpp"
#include "io/case_schema.hpp"
#include "io/fluid_presets.hpp"

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  const std::string_view text(reinterpret_cast<const char*>(data), size);
  try {
    settle::io::CaseValues values = settle::io::parse_case(settle::io::case_schema(), text, "fuzz");
    settle::fuzz::check_resolved_case_reads_back("fuzz_case", values);
    settle::io::apply_fluid_preset(values);
    settle::fuzz::setup_and_preflight(values, SETTLE_FUZZ_CASE_DIR);
  } catch (const settle::InputError&) {
    // The expected outcome for bad input.
  }
  return 0;
}
