#pragma once
// Time control, kept out of the physics (docs/architecture.md, "The run loop and time control";
// the shape of Lethe's SimulationControl): the simulated time, the step, the end condition and
// which outputs are due. The physics only ever sees dt.
#include <cstdint>

namespace settle::coupling {

/// Steps of dt_si to reach end_time_si, the last one passing it by less than dt (a double, so
/// that a case asking for more steps than an integer holds can be refused with its count).
double steps_to_reach(double end_time_si, double dt_si);

/// An output that is due every `interval_si` seconds of simulated time (0 = every step;
/// negative = never).
class OutputSchedule {
 public:
  explicit OutputSchedule(double interval_si) : interval_si_(interval_si) {}
  /// True when an output is due at time t_si (the first one at t = 0); marks it done.
  bool due(double t_si, double dt_si);
  bool enabled() const { return interval_si_ >= 0.0; }
  /// Index of the next output (the one at next_index x interval; with an interval of 0, every
  /// step, the next step's number): what a checkpoint stores so that a continued run neither
  /// repeats nor skips an output.
  std::int64_t next_index() const { return next_index_; }
  void set_next_index(std::int64_t index) { next_index_ = index; }

 private:
  double interval_si_;
  std::int64_t next_index_ = 0;
};

/// t, dt, the step count and the end. Steps are counted as integers and t = step * dt, so the
/// time does not accumulate round-off.
class TimeControl {
 public:
  /// Starts at `start_step` (0 for a fresh run; a restored simulation's steps() to continue it).
  TimeControl(double dt_si, double end_time_si, std::int64_t start_step = 0);
  double dt_si() const { return dt_si_; }
  double time_si() const { return static_cast<double>(step_) * dt_si_; }
  double end_time_si() const { return end_time_si_; }
  std::int64_t step() const { return step_; }
  /// Steps needed to reach the end time (the last step may pass it by less than dt).
  std::int64_t total_steps() const { return total_steps_; }
  bool finished() const { return step_ >= total_steps_ || stopped_; }
  void advance() { ++step_; }
  /// Ends the run early (e.g. the particle reached a wall).
  void stop() { stopped_ = true; }

 private:
  double dt_si_;
  double end_time_si_;
  std::int64_t total_steps_;
  std::int64_t step_ = 0;
  bool stopped_ = false;
};

}  // namespace settle::coupling
