#pragma once
// A study file (docs/studies.md): a base case and what to vary. Reading it checks its own keys;
// expanding it builds every case and checks each against the case schema and the set-up's rules
// before anything runs, so a bad study is refused whole with a message that names the key.
#include <cstdint>
#include <filesystem>
#include <string>
#include <string_view>
#include <utility>
#include <vector>

#include "io/schema.hpp"

namespace settle::study {

/// One varied input: a case key ("numerics.cells_per_diameter") or a derived input
/// (derived_inputs.hpp: "reynolds", "incidence_deg", "galileo"), with its values in order.
struct Variation {
  std::string name;
  std::vector<io::Value> values;
};

/// Attitudes drawn uniformly on the rotation group (derived_inputs.hpp), one case each.
struct OrientationEnsemble {
  int count = 0;  ///< 0: no ensemble
  std::uint64_t seed = 0;
};

struct StudySpec {
  std::string name;                      ///< [study] name, default the study file's stem
  std::filesystem::path study_file;      ///< absolute
  std::string base_case_text;            ///< TOML of the base case
  std::string base_origin;               ///< how messages name the base case
  std::filesystem::path base_directory;  ///< relative paths of the base case (a mesh) start here
  std::vector<Variation> variations;     ///< the product, in the order of the file, the last fastest
  OrientationEnsemble orientations;      ///< varies fastest of all
};

/// Reads and checks a study file. settle::InputError names the file and the key.
StudySpec read_study(const std::filesystem::path& study_file);

/// As read_study, for the study file's text: `study_file` names it in messages and is where its
/// relative paths (study.base) start; it need not exist.
StudySpec parse_study(std::string_view text, const std::filesystem::path& study_file);

/// The input that numbers a case's attitude in an orientation ensemble (0 to count - 1).
inline constexpr const char* kOrientationInput = "orientation";

/// One case of a study: its place, the inputs that single it out, and its checked values.
struct StudyCase {
  int index = 0;
  std::vector<std::pair<std::string, io::Value>> inputs;
  io::CaseValues values;
};

/// Every case of the study in order, each checked (io::simulation_setup) before any is returned.
/// settle::InputError names the case by its index and inputs, and the key.
std::vector<StudyCase> expand(const StudySpec& spec);

/// "reynolds = 50, incidence_deg = 30": how messages and the progress name a case.
std::string describe_inputs(const std::vector<std::pair<std::string, io::Value>>& inputs);

}  // namespace settle::study
