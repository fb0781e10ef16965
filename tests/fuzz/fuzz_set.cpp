// libFuzzer target for `settle run CASE --set key=value`: arbitrary bytes as the key and value of
// one override, applied to a shipped case through io::load_case (the function `settle run`,
// `settle bench --case` and `settle predict` read a case and its --set with: the override parsed as
// TOML and checked against the schema, then the fluid preset), then everything `settle run` does
// before it allocates the grid (case_oracle.hpp: set-up and preflight).
//
// Input: the first byte chooses the base case (its value modulo the number of kBaseCases), the rest
// is the assignment as one command-line word. A command line cannot hold a NUL byte, so inputs
// with one are rejected (not added to the corpus).
//
// Expected outcome for bad input: settle::InputError, caught here. A finding is anything else, as
// in fuzz_case: another exception, a crash, a sanitizer report, a hang, or a broken property (the
// resolved case reads back to the same values).
// Build and run: scripts/fuzz.sh (docs/fuzzing.md).
#include <array>
#include <cstddef>
#include <cstdint>
#include <string>

#include "case_oracle.hpp"
#include "common/error.hpp"
#include "io/case.hpp"

namespace {

// A towed and a fixed sphere (towing, inflow and periodic keys), a free spheroid (aspect ratio,
// attitude, the default momentum exchange) and a free cube (edges, size): keys that only matter for
// one kind of body meet a case where they do. No mesh: a mesh case's set-up takes up to 0.7 s under
// the sanitizers, which cut the target's pace several times; fuzz_case covers cases/grain.toml.
constexpr std::array<const char*, 4> kBaseCases{"towed_sphere.toml", "periodic_sphere_array.toml",
                                                "prolate_spheroid.toml", "cube.toml"};

}  // namespace

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  if (size == 0) return 0;
  const std::string base = std::string(SETTLE_FUZZ_CASE_DIR) + "/" + kBaseCases[data[0] % kBaseCases.size()];
  const std::string assignment(reinterpret_cast<const char*>(data) + 1, size - 1);
  if (assignment.find('\0') != std::string::npos) return -1;
  try {
    const settle::io::CaseValues values = settle::io::load_case(base, {assignment});
    settle::fuzz::check_resolved_case_reads_back("fuzz_set", values);
    settle::fuzz::setup_and_preflight(values, SETTLE_FUZZ_CASE_DIR);
  } catch (const settle::InputError&) {
    // The expected outcome for bad input.
  }
  return 0;
}
