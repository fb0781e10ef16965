#include "analysis/regime_evidence.hpp"

#include <string>
#include <utility>

#include <fmt/core.h>

namespace settle::analysis {
namespace {

RegimeEvidence evidence_of(const Analysis& a, std::string not_classifiable_reason) {
  RegimeEvidence e;
  e.classifiable = not_classifiable_reason.empty();
  e.not_classifiable_reason = std::move(not_classifiable_reason);
  const double speed = a.terminal_speed_si;
  e.path_angle_deg = a.path_angle_deg;
  e.lateral_drift_ratio = speed > 0.0 ? a.lateral_drift_speed_si / speed : 0.0;
  e.lateral_amplitude_ratio = speed > 0.0 ? a.lateral_amplitude_si / speed : 0.0;
  e.lateral_circularity = a.lateral_circularity;
  e.lateral_concentration = a.lateral_peak.concentration;
  e.lateral_cycles = a.lateral_peak.cycles;
  e.lateral_trend_fraction = a.lateral_trend_fraction;
  e.lateral_decay_ratio = a.lateral_decay_ratio;
  e.has_axis = a.axis.kind != AxisKind::none;
  e.tilt_amplitude_deg = a.tilt_amplitude_deg.value_or(0.0);
  e.tilt_concentration = a.tilt_peak.concentration;
  e.tilt_cycles = a.tilt_peak.cycles;
  e.tilt_trend_fraction = a.tilt_trend_fraction;
  e.tilt_decay_ratio = a.tilt_decay_ratio;
  e.axis_net_rotation = a.axis_net_rotation;
  e.axis_rotation_monotonicity = a.axis_rotation_monotonicity;
  e.axis_rotation_elevation_deg = a.axis_rotation_elevation_deg;
  return e;
}

// Why the window cannot be classified, or "" when it can.
std::string classifiability(const Analysis& a) {
  if (a.regime_window_samples < kMinClassifiableSamples)
    return fmt::format("the averaging window has {} samples (< {})", a.regime_window_samples, kMinClassifiableSamples);
  if (!(a.terminal_speed_si > 0.0)) return "the particle does not move";
  if (a.terminal.reached || !(a.criteria.response_time_si > 0.0)) return "";
  const double half = a.window_end_si - a.window_start_si, needed = 2.0 * a.criteria.window_si();
  if (half < needed)
    return fmt::format(
        "no terminal state, and the second half of the run ({:.4g} s) is shorter than the two "
        "detection windows ({:.4g} s) that would have to disagree for an unsteady regime",
        half, needed);
  return "";
}

}  // namespace

RegimeEvidence regime_evidence(const Analysis& a) { return evidence_of(a, classifiability(a)); }

}  // namespace settle::analysis
