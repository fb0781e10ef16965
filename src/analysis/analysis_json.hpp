#pragma once
// The analysis of a run as the JSON fields of summary.json (docs/analysis.md): the contract keys
// first, then terminal state, averaging window, lateral motion, tilt, rotation and the runner's
// averages over the analysis' window.
#include <nlohmann/json_fwd.hpp>

#include "analysis/observables.hpp"

namespace settle::analysis {

/// The fields of summary.json the analysis owns, keys in a fixed order; quantities that are
/// undefined (e.g. I* of a non-disk) are null.
nlohmann::ordered_json to_json(const Analysis& analysis);

}  // namespace settle::analysis
