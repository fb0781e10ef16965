#pragma once
// The evidence the regime rules (regime.hpp) judge, read off the observables of one analysis:
// path angle, lateral and tilt amplitudes, spectral concentration and periods, trends, rotation of
// the body axis, and whether the averaging window can be classified at all.
#include "analysis/observables.hpp"
#include "analysis/regime.hpp"

namespace settle::analysis {

/// A window needs this many samples before its regime is judged.
constexpr std::size_t kMinClassifiableSamples = 8;

/// The regime evidence of an analysis whose observables are computed (everything analyse() fills
/// before it classifies). Not classifiable, with the reason, when the part of the window judged
/// (Analysis::regime_window_samples) has fewer than kMinClassifiableSamples samples, the particle
/// does not move, or without a terminal state the second half of the run is shorter than the two
/// detection windows an unsteady regime would have to fill.
RegimeEvidence regime_evidence(const Analysis& analysis);

}  // namespace settle::analysis
