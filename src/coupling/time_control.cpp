#include "coupling/time_control.hpp"

#include <cmath>
#include <stdexcept>

namespace settle::coupling {

bool OutputSchedule::due(double t_si, double dt_si) {
  if (interval_si_ < 0.0) return false;
  if (interval_si_ == 0.0) {
    // Every step: next_index counts steps, so that a continued run does not repeat the sample of
    // the step it continues from.
    const auto step = static_cast<std::int64_t>(std::llround(t_si / dt_si));
    if (step < next_index_) return false;
    next_index_ = step + 1;
    return true;
  }
  // Due at the first step whose time reaches the next multiple of the interval (half a step
  // of slack so that round-off in t = n dt does not skip a row).
  const double next_time = static_cast<double>(next_index_) * interval_si_;
  if (t_si + 0.5 * dt_si < next_time) return false;
  next_index_ = static_cast<std::int64_t>(std::floor((t_si + 0.5 * dt_si) / interval_si_)) + 1;
  return true;
}

TimeControl::TimeControl(double dt_si, double end_time_si, std::int64_t start_step)
    : dt_si_(dt_si), end_time_si_(end_time_si), step_(start_step) {
  if (!(dt_si > 0.0) || !(end_time_si >= 0.0)) throw std::invalid_argument("TimeControl: dt > 0 and end >= 0 required");
  if (start_step < 0) throw std::invalid_argument("TimeControl: the start step must be >= 0");
  total_steps_ = static_cast<std::int64_t>(steps_to_reach(end_time_si, dt_si));
}

double steps_to_reach(double end_time_si, double dt_si) {
  // 1e-9 of a step of slack: an end time that is a whole number of steps is not rounded up.
  return std::ceil(end_time_si / dt_si - 1e-9);
}

}  // namespace settle::coupling
