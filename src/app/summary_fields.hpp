#pragma once
// The analysis fields of summary.json, shared by `settle run` (written at the end of a
// free-settling run) and `settle analyze` (recomputed from a run's files later): the terminal
// state, observables and regime (analysis/observables.hpp, docs/analysis.md) and the empirical
// correlations' predictions for the same particle next to them (analysis/correlations.hpp,
// docs/correlations.md).
#include <filesystem>

#include <nlohmann/json.hpp>

#include "analysis/correlations.hpp"
#include "analysis/observables.hpp"
#include "coupling/simulation.hpp"

namespace settle::app {

/// One law's prediction as summary.json and `settle predict --json` write it.
nlohmann::ordered_json prediction_json(const analysis::LawPrediction& prediction, analysis::Orientation orientation);

/// The analysis of a run's time series file for the particle of `setup`.
analysis::Analysis analyse_timeseries(const coupling::SimulationSetup& setup, const std::filesystem::path& timeseries,
                                      const analysis::AnalysisOptions& options);

/// The analysis fields (analysis::to_json) plus "correlations": every law's prediction for the
/// broadside orientation (settle predict's default), each with "ratio_to_run", its terminal speed
/// over the run's (null when the law has no solution or the run did not move).
nlohmann::ordered_json analysis_summary_fields(const coupling::SimulationSetup& setup,
                                               const analysis::Analysis& result);

}  // namespace settle::app
