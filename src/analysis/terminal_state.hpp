#pragma once
// Terminal-state detection: the particle has reached its terminal state when the
// mean velocity over a window of several particle response times no longer changes.
//
// Criterion. With W the window length, the detector compares, at every sample time t, the
// weighted mean velocity over the window [t - W, t] with the one over the window before it,
// [t - 2W, t - W]:
//
//     |U(t) - U(t - W)| / |U(t)| < tolerance,   U(t) = weighted mean of u over [t - W, t].
//
// The first t at which this holds is the detection time; the terminal state is taken to start
// at terminal_time = t - W, the start of the window whose mean agrees with the one before it.
// The averages of the analysis then run from terminal_time to the end, so that even a run
// stopped at detection (run.stop_at_terminal) has one full window of terminal samples.
//
// Weighting. The means are weighted by a Hann window, w(s) = sin^2(pi s / W): for a periodic
// regime (zigzag, spiral) the mean of an oscillation over a window holding c > 2 periods is
// reduced by |sinc(c) / (1 - c^2)| (< 0.027 for c > 2, falling as c^-3), where a plain mean
// leaves up to 1/(pi c). The window must therefore hold at least two periods; see the default
// window below. The integrals are trapezoidal sums over the samples in each window (the
// normalisation uses the same sum, so a constant velocity has exactly that mean); a window of
// more than 512 samples is summed over every k-th one (k = ceil(n / 512)), so that a check costs
// the same when every time step is an output sample.
//
// Response time. tau_p = (rho_p + C_m rho_f) U_t / (|rho_p - rho_f| g): the time the particle
// would take to reach its terminal speed U_t under its initial acceleration (net weight over
// mass plus added mass, C_m = 1/2 for a sphere). In the Stokes regime U_t = |rho_p - rho_f| g
// d^2 / (18 mu) and tau_p is the Stokes response time (rho_p + C_m rho_f) d^2 / (18 mu); at
// larger Reynolds numbers it stays the time scale of the approach: Mordant and Pinton (2000),
// "Velocity measurement of a settling sphere", Eur. Phys. J. B 18 (journal details as quoted in
// validation/reference-data.json), fitted u = U_t (1 - exp(-3 t / t_95)) to settling spheres at
// Re = 37, and t_95 / 3 is within 20% of tau_p (tests/analysis/test_terminal_state.cpp), whereas
// the Stokes formula, with U_t in place, would overestimate it by the factor 1 + 0.15 Re^0.687. U_t is not known before
// the run, so the detector uses an estimate: the terminal speed of the volume-equivalent sphere
// with the Schiller-Naumann drag law (coupling::estimated_terminal_speed_si), the same before,
// during and after a run.
#include <cstddef>
#include <deque>
#include <optional>
#include <vector>

#include <Eigen/Core>

namespace settle::analysis {

/// The parameters of the criterion (file comment), with their defaults.
struct TerminalCriteria {
  /// tau_p in s (> 0). Use estimated_response_time_si() for a particle.
  double response_time_si = 0.0;
  /// W / tau_p. Five response times: the exponential part of the approach decays by e^-5
  /// within one window. A path oscillation of Strouhal number Sr = f d / U has the period
  /// T = (3/4) C_D rho_f / (Sr (rho_p + rho_f/2)) tau_p (force balance at the terminal state):
  /// 2 to 4 tau_p for a sphere of rho_p/rho_f = 1.5 past the onset of path oscillation
  /// (C_D = 0.65, Sr = 0.06 to 0.12), so a window holds 1.3 to 2.5 periods. That is the
  /// compromise with the run length (detection needs at least 2W); the analysis warns when a
  /// window holds fewer than two of the periods it measures, and a longer window can be asked
  /// for (settle analyze --window).
  double window_response_times = 5.0;
  /// Largest relative change of the window mean velocity between consecutive windows.
  double tolerance = 0.01;
  /// A window with fewer samples is not judged (its mean would be too coarse); reached() stays
  /// false until both windows have this many.
  std::size_t min_samples_per_window = 8;

  [[nodiscard]] double window_si() const { return window_response_times * response_time_si; }
  /// The criterion compares two whole windows, so it cannot hold before this time after the
  /// series' first sample (the release of a held body): 2W. An approach slower than e^(-t/tau_p)
  /// is detected later.
  [[nodiscard]] double earliest_detection_si() const { return 2.0 * window_si(); }
  /// std::invalid_argument naming the parameter when a value is out of range.
  void validate() const;
};

/// The terminal state found (or not) in a series.
struct TerminalState {
  bool reached = false;
  double terminal_time_si = 0.0;                                      ///< start of the terminal window (t_detected - W)
  double detected_at_si = 0.0;                                        ///< sample time at which the criterion first held
  Eigen::Vector3d window_mean_velocity_si = Eigen::Vector3d::Zero();  ///< U over [t - W, t] at detection
  double relative_change = 0.0;                                       ///< |U(t) - U(t - W)| / |U(t)| at detection
  /// Largest number of samples seen in one window; below min_samples_per_window the output is
  /// too coarse for the criterion.
  std::size_t samples_per_window = 0;
};

/// Incremental detector: feed it every output sample; once reached() it stays reached.
/// Memory is bounded by the samples of two windows.
class TerminalStateDetector {
 public:
  explicit TerminalStateDetector(const TerminalCriteria& criteria);

  /// Adds the velocity (m/s, any frame) at time t (s). std::invalid_argument when t does not
  /// increase. Samples after detection are ignored.
  void add(double t_si, const Eigen::Vector3d& velocity_si);

  [[nodiscard]] bool reached() const { return state_.reached; }
  /// Start of the terminal window (t_detected - W); meaningful once reached().
  [[nodiscard]] double terminal_time() const { return state_.terminal_time_si; }
  [[nodiscard]] const TerminalState& state() const { return state_; }
  [[nodiscard]] const TerminalCriteria& criteria() const { return criteria_; }

 private:
  struct Sample {
    double t;
    Eigen::Vector3d u;
  };
  void check(double t_si);

  TerminalCriteria criteria_;
  std::deque<Sample> samples_;
  std::optional<double> first_t_, last_t_;
  TerminalState state_;
};

/// The detector run over a whole series (identical to feeding it sample by sample).
/// t_si and velocity_si have the same length.
TerminalState detect_terminal_state(const std::vector<double>& t_si, const std::vector<Eigen::Vector3d>& velocity_si,
                                    const TerminalCriteria& criteria);

/// tau_p = (rho_p + C_m rho_f) U / (|rho_p - rho_f| g) (file comment), s. Zero when
/// rho_p = rho_f (no net weight: no approach to a terminal speed).
double response_time_si(double particle_density_si, double fluid_density_si, double gravity_si,
                        double terminal_speed_si, double added_mass_coefficient = 0.5);

/// tau_p with U estimated as the Schiller-Naumann terminal speed of the volume-equivalent
/// sphere of diameter d (coupling::estimated_terminal_speed_si).
double estimated_response_time_si(double equivalent_diameter_si, double particle_density_si, double fluid_density_si,
                                  double dynamic_viscosity_si, double gravity_si, double added_mass_coefficient = 0.5);

}  // namespace settle::analysis
