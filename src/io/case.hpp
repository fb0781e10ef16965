#pragma once
// From a checked case (io/schema.hpp, keys of case_schema.cpp) to the coupled simulation's
// SI set-up, and the built-in default case of `settle run`.
#include <filesystem>
#include <string>
#include <string_view>
#include <vector>

#include "body/shape_factory.hpp"
#include "coupling/simulation.hpp"
#include "io/schema.hpp"

namespace settle::io {

/// Reads a case file (or the default case when `path` is empty), applies the --set overrides in
/// order, then the fluid preset (io/fluid_presets.hpp: fluid.density and fluid.dynamic_viscosity
/// from fluid.preset unless given). settle::InputError names the file or --set and the key on any
/// problem.
CaseValues load_case(const std::filesystem::path& path, const std::vector<std::string>& overrides);

/// The text of a TOML input file (`what`: "case file", "study file", named in messages), read up
/// to 64 MiB: settle::InputError for a missing file, a directory, an unreadable or a larger one
/// (an endless stream such as /dev/zero included).
std::string read_toml_file(const std::filesystem::path& path, std::string_view what);

/// As load_case, for a case given as TOML text (`origin` names it in messages), without overrides.
CaseValues load_case_text(std::string_view toml_text, std::string_view origin);

/// The shape keys of a checked case's [particle] table (shape, diameter, aspect_ratio, semi_axes,
/// exponents, length, size, file, scale), for body::make_shape: the one reader of a case's shape,
/// used by `settle run`, `settle shape` and `settle predict`.
body::ShapeSpec shape_spec(const CaseValues& values);

/// The body's motion of a particle.motion value ("free", "towed", "fixed"; the schema refuses
/// any other).
body::MotionKind motion_kind(const std::string& name);

/// The simulation set-up of a checked case. Relative mesh paths are taken relative to
/// `base_directory` (the case file's folder). Keys that depend on each other are checked here
/// (settle::InputError naming the key): towing_velocity for towed bodies, domain.size.
coupling::SimulationSetup simulation_setup(const CaseValues& values, const std::filesystem::path& base_directory,
                                           std::string name);

/// particle.density, which every case states (a default would silently make a sand grain of
/// plastic); settle::InputError saying so when it is absent.
double particle_density_si(const CaseValues& values);

/// Messages for the user about the case: keys accepted but not acted on by this version, and
/// explicit fluid values that replace a preset's (io::fluid_preset_warnings).
std::vector<std::string> unsupported_key_warnings(const CaseValues& values);

}  // namespace settle::io
