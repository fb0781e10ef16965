#include "coupling/runner.hpp"

#include <algorithm>
#include <array>
#include <chrono>
#include <cmath>
#include <numbers>
#include <stdexcept>

#include <fmt/core.h>

#include "common/error.hpp"
#include "coupling/health.hpp"
#include "coupling/time_control.hpp"
#include "parallel/communicator.hpp"

namespace settle::coupling {
namespace {

using Clock = std::chrono::steady_clock;

double seconds_since(Clock::time_point start) { return std::chrono::duration<double>(Clock::now() - start).count(); }

// wall_s: of this segment, which began at start_step (0, or a restart's step).
std::string progress_line(const Simulation& sim, const TimeControl& time, std::int64_t start_step, double wall_s) {
  const double fraction =
      static_cast<double>(time.step()) / static_cast<double>(std::max<std::int64_t>(1, time.total_steps()));
  const double steps_done = static_cast<double>(time.step() - start_step);
  const double steps_left = static_cast<double>(std::max<std::int64_t>(0, time.total_steps() - time.step()));
  const double eta = steps_done > 0.0 ? wall_s * steps_left / steps_done : 0.0;
  const double mlups = sim.lattice_cell_count() * steps_done / wall_s / 1e6;
  return fmt::format("t = {:.4g} s ({:.1f}%), |u| = {:.4g} m/s, ETA {:.0f} s, {:.1f} MLUPS", time.time_si(),
                     100.0 * fraction, sim.body().state().velocity_si.norm(), eta, mlups);
}

}  // namespace

void IntervalSums::add(const body::Wrench& step_hydrodynamic, const body::Wrench& step_contact) {
  hydrodynamic.force_si += step_hydrodynamic.force_si;
  hydrodynamic.torque_si += step_hydrodynamic.torque_si;
  contact.force_si += step_contact.force_si;
  contact.torque_si += step_contact.torque_si;
  ++steps;
}

namespace {

body::Wrench mean_of(const body::Wrench& sum, std::int64_t steps) {
  const double n = static_cast<double>(steps);
  return {sum.force_si / n, sum.torque_si / n};
}

}  // namespace

Sample take_sample(const Simulation& sim, double t_si, const IntervalSums& interval) {
  const auto& state = sim.body().state();
  Sample s;
  s.t_si = t_si;
  s.position_si = state.position_si;
  s.velocity_si = state.velocity_si;
  s.angular_velocity_b_si = state.angular_velocity_b_si;
  s.angular_velocity_n_si = sim.body().angular_velocity_n_si();
  s.attitude = state.attitude;
  s.slip_max_si = sim.last_step().slip_max_si;
  s.slip_rms_si = sim.last_step().slip_rms_si;
  if (interval.steps > 0) {
    s.hydrodynamic = mean_of(interval.hydrodynamic, interval.steps);
    s.contact = mean_of(interval.contact, interval.steps);
  } else if (sim.steps() > 0) {
    s.hydrodynamic = sim.last_step().hydrodynamic;
    s.contact = sim.last_step().contact;
  }
  if (sim.steps() > 0) s.wall_gap_si = sim.last_step().wall_gap_si;
  // The far field: the stream entering at an inlet, else the driven flow around a fixed body and
  // fluid at rest around a moving one.
  if (sim.setup().inflow) {
    s.relative_flow_si = sim.setup().inflow_velocity_si - state.velocity_si;
  } else {
    s.relative_flow_si = sim.body().motion_kind() == body::MotionKind::fixed ? sim.superficial_velocity_si()
                                                                             : Eigen::Vector3d(-state.velocity_si);
  }
  s.reynolds = s.relative_flow_si.norm() * sim.plan().equivalent_diameter_si / sim.units().kinematic_viscosity_si();
  return s;
}

namespace {

// A signal, or the wall clock, reaches the ranks of a split run after different steps: a rank that
// stopped or checkpointed alone would leave the others waiting. They act when any rank saw the
// event (`asked`: the events can happen at all, the same on every rank).
std::array<bool, 2> decided_together(parallel::Communicator& ranks, std::array<bool, 2> seen, bool asked) {
  if (ranks.size() == 1 || !asked) return seen;
  const std::vector<double> any = parallel::sum_in_rank_order(ranks, {seen[0] ? 1.0 : 0.0, seen[1] ? 1.0 : 0.0});
  return {any[0] > 0.0, any[1] > 0.0};
}

}  // namespace

RunResult run(Simulation& sim, const RunCallbacks& callbacks, double progress_interval_wall_s) {
  return run(sim, callbacks, RunStart{}, progress_interval_wall_s);
}

RunResult run(Simulation& sim, const RunCallbacks& callbacks, RunStart start, double progress_interval_wall_s) {
  if (start.step != sim.steps())
    throw std::invalid_argument(
        fmt::format("run: the start step {} is not the simulation's step {}", start.step, sim.steps()));
  TimeControl time(sim.units().dt_si(), sim.setup().end_time_si, start.step);
  OutputSchedule output(sim.setup().output_interval_si);
  output.set_next_index(start.next_output_index);
  // Checkpoints at the multiples of their interval after the start time (marked done here): a
  // checkpoint at the start would hold what the case or the restored checkpoint already holds.
  OutputSchedule checkpoints(
      callbacks.checkpoint_due && callbacks.checkpoint_interval_si > 0.0 ? callbacks.checkpoint_interval_si : -1.0);
  checkpoints.due(time.time_si(), time.dt_si());
  RunResult result;
  result.samples = std::move(start.samples);
  result.extremes = start.extremes;
  IntervalSums interval = start.interval;
  const auto segment_start = Clock::now();
  const auto wall_so_far = [&] { return start.wall_seconds + seconds_since(segment_start); };
  double next_progress_s = progress_interval_wall_s;

  std::string stop_reason;
  std::int64_t healthy_at_step = -1;  // the last step whose fluid check_health passed
  const auto check_fluid_health = [&] {
    if (healthy_at_step == time.step()) return;
    const HealthReport health = check_health(sim);
    result.extremes.density_deviation = std::max(
        {result.extremes.density_deviation, std::abs(health.min_density - 1.0), std::abs(health.max_density - 1.0)});
    result.extremes.lattice_speed = std::max(result.extremes.lattice_speed, health.max_lattice_speed);
    if (!health.problem.empty())
      throw NumericalError(fmt::format("at t = {:.6g} s (step {}): {}", time.time_si(), time.step(), health.problem));
    healthy_at_step = time.step();
  };
  const auto record_sample = [&] {
    result.samples.push_back(take_sample(sim, time.time_si(), interval));
    interval = IntervalSums{};
    if (callbacks.on_sample) callbacks.on_sample(result.samples.back());
    check_fluid_health();
    if (callbacks.stop_after_sample) stop_reason = callbacks.stop_after_sample(result.samples.back());
  };
  const auto sample_if_due = [&] {
    if (output.due(time.time_si(), time.dt_si())) record_sample();
    if (callbacks.after_step) callbacks.after_step(time.time_si(), time.dt_si());
  };
  double last_checkpoint_wall_s = 0.0;  // of this segment
  std::int64_t last_checkpoint_step = -1;
  const auto wall_checkpoint_due = [&] {
    return callbacks.checkpoint_wall_interval_s > 0.0 &&
           seconds_since(segment_start) - last_checkpoint_wall_s >= callbacks.checkpoint_wall_interval_s;
  };
  const auto hand_over_checkpoint = [&] {
    // Also between samples: a checkpoint of a diverged fluid would replace the last good one.
    check_fluid_health();
    // The samples are lent to the state rather than copied (a long run holds many); they come back
    // before anything else reads them.
    RunStart state{time.step(),   output.next_index(), std::move(result.samples),
                   wall_so_far(), result.extremes,     interval};
    callbacks.checkpoint_due(state);
    result.samples = std::move(state.samples);
    last_checkpoint_wall_s = seconds_since(segment_start);
    last_checkpoint_step = time.step();
  };

  sample_if_due();
  result.stop_reason = "end_time";
  while (!time.finished()) {
    if (!sim.can_step()) {
      result.stop_reason = "reached_boundary";
      time.stop();
      break;
    }
    sim.step();
    interval.add(sim.last_step().hydrodynamic, sim.last_step().contact);
    time.advance();
    sample_if_due();
    // Checkpoints and stops wait for the end of a body step that spans two lattice steps.
    if (!sim.between_body_steps()) continue;
    const std::array<bool, 2> wall_events = decided_together(
        sim.communicator(),
        {stop_reason.empty() && callbacks.interrupted && callbacks.interrupted(),
         callbacks.checkpoint_due && wall_checkpoint_due()},
        callbacks.interrupted || (callbacks.checkpoint_due && callbacks.checkpoint_wall_interval_s > 0.0));
    if (wall_events[0]) stop_reason = "interrupted";
    // Both schedules are asked every step (OutputSchedule::due marks its time done).
    const bool simulated_due = checkpoints.due(time.time_si(), time.dt_si());
    if (callbacks.checkpoint_due && (simulated_due || wall_events[1] || stop_reason == "interrupted"))
      hand_over_checkpoint();
    if (!stop_reason.empty()) {
      result.stop_reason = stop_reason;
      break;
    }
    const double wall = seconds_since(segment_start);
    if (callbacks.on_progress && wall >= next_progress_s) {
      callbacks.on_progress(progress_line(sim, time, start.step, wall));
      next_progress_s = wall + progress_interval_wall_s;
    }
  }
  // The end's checkpoint comes before the final sample, as an interruption's, so that a restart
  // cuts that row off and the continued series is the longer run's. A body step spanning two
  // lattice steps cut by the end has no state to resume from: no checkpoint then.
  if (callbacks.checkpoint_due && callbacks.checkpoint_at_end && result.stop_reason != "interrupted" &&
      sim.between_body_steps() && last_checkpoint_step != time.step())
    hand_over_checkpoint();
  // The final state is always sampled, so that the last row is the end of the run (an interrupted
  // run's too: its checkpoint was written before, and a restart cuts the row off again).
  if (result.samples.empty() || result.samples.back().t_si < time.time_si()) record_sample();
  result.steps = time.step();
  result.simulated_time_si = time.time_si();
  result.wall_seconds = wall_so_far();
  result.mlups = result.wall_seconds > 0.0
                     ? sim.lattice_cell_count() * static_cast<double>(result.steps) / result.wall_seconds / 1e6
                     : 0.0;
  return result;
}

RunSummary summarise(const Simulation& sim, const RunResult& result) {
  RunSummary summary;
  summary.galileo = sim.plan().galileo;
  const double d = sim.plan().equivalent_diameter_si;
  const double rho = sim.setup().fluid_density_si;
  const double nu = sim.units().kinematic_viscosity_si();
  const double area = std::numbers::pi * d * d / 4.0;
  if (result.samples.empty()) return summary;

  // Averaging window: the second half of the simulated time (the first sample, t = 0, never).
  const double t_start = 0.5 * result.simulated_time_si;
  Eigen::Vector3d velocity = Eigen::Vector3d::Zero();
  std::size_t count = 0;
  for (const Sample& s : result.samples) {
    if (s.t_si < t_start || s.t_si <= 0.0) continue;
    velocity += s.velocity_si;
    summary.mean_force_si += s.hydrodynamic.force_si;
    summary.mean_torque_si += s.hydrodynamic.torque_si;
    summary.mean_relative_flow_si += s.relative_flow_si;
    ++count;
  }
  if (count == 0) {
    const Sample& s = result.samples.back();
    velocity = s.velocity_si;
    summary.mean_force_si = s.hydrodynamic.force_si;
    summary.mean_torque_si = s.hydrodynamic.torque_si;
    summary.mean_relative_flow_si = s.relative_flow_si;
    count = 1;
  } else {
    const double n = static_cast<double>(count);
    velocity /= n;
    summary.mean_force_si /= n;
    summary.mean_torque_si /= n;
    summary.mean_relative_flow_si /= n;
  }
  summary.averaged_samples = count;

  const Eigen::Vector3d gravity = sim.setup().gravity_si;
  const Eigen::Vector3d down = gravity.norm() > 0.0 ? Eigen::Vector3d(gravity.normalized()) : Eigen::Vector3d::Zero();
  const double speed = summary.mean_relative_flow_si.norm();
  summary.terminal_velocity_si = velocity.norm();
  summary.terminal_vertical_velocity_si = velocity.dot(down);
  summary.reynolds = speed * d / nu;
  const double dynamic_pressure_area = 0.5 * rho * speed * speed * area;
  if (dynamic_pressure_area <= 0.0) return summary;

  if (sim.body().motion_kind() == body::MotionKind::free) {
    // At the terminal state the drag balances the net weight.
    summary.drag_coefficient = sim.body().net_weight_si().norm() / dynamic_pressure_area;
    return summary;
  }
  const Eigen::Vector3d flow = summary.mean_relative_flow_si / speed;
  const double drag = summary.mean_force_si.dot(flow);
  summary.has_coefficients = true;
  summary.drag_coefficient = drag / dynamic_pressure_area;
  summary.lift_coefficient = (summary.mean_force_si - drag * flow).norm() / dynamic_pressure_area;
  summary.torque_coefficient = summary.mean_torque_si.norm() / (dynamic_pressure_area * 0.5 * d);
  const Eigen::Vector3d mean_lift = summary.mean_force_si - drag * flow;
  double square_sum = 0.0;
  for (const Sample& s : result.samples) {
    if (s.t_si < t_start || s.t_si <= 0.0) continue;
    const Eigen::Vector3d force = s.hydrodynamic.force_si;
    square_sum += (force - force.dot(flow) * flow - mean_lift).squaredNorm();
  }
  summary.lift_fluctuation_coefficient = std::sqrt(square_sum / static_cast<double>(count)) / dynamic_pressure_area;
  return summary;
}

}  // namespace settle::coupling
