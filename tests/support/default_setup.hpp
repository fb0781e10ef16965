#pragma once
// The set-up of the minimal case, the one whose file gives only the keys without a default
// (kMinimalCase): every other member holds the case schema's default (io/case_schema.cpp, the one
// place defaults are declared), read through the path every case takes (io::load_case_text,
// io::simulation_setup). Tests that build a coupling::SimulationSetup start from it and set what
// they vary; coupling::SimulationSetup's members carry no defaults of their own (coupling/setup.hpp).
#include <string_view>

#include "coupling/setup.hpp"
#include "io/case.hpp"

namespace settle::test {

/// The required keys only, at the values the tests assume when they set nothing else: a 1 mm sphere
/// (replaced by every test's own shape) of 1050 kg/m^3 (polystyrene) in a 10 mm cube.
inline constexpr std::string_view kMinimalCase = R"toml(
[particle]
diameter = 1.0e-3
density = 1050.0

[domain]
size = [0.01, 0.01, 0.01]
)toml";

inline coupling::SimulationSetup default_setup() {
  return io::simulation_setup(io::load_case_text(kMinimalCase, "the minimal case (tests/support)"), ".", "case");
}

}  // namespace settle::test
