#pragma once
// Observables of a settling run and the whole analysis of one run: terminal state,
// averages over the terminal window, dimensionless groups, drag, tilt, lateral motion and its
// spectrum (spectrum.hpp), rotation, and the regime (regime_evidence.hpp, regime.hpp); its JSON is
// analysis_json.hpp. docs/analysis.md lists every definition.
//
// Conventions: SI units; inertial frame with gravity g (any direction; "down" is g/|g|, the
// vertical the line along g, "lateral" or horizontal the plane normal to it); body frame and
// C_b^n as in timeseries.hpp. Angles in the results are in degrees where the name says _deg,
// otherwise in radians; frequencies in Hz.
//
// Averages are time averages (trapezoidal rule over the samples) over the averaging window:
// from the detected terminal time to the end of the series when a terminal state is found
// (terminal_state.hpp), otherwise over the second half of the series (the result says which).
// The analysis applies to freely moving bodies (motion = "free").
#include <functional>
#include <memory>
#include <optional>
#include <string>
#include <vector>

#include <Eigen/Core>

#include "analysis/regime.hpp"
#include "analysis/spectrum.hpp"
#include "analysis/terminal_state.hpp"
#include "analysis/timeseries.hpp"
#include "common/physical_defaults.hpp"

namespace settle::body {
class Shape;
struct MassProperties;
}  // namespace settle::body
namespace settle::coupling {
struct SimulationSetup;
}

namespace settle::analysis {

/// Which body axis the tilt is measured on.
enum class AxisKind {
  none,      ///< no distinguished axis (sphere, cube: three equal principal moments)
  symmetry,  ///< the axis of the distinct principal moment of an axisymmetric body
  longest,   ///< the principal axis of least moment (the longest extent) of other bodies
};

/// The body axis chosen from the principal moments (ascending m0 <= m1 <= m2): none when
/// m2 - m0 <= 1e-6 m2; symmetry axis (the axis of m2, oblate) when m1 - m0 <= 1e-2 (m2 - m1);
/// symmetry axis (the axis of m0, prolate) when m2 - m1 <= 1e-2 (m1 - m0); otherwise the axis
/// of m0 (longest). The axis is a unit vector in the body frame.
struct BodyAxis {
  AxisKind kind = AxisKind::none;
  Eigen::Vector3d axis_b = Eigen::Vector3d::UnitZ();
};
BodyAxis body_axis(const body::MassProperties& mass_properties);

/// What the analysis needs to know of the particle and the fluid, SI.
struct ParticleProperties {
  double fluid_density_si = defaults::fluid_density_si;
  double dynamic_viscosity_si = defaults::dynamic_viscosity_si;
  Eigen::Vector3d gravity_si{0.0, 0.0, -defaults::gravity_si};
  double particle_density_si = defaults::particle_density_si;
  double volume_si = 0.0;
  double equivalent_diameter_si = 0.0;  ///< (6 V / pi)^(1/3)
  BodyAxis axis;
  /// Shadow area (m^2) along a unit direction given in the body frame; empty: the drag
  /// coefficient on the projected area is not computed.
  std::function<double(const Eigen::Vector3d&)> projected_area_si;
  /// Diameter and thickness of a disk (a cylinder shorter than its diameter), for I*.
  std::optional<double> disk_diameter_si;
  std::optional<double> disk_thickness_si;

  [[nodiscard]] double kinematic_viscosity_si() const { return dynamic_viscosity_si / fluid_density_si; }
};

/// Properties of a shape of uniform density in a fluid.
ParticleProperties particle_properties(std::shared_ptr<const body::Shape> shape, double particle_density_si,
                                       double fluid_density_si, double dynamic_viscosity_si,
                                       const Eigen::Vector3d& gravity_si);
/// Properties of a run's particle and fluid.
ParticleProperties particle_properties(const coupling::SimulationSetup& setup);

/// Parameters of the analysis, with their defaults.
struct AnalysisOptions {
  /// tau_p in s; default: estimated_response_time_si() of the particle.
  std::optional<double> response_time_si;
  double window_response_times = TerminalCriteria{}.window_response_times;
  double tolerance = TerminalCriteria{}.tolerance;
  std::size_t min_samples_per_window = TerminalCriteria{}.min_samples_per_window;
  RegimeThresholds thresholds;
};

/// The terminal-state criteria analyse() uses for this particle: tau_p from the options or
/// estimated_response_time_si(); window, tolerance and sample minimum from the options. The
/// runner's incremental detector (run.stop_at_terminal) must use the same, so that the run stops
/// where the analysis finds the terminal state. response_time_si is 0 without net weight.
TerminalCriteria terminal_criteria(const ParticleProperties& properties, const AnalysisOptions& options = {});

/// Everything the analysis finds (docs/analysis.md for each definition).
struct Analysis {
  // Terminal state and the averaging window.
  TerminalCriteria criteria;  ///< response_time_si = 0 when there is no net weight
  TerminalState terminal;
  bool averaged_over_terminal_window = false;         ///< else over the second half
  double window_start_si = 0.0, window_end_si = 0.0;  ///< first and last averaged sample
  std::size_t window_samples = 0;
  /// The part of the window the motion's fluctuation (lateral motion, tilt, rotation of the axis)
  /// and the regime are judged over: the whole window, or its later part when an oscillation
  /// dies away over it (regime.hpp, rule 3b). Its first sample and sample count.
  double regime_window_start_si = 0.0;
  std::size_t regime_window_samples = 0;

  // Velocity and path.
  Eigen::Vector3d mean_velocity_si = Eigen::Vector3d::Zero();
  double terminal_speed_si = 0.0;     ///< |mean velocity|
  double vertical_velocity_si = 0.0;  ///< mean velocity along g (> 0 sinking)
  /// How fast the velocity along g still changes over the window: the slope of the least-squares
  /// line through it over its mean, 1/s (0 when the mean is 0). A statement about a window that
  /// is not terminal ("rising 8% per window"); the terminal test itself compares window means.
  double vertical_velocity_trend_per_s = 0.0;
  double lateral_drift_speed_si = 0.0;   ///< |mean horizontal velocity|
  double path_angle_deg = 0.0;           ///< mean velocity from the vertical line, [0, 90]
  double lateral_displacement_si = 0.0;  ///< horizontal distance moved over the window
  /// Direction of the mean horizontal velocity, degrees in (-180, 180], counter-clockwise seen from
  /// above, from the horizontal projection of the x axis (of the y axis when g is along x). Empty
  /// when the path is less than the regime's oblique angle from the vertical.
  std::optional<double> drift_azimuth_deg;
  /// How fast the drift's direction turns, degrees per second (counter-clockwise positive): the
  /// azimuth of the mean horizontal velocity over the window's last quarter minus that over its
  /// first quarter, wrapped to (-180, 180], over the time between the quarters' midpoints. Empty
  /// when either quarter's path is less than the oblique angle from the vertical.
  std::optional<double> drift_turn_rate_deg_per_s;
  /// Time from the first sample at which the velocity along g first reaches 95% of the terminal
  /// vertical velocity (linear interpolation between samples): Mordant and Pinton's t_95. Empty
  /// unless the terminal state was reached, the body sinks, and the first sample is below 95%.
  std::optional<double> time_to_95_percent_si;
  /// Mordant and Pinton's own t_95: the T of u = U (1 - exp(-3 t / T)) fitted by least squares
  /// (U and T both free) to the velocity along g over the whole record, from its first sample.
  /// It differs from time_to_95_percent_si when the approach is not a single exponential (a bead
  /// that overshoots its terminal speed). Empty unless the terminal state was reached, the body
  /// sinks and starts from rest (along g below 5% of the terminal vertical velocity).
  std::optional<double> fitted_time_to_95_percent_si;
  std::optional<double> fitted_terminal_velocity_si;  ///< the fit's U, m/s
  std::optional<double> fit_rms_residual_si;          ///< rms of u - fit over the record, m/s

  // Dimensionless groups.
  double reynolds = 0.0;                        ///< |U| d_eq / nu
  double galileo = 0.0;                         ///< sqrt(|rho_p/rho_f - 1| g d_eq^3) / nu
  double archimedes = 0.0;                      ///< Ga^2
  double stokes_number = 0.0;                   ///< rho_p |U| d_eq / (9 mu) (ten Cate et al. 2002)
  double density_ratio = 0.0;                   ///< rho_p / rho_f
  std::optional<double> dimensionless_inertia;  ///< Field et al. 1997, disks only

  // Drag (NaN, and null in the JSON, when the body touched a wall in the window: wall_contact_samples).
  double drag_coefficient = 0.0;             ///< net weight along the mean motion / (rho U^2 / 2 pi d_eq^2 / 4)
  double drag_coefficient_from_force = 0.0;  ///< mean hydrodynamic force against the mean motion, same scale
  /// Averaged samples with a particle-wall contact force: the body rests on or strikes a wall, so
  /// the net weight is not balanced by the drag alone and no drag coefficient is given.
  std::size_t wall_contact_samples = 0;
  std::optional<double> projected_area_si;                ///< mean shadow along the mean motion
  std::optional<double> drag_coefficient_projected_area;  ///< drag_coefficient on projected_area_si
  Eigen::Vector3d mean_force_si = Eigen::Vector3d::Zero();
  Eigen::Vector3d mean_torque_si = Eigen::Vector3d::Zero();

  // Lateral motion (velocity normal to g, minus its mean).
  double lateral_amplitude_si = 0.0;        ///< sqrt(2 lambda_1) of its covariance
  double lateral_minor_amplitude_si = 0.0;  ///< sqrt(2 lambda_2)
  double lateral_circularity = 0.0;         ///< |<du x du'>| / sqrt(<|du|^2> <|du'|^2>)
  double lateral_trend_fraction = 0.0;      ///< variance fraction of a linear trend (least squares)
  double lateral_decay_ratio = 1.0;         ///< amplitude over the later half / the earlier half
  SpectralPeak lateral_peak;
  std::optional<double> lateral_frequency_hz;  ///< when the lateral motion is not steady
  std::optional<double> lateral_strouhal;      ///< f d_eq / |U|

  // Tilt of the body axis (when the body has one).
  BodyAxis axis;
  double tilt_mean_deg = 0.0;  ///< time mean of the angle between the axis line and the vertical
  /// Angle of the mean axis direction from the vertical, and sqrt(2) x rms of the axis' signed
  /// deviation from that mean axis in the plane it swings in. Undefined (empty) without an axis
  /// and for a tumbling body, whose axis has no mean direction to oscillate about.
  std::optional<double> mean_axis_tilt_deg;
  std::optional<double> tilt_amplitude_deg;
  double tilt_trend_fraction = 0.0;
  double tilt_decay_ratio = 1.0;  ///< amplitude over the later half / the earlier half
  SpectralPeak tilt_peak;
  std::optional<double> tilt_frequency_hz;
  std::optional<double> tilt_strouhal;

  // Rotation.
  Eigen::Vector3d mean_body_rotation_rate_si = Eigen::Vector3d::Zero();  ///< rad/s, body axes
  double axis_net_rotation = 0.0;      ///< rad, the axis' net turn about its mean rotation axis
  double axis_rotation_rate_si = 0.0;  ///< rad/s, net turn / window duration
  double axis_rotation_monotonicity = 0.0;
  double axis_rotation_elevation_deg = 90.0;

  RegimeEvidence evidence;
  RegimeResult regime;
  std::vector<std::string> warnings;
};

/// One line on the velocity the analysis found, that calls it terminal only when the terminal
/// state was detected: "terminal velocity along g 0.1234 m/s (|U| = ...), reached at t = ..." or
/// "not terminal: mean velocity along g over the second half (t = a .. b s) 0.00646 m/s, speeding
/// up 8% over these 0.2 s (terminal means a change below 1% per window of 5 response times)".
std::string velocity_statement(const Analysis& a);

/// The analysis of a free body's series (at least 2 samples, increasing t). settle::InputError
/// naming fluid.gravity when gravity is zero.
Analysis analyse(const SettlingSeries& series, const ParticleProperties& properties,
                 const AnalysisOptions& options = {});

}  // namespace settle::analysis
