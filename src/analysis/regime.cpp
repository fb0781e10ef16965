#include "analysis/regime.hpp"

#include <cmath>
#include <numbers>

#include <fmt/core.h>

namespace settle::analysis {
namespace {

bool is_tumbling(const RegimeEvidence& e, const RegimeThresholds& th) {
  return e.has_axis && std::abs(e.axis_net_rotation) >= th.tumbling_min_net_rotation &&
         e.axis_rotation_monotonicity >= th.tumbling_min_monotonicity &&
         e.axis_rotation_elevation_deg <= th.tumbling_max_axis_elevation_deg;
}

bool lateral_is_steady(const RegimeEvidence& e, const RegimeThresholds& th) {
  return e.lateral_amplitude_ratio < th.steady_lateral_amplitude;
}

bool tilt_is_steady(const RegimeEvidence& e, const RegimeThresholds& th) {
  return !e.has_axis || e.tilt_amplitude_deg < th.steady_tilt_amplitude_deg;
}

RegimeResult steady(const RegimeEvidence& e, const RegimeThresholds& th) {
  const std::string numbers = fmt::format(
      "lateral amplitude {:.3g}% of the speed, tilt amplitude {:.3g} deg, path "
      "{:.3g} deg from vertical",
      100.0 * e.lateral_amplitude_ratio, e.tilt_amplitude_deg, e.path_angle_deg);
  if (e.path_angle_deg >= th.oblique_path_angle_deg) return {Regime::steady_oblique, "steady, oblique: " + numbers};
  return {Regime::steady_vertical, "steady, vertical: " + numbers};
}

RegimeResult periodic(const RegimeEvidence& e, const RegimeThresholds& th) {
  if (e.lateral_circularity >= th.spiral_min_circularity)
    return {Regime::spiral, fmt::format("periodic lateral velocity turning round the vertical (circularity {:.2f})",
                                        e.lateral_circularity)};
  const std::string planar = fmt::format("periodic planar oscillation (circularity {:.2f})", e.lateral_circularity);
  const double lateral_amplitude = e.lateral_amplitude_ratio;
  if (e.path_angle_deg >= th.oblique_path_angle_deg && lateral_amplitude < e.lateral_drift_ratio)
    return {Regime::oblique_oscillating,
            fmt::format("{} about a path {:.3g} deg from vertical; the lateral velocity does not reverse (amplitude "
                        "{:.3g}, drift {:.3g} of the speed)",
                        planar, e.path_angle_deg, lateral_amplitude, e.lateral_drift_ratio)};
  if (e.has_axis && e.tilt_amplitude_deg >= th.flutter_min_tilt_amplitude_deg)
    return {Regime::fluttering, fmt::format("{} with a tilt amplitude of {:.3g} deg (>= {:.3g})", planar,
                                            e.tilt_amplitude_deg, th.flutter_min_tilt_amplitude_deg)};
  return {Regime::zigzag, e.has_axis ? fmt::format("{} with a tilt amplitude of {:.3g} deg (< {:.3g})", planar,
                                                   e.tilt_amplitude_deg, th.flutter_min_tilt_amplitude_deg)
                                     : planar};
}

// The signal rules 3 and 4 of the header judge: the lateral velocity, or the tilt when only the
// tilt is unsteady.
struct UnsteadySignal {
  const char* name;
  double concentration, cycles, trend, decay;
};

UnsteadySignal unsteady_signal(const RegimeEvidence& e, const RegimeThresholds& th) {
  if (lateral_is_steady(e, th))
    return {"tilt", e.tilt_concentration, e.tilt_cycles, e.tilt_trend_fraction, e.tilt_decay_ratio};
  return {"lateral velocity", e.lateral_concentration, e.lateral_cycles, e.lateral_trend_fraction,
          e.lateral_decay_ratio};
}

bool is_drifting(const UnsteadySignal& s, const RegimeThresholds& th) { return s.trend >= th.drift_min_trend_fraction; }

bool dies_away(const UnsteadySignal& s, const RegimeThresholds& th) {
  return s.decay < th.decaying_max_amplitude_ratio;
}

bool is_unsteady(const RegimeEvidence& e, const RegimeThresholds& th) {
  return e.classifiable && !is_tumbling(e, th) && !(lateral_is_steady(e, th) && tilt_is_steady(e, th));
}

RegimeResult unsteady(const RegimeEvidence& e, const RegimeThresholds& th) {
  const UnsteadySignal s = unsteady_signal(e, th);
  const char* signal = s.name;
  if (is_drifting(s, th))
    return {Regime::not_classified,
            fmt::format("the {} is still drifting: {:.0f}% of its variance over the window is a linear trend (>= "
                        "{:.0f}%); run longer",
                        signal, 100.0 * s.trend, 100.0 * th.drift_min_trend_fraction)};
  if (dies_away(s, th))
    return {Regime::not_classified,
            fmt::format("the {} oscillation is dying away (its amplitude over the later half of the window is {:.2f} "
                        "of the earlier half's, < {:.2f}): the body is still settling into its regime; run longer",
                        signal, s.decay, th.decaying_max_amplitude_ratio)};
  const bool concentrated = s.concentration >= th.periodic_min_concentration;
  if (concentrated && s.cycles >= th.periodic_min_cycles) return periodic(e, th);
  if (concentrated)
    return {Regime::not_classified,
            fmt::format("unsteady, but the window holds only {:.2g} periods of the {} oscillation (< {:.3g}): too "
                        "short to tell periodic from chaotic",
                        s.cycles, signal, th.periodic_min_cycles)};
  return {Regime::chaotic, fmt::format("unsteady and broadband: {:.0f}% of the {} fluctuation power near its peak "
                                       "(< {:.0f}%)",
                                       100.0 * s.concentration, signal, 100.0 * th.periodic_min_concentration)};
}

}  // namespace

std::string_view regime_name(Regime regime) {
  switch (regime) {
    case Regime::steady_vertical:
      return "steady_vertical";
    case Regime::steady_oblique:
      return "steady_oblique";
    case Regime::oblique_oscillating:
      return "oblique_oscillating";
    case Regime::zigzag:
      return "zigzag";
    case Regime::fluttering:
      return "fluttering";
    case Regime::tumbling:
      return "tumbling";
    case Regime::spiral:
      return "spiral";
    case Regime::chaotic:
      return "chaotic";
    case Regime::not_classified:
      break;
  }
  return "not classified";
}

bool is_decaying(const RegimeEvidence& e, const RegimeThresholds& th) {
  if (!is_unsteady(e, th)) return false;
  const UnsteadySignal s = unsteady_signal(e, th);
  return !is_drifting(s, th) && dies_away(s, th);
}

RegimeResult classify_regime(const RegimeEvidence& e, const RegimeThresholds& th) {
  if (!e.classifiable) return {Regime::not_classified, e.not_classifiable_reason};
  if (is_tumbling(e, th))
    return {Regime::tumbling,
            fmt::format("the axis turned {:.3g} turns about an axis {:.3g} deg above horizontal (monotonicity {:.2f})",
                        std::abs(e.axis_net_rotation) / (2.0 * std::numbers::pi), e.axis_rotation_elevation_deg,
                        e.axis_rotation_monotonicity)};
  if (lateral_is_steady(e, th) && tilt_is_steady(e, th)) return steady(e, th);
  return unsteady(e, th);
}

}  // namespace settle::analysis
