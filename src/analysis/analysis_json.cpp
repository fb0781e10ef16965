#include "analysis/analysis_json.hpp"

#include <cmath>
#include <string_view>

#include <nlohmann/json.hpp>

namespace settle::analysis {
namespace {

nlohmann::ordered_json optional_json(const std::optional<double>& value) {
  return value ? nlohmann::ordered_json(*value) : nlohmann::ordered_json(nullptr);
}

nlohmann::ordered_json finite_or_null(double value) {
  return std::isfinite(value) ? nlohmann::ordered_json(value) : nlohmann::ordered_json(nullptr);
}

nlohmann::ordered_json vector_json(const Eigen::Vector3d& v) {
  return nlohmann::ordered_json::array({v[0], v[1], v[2]});
}

std::string_view axis_kind_name(AxisKind kind) {
  switch (kind) {
    case AxisKind::symmetry:
      return "symmetry";
    case AxisKind::longest:
      return "longest";
    case AxisKind::none:
      break;
  }
  return "none";
}

nlohmann::ordered_json peak_json(const SpectralPeak& peak, const std::optional<double>& frequency,
                                 const std::optional<double>& strouhal) {
  nlohmann::ordered_json j;
  j["frequency"] = optional_json(frequency);
  j["strouhal"] = optional_json(strouhal);
  j["spectral_concentration"] = peak.found ? nlohmann::ordered_json(peak.concentration) : nullptr;
  j["periods_in_window"] = peak.found ? nlohmann::ordered_json(peak.cycles) : nullptr;
  return j;
}

}  // namespace

nlohmann::ordered_json to_json(const Analysis& a) {
  using json = nlohmann::ordered_json;
  json j;
  // A velocity is called terminal only when the terminal state was detected; the mean over the
  // averaging window (terminal window or second half) is always given as late_mean_*.
  const bool reached = a.terminal.reached;
  j["terminal_velocity"] = reached ? json(a.terminal_speed_si) : json(nullptr);
  j["terminal_vertical_velocity"] = reached ? json(a.vertical_velocity_si) : json(nullptr);
  j["late_mean_velocity"] = a.terminal_speed_si;
  j["late_mean_vertical_velocity"] = a.vertical_velocity_si;
  j["late_velocity_trend"] = a.vertical_velocity_trend_per_s;
  j["reynolds"] = a.reynolds;
  j["drag_coefficient"] = finite_or_null(a.drag_coefficient);
  j["galileo"] = a.galileo;
  j["regime"] = regime_name(a.regime.regime);
  j["regime_reason"] = a.regime.reason;
  j["terminal_velocity_vector"] = reached ? vector_json(a.mean_velocity_si) : json(nullptr);
  j["late_mean_velocity_vector"] = vector_json(a.mean_velocity_si);
  j["archimedes"] = a.archimedes;
  j["stokes_number"] = a.stokes_number;
  j["density_ratio"] = a.density_ratio;
  j["dimensionless_inertia"] = optional_json(a.dimensionless_inertia);
  j["drag_coefficient_projected_area"] = optional_json(a.drag_coefficient_projected_area);
  j["projected_area"] = optional_json(a.projected_area_si);
  j["drag_coefficient_from_force"] = finite_or_null(a.drag_coefficient_from_force);
  j["wall_contact_samples"] = a.wall_contact_samples;

  json terminal;
  terminal["reached"] = a.terminal.reached;
  terminal["time"] = a.terminal.reached ? json(a.terminal.terminal_time_si) : json(nullptr);
  terminal["detected_at"] = a.terminal.reached ? json(a.terminal.detected_at_si) : json(nullptr);
  terminal["relative_change"] = a.terminal.reached ? json(a.terminal.relative_change) : json(nullptr);
  terminal["time_to_95_percent"] = optional_json(a.time_to_95_percent_si);
  terminal["time_to_95_percent_fit"] = optional_json(a.fitted_time_to_95_percent_si);
  terminal["terminal_velocity_fit"] = optional_json(a.fitted_terminal_velocity_si);
  terminal["fit_rms_residual"] = optional_json(a.fit_rms_residual_si);
  terminal["response_time"] = a.criteria.response_time_si;
  terminal["window"] = a.criteria.window_si();
  terminal["window_response_times"] = a.criteria.window_response_times;
  terminal["tolerance"] = a.criteria.tolerance;
  j["terminal_state"] = terminal;

  json averaging;
  averaging["basis"] = a.averaged_over_terminal_window ? "terminal_window" : "second_half";
  averaging["start_time"] = a.window_start_si;
  averaging["end_time"] = a.window_end_si;
  averaging["samples"] = a.window_samples;
  averaging["regime_start_time"] = a.regime_window_start_si;
  averaging["regime_samples"] = a.regime_window_samples;
  j["averaging"] = averaging;

  json lateral;
  lateral["drift_velocity"] = a.lateral_drift_speed_si;
  lateral["path_angle_deg"] = a.path_angle_deg;
  lateral["drift_azimuth_deg"] = optional_json(a.drift_azimuth_deg);
  lateral["drift_turn_rate_deg_per_s"] = optional_json(a.drift_turn_rate_deg_per_s);
  lateral["displacement"] = a.lateral_displacement_si;
  lateral["amplitude"] = a.lateral_amplitude_si;
  lateral["minor_amplitude"] = a.lateral_minor_amplitude_si;
  lateral["circularity"] = a.lateral_circularity;
  lateral["trend_fraction"] = a.lateral_trend_fraction;
  lateral["decay_ratio"] = a.lateral_decay_ratio;
  lateral.update(peak_json(a.lateral_peak, a.lateral_frequency_hz, a.lateral_strouhal));
  j["lateral"] = lateral;

  json tilt_json;
  tilt_json["axis"] = axis_kind_name(a.axis.kind);
  if (a.axis.kind != AxisKind::none) {
    tilt_json["axis_body"] = vector_json(a.axis.axis_b);
    tilt_json["mean_deg"] = a.tilt_mean_deg;
    tilt_json["mean_axis_deg"] = optional_json(a.mean_axis_tilt_deg);
    tilt_json["amplitude_deg"] = optional_json(a.tilt_amplitude_deg);
    tilt_json["trend_fraction"] = a.tilt_trend_fraction;
    tilt_json["decay_ratio"] = a.tilt_decay_ratio;
    tilt_json.update(peak_json(a.tilt_peak, a.tilt_frequency_hz, a.tilt_strouhal));
  }
  j["tilt"] = tilt_json;

  json rotation;
  rotation["mean_body_rate"] = vector_json(a.mean_body_rotation_rate_si);
  if (a.axis.kind != AxisKind::none) {
    rotation["axis_net_rotation"] = a.axis_net_rotation;
    rotation["axis_rotation_rate"] = a.axis_rotation_rate_si;
    rotation["axis_rotation_monotonicity"] = a.axis_rotation_monotonicity;
    rotation["rotation_axis_elevation_deg"] = a.axis_rotation_elevation_deg;
  }
  j["rotation"] = rotation;

  // The runner's averages (coupling::RunSummary), over the analysis' window.
  j["averaged_samples"] = a.window_samples;
  j["mean_force"] = vector_json(a.mean_force_si);
  j["mean_torque"] = vector_json(a.mean_torque_si);
  j["mean_relative_flow"] = vector_json(-a.mean_velocity_si);
  j["analysis_warnings"] = a.warnings;
  return j;
}

}  // namespace settle::analysis
