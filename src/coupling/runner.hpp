#pragma once
// The run loop around the coupled step: time control, output samples on their schedule,
// progress reports, the end condition, and the run's summary (time-averaged coefficients).
// Writing files is the caller's business (callbacks), so the loop is testable without a disk.
#include <cstdint>
#include <functional>
#include <limits>
#include <string>
#include <vector>

#include <Eigen/Core>

#include "attitude/attitude.hpp"
#include "body/rigid_body.hpp"
#include "coupling/simulation.hpp"

namespace settle::coupling {

/// The state of the run at one output time, SI, inertial frame unless named body.
struct Sample {
  double t_si = 0.0;
  Eigen::Vector3d position_si = Eigen::Vector3d::Zero();
  Eigen::Vector3d velocity_si = Eigen::Vector3d::Zero();
  Eigen::Vector3d angular_velocity_n_si = Eigen::Vector3d::Zero();
  Eigen::Vector3d angular_velocity_b_si = Eigen::Vector3d::Zero();
  attitude::Attitude attitude;
  body::Wrench hydrodynamic;  ///< mean over the steps since the previous sample (zero at t = 0)
  /// Speed of the flow relative to the body times d_eq / nu. Fixed bodies: the superficial
  /// velocity (the driven flow); others: the body's velocity (fluid at rest far away).
  double reynolds = 0.0;
  Eigen::Vector3d relative_flow_si = Eigen::Vector3d::Zero();  ///< far-field fluid minus body velocity
  double slip_max_si = 0.0;
  double slip_rms_si = 0.0;
  /// Particle-wall contact (StepObservation::contact: impulse / dt), mean over the steps since the
  /// previous sample: the impulse over the interval / its length; zero away from walls and at t = 0.
  body::Wrench contact;
  /// Smallest body-wall gap of the last step's corrector, m; infinity without contact walls (a
  /// following window, periodic axes, contact off, towed or fixed bodies) and at t = 0.
  double wall_gap_si = std::numeric_limits<double>::infinity();
};

/// The hydrodynamic and contact wrenches summed over the steps since the last sample. A row records
/// their means over its interval, so that a mean over rows is a time mean whatever the output
/// interval: the momentum exchange's force jumps from step to step as the body crosses cells, and
/// rows a whole number of cells of travel apart would all see the same phase of that cycle (a
/// towed sphere's drag came out 1.9 times too large so, docs/notes.md).
struct IntervalSums {
  body::Wrench hydrodynamic;
  body::Wrench contact;
  std::int64_t steps = 0;

  void add(const body::Wrench& step_hydrodynamic, const body::Wrench& step_contact);
};

/// Takes a sample of the simulation's current state; its wrenches are the means of `interval`,
/// or the last step's when the interval holds no step (a continued run whose checkpoint predates
/// the sums), zero at t = 0.
Sample take_sample(const Simulation& simulation, double t_si, const IntervalSums& interval = {});

/// The largest values the health check (coupling/health.hpp) met at the output times of a run:
/// how close the run came to its limits (summary.json "fluid_health").
struct RunExtremes {
  double density_deviation = 0.0;  ///< largest |rho - 1| (lattice units)
  double lattice_speed = 0.0;      ///< largest |u| dt / dx
};

/// Where run() starts, and the loop's own state that a checkpoint stores beside the simulation's.
/// A fresh run starts from the default; a continued run from what checkpoint_due was given, with
/// the simulation restored to the same step.
struct RunStart {
  std::int64_t step = 0;               ///< coupled steps already taken (== Simulation::steps())
  std::int64_t next_output_index = 0;  ///< OutputSchedule::next_index() of the samples
  std::vector<Sample> samples;         ///< recorded so far (RunResult::samples: the summary's data)
  double wall_seconds = 0.0;           ///< wall time of the run so far (earlier segments)
  RunExtremes extremes;                ///< of the health checks so far (earlier segments)
  IntervalSums interval;               ///< the wrenches since the last sample
};

struct RunCallbacks {
  std::function<void(const Sample&)> on_sample;         ///< every output time
  std::function<void(const std::string&)> on_progress;  ///< a progress line every few seconds
  /// After each sample: a non-empty reason ends the run there (e.g. "terminal_state").
  std::function<std::string(const Sample&)> stop_after_sample;
  /// Checked after every step (keep it cheap: an atomic flag set by a signal handler); true ends
  /// the run after the current step with stop_reason "interrupted".
  std::function<bool()> interrupted;
  /// At t = 0 and after every step, with the simulated time and dt (for outputs on their own
  /// schedule, e.g. VTK; keep it cheap when nothing is due).
  std::function<void(double t_si, double dt_si)> after_step;
  /// Called with the loop's state (RunStart) when a checkpoint is due: after the step that reaches
  /// each multiple of checkpoint_interval_si of simulated time (0: never; none at the start time,
  /// which the checkpoint or the case already describes), and once after the interrupting step,
  /// whatever the interval. It comes after that step's sample and after_step, so the state includes
  /// them. The caller writes the checkpoint (coupling/checkpoint_state.hpp). Also due once
  /// checkpoint_wall_interval_s of wall-clock time have passed since the last checkpoint (or the
  /// start of this run segment; 0: never): a long run on a shared machine loses at most that much
  /// work, however slowly its simulated time advances.
  std::function<void(const RunStart&)> checkpoint_due;
  /// Also once at the end of a run that was not interrupted (end time, terminal state, boundary),
  /// before its final sample, unless one was just written at that step: a finished run continues
  /// from its end (settle run --restart DIR --set run.end_time=T) rather than from an older one.
  bool checkpoint_at_end = false;
  double checkpoint_interval_si = 0.0;
  double checkpoint_wall_interval_s = 0.0;
};

struct RunResult {
  std::int64_t steps = 0;
  double simulated_time_si = 0.0;
  double wall_seconds = 0.0;  ///< a continued run: its earlier segments' (RunStart) included
  double mlups = 0.0;         ///< million fluid-cell updates per wall second over steps and wall_seconds
  std::string stop_reason;    ///< "end_time", "reached_boundary", "interrupted" or a stop_after_sample reason
  std::vector<Sample> samples;
  RunExtremes extremes;  ///< over every output time, earlier segments (RunStart) included
};

/// Runs from t = 0 to setup().end_time_si (or until the body reaches the grid's edge, a callback
/// stops it, or it is interrupted), sampling every setup().output_interval_si. The numerical
/// health (coupling/health.hpp) is checked at every sample: settle::NumericalError when it fails,
/// after the sample has been handed to on_sample.
RunResult run(Simulation& simulation, const RunCallbacks& callbacks, double progress_interval_wall_s = 5.0);

/// Continues a run from `start` (a checkpoint's loop state; the simulation restored to
/// start.step): the samples due before start.step are not taken again, and the result holds
/// start.samples followed by the new ones, as if the run had never stopped.
RunResult run(Simulation& simulation, const RunCallbacks& callbacks, RunStart start,
              double progress_interval_wall_s = 5.0);

/// Results of a run. Time averages are over the samples in the second half of the simulated
/// time (the first half is the start-up transient), or the last sample when there is none there.
/// These are the results of fixed and towed bodies; for a free body `settle run` reports the
/// terminal state the analysis detects (analysis/terminal_state.hpp) and falls back on these
/// averages only when that analysis cannot be made.
struct RunSummary {
  double terminal_velocity_si = 0.0;           ///< |mean velocity| (free), towing speed (towed), 0 (fixed)
  double terminal_vertical_velocity_si = 0.0;  ///< mean velocity along gravity, > 0 when sinking
  double reynolds = 0.0;                       ///< mean relative speed x d_eq / nu
  double drag_coefficient = 0.0;               ///< free: net weight / (rho U^2 pi d^2 / 8); else mean C_D
  double galileo = 0.0;
  std::string regime = "not classified";
  // Fixed and towed bodies (Zastawny et al. 2012 normalisation: forces by 1/2 rho U^2 pi d^2 / 4,
  // torque by that times d/2; U the mean relative flow speed).
  bool has_coefficients = false;
  double lift_coefficient = 0.0;    ///< |force normal to the relative flow| normalised
  double torque_coefficient = 0.0;  ///< |torque| normalised
  /// rms of the lift's fluctuation about its mean (the force normal to the relative flow), normalised
  double lift_fluctuation_coefficient = 0.0;
  Eigen::Vector3d mean_force_si = Eigen::Vector3d::Zero();
  Eigen::Vector3d mean_torque_si = Eigen::Vector3d::Zero();
  Eigen::Vector3d mean_relative_flow_si = Eigen::Vector3d::Zero();
  std::size_t averaged_samples = 0;
};

RunSummary summarise(const Simulation& simulation, const RunResult& result);

}  // namespace settle::coupling
