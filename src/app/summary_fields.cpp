#include "app/summary_fields.hpp"

#include <cmath>

#include <fmt/core.h>

#include "analysis/analysis_json.hpp"
#include "analysis/timeseries.hpp"
#include "common/error.hpp"

namespace settle::app {
namespace {

using json = nlohmann::ordered_json;

json number_or_null(bool present, double value) {
  return present && std::isfinite(value) ? json(value) : json(nullptr);
}

}  // namespace

json prediction_json(const analysis::LawPrediction& p, analysis::Orientation orientation) {
  json descriptors = json::object();
  for (const auto& [name, value] : p.descriptors) descriptors[name] = number_or_null(true, value);
  return {{"law", p.law},
          {"terminal_velocity", number_or_null(p.state.solved, p.state.terminal_velocity_si)},
          {"reynolds", number_or_null(p.state.solved, p.state.reynolds)},
          {"drag_coefficient", number_or_null(p.state.solved, p.state.drag_coefficient)},
          {"in_range", p.in_range},
          {"solved", p.state.solved},
          {"range", p.range},
          {"reason", p.reason},
          {"orientation", analysis::orientation_name(orientation)},
          {"descriptors", descriptors},
          {"citation", p.citation}};
}

analysis::Analysis analyse_timeseries(const coupling::SimulationSetup& setup, const std::filesystem::path& timeseries,
                                      const analysis::AnalysisOptions& options) {
  // A body held before its release (particle.release_time) is analysed from the release on: the
  // held phase is the preparation of the flow, not settling.
  const analysis::SettlingSeries series =
      analysis::settling_series(analysis::read_timeseries_csv(timeseries)).since(setup.release_time_si);
  if (series.size() < 2)
    throw InputError(
        fmt::format("{}: {} samples after the release at particle.release_time = {:g} s; the analysis "
                    "needs at least 2",
                    timeseries.string(), series.size(), setup.release_time_si));
  return analysis::analyse(series, analysis::particle_properties(setup), options);
}

json analysis_summary_fields(const coupling::SimulationSetup& setup, const analysis::Analysis& result) {
  json fields = analysis::to_json(result);
  // Broadside is the orientation in which most non-spherical bodies settle steadily at moderate
  // Reynolds numbers, and settle predict's default: the two agree for the same case.
  const analysis::Orientation orientation = analysis::Orientation::broadside;
  json correlations = json::array();
  std::vector<analysis::LawPrediction> predictions;
  try {
    predictions = analysis::predict_terminal_velocities(setup, orientation);
  } catch (const InputError& e) {
    // No net weight or no gravity: there is no terminal velocity to predict; say why.
    fields["correlations_note"] = e.what();
  }
  for (const analysis::LawPrediction& p : predictions) {
    json entry = prediction_json(p, orientation);
    entry["ratio_to_run"] = number_or_null(p.state.solved && result.terminal_speed_si > 0.0,
                                           p.state.terminal_velocity_si / result.terminal_speed_si);
    correlations.push_back(std::move(entry));
  }
  fields["correlations"] = std::move(correlations);
  return fields;
}

}  // namespace settle::app
