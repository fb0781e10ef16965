// `settle attitude`: torque-free rigid-body rotation from initial body rates, or attitude
// reconstruction from a body-rate time series, by the dual-Euler whole-attitude solver
// (Cheng et al. 2023, doi:10.1063/5.0165555, supplementary material) or the unit-quaternion
// reference (docs/architecture.md, "Contracts"; docs/attitude.md).
#include <algorithm>
#include <charconv>
#include <cmath>
#include <cstdio>
#include <memory>
#include <optional>
#include <string>
#include <string_view>
#include <vector>

#include <fmt/core.h>

#include "app/commands.hpp"
#include "attitude/attitude.hpp"
#include "attitude/body_rate_series.hpp"
#include "attitude/integrators.hpp"
#include "attitude/rotational_dynamics.hpp"
#include "common/error.hpp"

namespace settle::app {
namespace {

using attitude::Attitude;

/// The flags as typed; every one is parsed and checked by hand so that all bad input
/// leaves through InputError (exit status 2) with the flag's name.
struct AttitudeOptions {
  std::string inertia, omega, omega_file, euler = "0,0,0", dt, t_end;
  std::string method = "dual-euler", output, output_every = "1";
};

enum class Method { dual_euler, quaternion };

/// A checked run description.
struct AttitudeRun {
  Eigen::Vector3d inertia = Eigen::Vector3d::Ones();  ///< principal moments, body axes
  std::optional<Eigen::Vector3d> omega0_b;            ///< torque-free mode
  std::optional<attitude::BodyRateSeries> series;     ///< kinematics mode
  Eigen::Vector3d euler = Eigen::Vector3d::Zero();    ///< set-1 (psi, theta, gamma), rad
  double dt = 0.0;
  double t_end = 0.0;
  Method method = Method::dual_euler;
  std::string output;  ///< empty: stdout
  long output_every = 1;
};

std::string_view trim(std::string_view text) {
  const auto first = text.find_first_not_of(" \t");
  if (first == std::string_view::npos) return {};
  return text.substr(first, text.find_last_not_of(" \t") - first + 1);
}

double parse_number(std::string_view flag, std::string_view text) {
  const std::string_view field = trim(text);
  double value = 0.0;
  const auto* end = field.data() + field.size();
  const auto [ptr, error] = std::from_chars(field.data(), end, value);
  if (field.empty() || error != std::errc() || ptr != end || !std::isfinite(value)) {
    throw InputError(fmt::format("{}: '{}' is not a finite number", flag, field));
  }
  return value;
}

Eigen::Vector3d parse_vector3(std::string_view flag, const std::string& text) {
  std::vector<std::string_view> fields;
  std::string_view rest = text;
  for (auto comma = rest.find(',');; comma = rest.find(',')) {
    fields.push_back(rest.substr(0, comma));
    if (comma == std::string_view::npos) break;
    rest.remove_prefix(comma + 1);
  }
  if (fields.size() != 3) {
    throw InputError(fmt::format("{}: expected 3 comma-separated numbers, got {} in '{}'", flag, fields.size(), text));
  }
  return {parse_number(flag, fields[0]), parse_number(flag, fields[1]), parse_number(flag, fields[2])};
}

double parse_positive(std::string_view flag, const std::string& text) {
  if (text.empty()) throw InputError(fmt::format("{}: required", flag));
  const double value = parse_number(flag, text);
  if (!(value > 0.0)) throw InputError(fmt::format("{}: must be > 0, got {}", flag, value));
  return value;
}

Eigen::Vector3d parse_inertia(const std::string& text) {
  if (text.empty()) throw InputError("--inertia: required (principal moments I1,I2,I3 in kg m^2)");
  const Eigen::Vector3d inertia = parse_vector3("--inertia", text);
  if ((inertia.array() <= 0.0).any()) {
    throw InputError(
        fmt::format("--inertia: every moment must be > 0, got {},{},{}", inertia[0], inertia[1], inertia[2]));
  }
  // A physical body has each principal moment at most the sum of the other two (equality for
  // a flat lamina); the small slack absorbs the rounding of decimal input such as 0.1,0.2,0.3.
  for (int i = 0; i < 3; ++i) {
    const double others = inertia.sum() - inertia[i];
    if (others < inertia[i] * (1.0 - 1e-12)) {
      throw InputError(
          fmt::format("--inertia: each moment must not exceed the sum of the other two "
                      "(triangle inequality of a physical body), got {},{},{}",
                      inertia[0], inertia[1], inertia[2]));
    }
  }
  return inertia;
}

attitude::BodyRateSeries read_series(const std::string& path, double t_end) {
  try {
    attitude::BodyRateSeries series = attitude::BodyRateSeries::read_csv(path);
    if (series.start_time() > 0.0 || series.end_time() < t_end) {
      throw InputError(fmt::format("'{}': the series covers [{}, {}] s but the run needs [0, {}] s", path,
                                   series.start_time(), series.end_time(), t_end));
    }
    return series;
  } catch (const InputError& e) {
    throw InputError(fmt::format("--omega-file: {}", e.what()));
  }
}

// The energy 0.5 w.(I w) and the angular momentum |I w| the torque-free run conserves (and prints)
// must be numbers: beyond about 1e154 rad/s they overflow, and every row after the first is NaN.
void check_invariants_finite(const Eigen::Vector3d& inertia, const Eigen::Vector3d& omega_b) {
  const Eigen::Vector3d momentum = inertia.cwiseProduct(omega_b);
  const double energy = 0.5 * omega_b.dot(momentum);
  if (std::isfinite(energy) && std::isfinite(momentum.norm())) return;
  throw InputError(fmt::format(
      "--omega: with --inertia {:g},{:g},{:g} the rotational energy 0.5 w.(I w) of the body rates {:g},{:g},{:g} "
      "rad/s overflows double precision ({}); give smaller rates or moments (other units)",
      inertia[0], inertia[1], inertia[2], omega_b[0], omega_b[1], omega_b[2], energy));
}

// A state that is no longer finite ends the run (exit status 3) before its row is written: the rows
// before it are the run's valid part.
void require_finite_state(double t, long step, const Eigen::Vector3d& omega_b, bool attitude_finite) {
  if (omega_b.allFinite() && attitude_finite) return;
  throw NumericalError(fmt::format(
      "settle attitude: at t = {} s (step {}) the body rates or the attitude are no longer finite "
      "(w = {:g},{:g},{:g} rad/s): the step w dt is too large for the integrator; lower --dt. The rows written "
      "before t = {} s are valid",
      t, step, omega_b[0], omega_b[1], omega_b[2], t));
}

AttitudeRun check(const AttitudeOptions& o) {
  AttitudeRun run;
  run.inertia = parse_inertia(o.inertia);
  run.dt = parse_positive("--dt", o.dt);
  run.t_end = parse_positive("--t-end", o.t_end);
  // A bound on the work: beyond 1e9 steps the run would take hours and the output terabytes.
  if (run.t_end / run.dt > 1e9) {
    throw InputError(fmt::format("--dt: t_end/dt = {:.3g} steps, at most 1e9 allowed", run.t_end / run.dt));
  }
  run.euler = parse_vector3("--euler", o.euler);
  if (o.method == "dual-euler") {
    run.method = Method::dual_euler;
  } else if (o.method == "quaternion") {
    run.method = Method::quaternion;
  } else {
    throw InputError(fmt::format("--method: must be dual-euler or quaternion, got '{}'", o.method));
  }
  const double every = parse_number("--output-every", o.output_every);
  if (!(every >= 1.0 && every <= 1e12) || every != std::floor(every)) {
    throw InputError(fmt::format("--output-every: must be an integer >= 1, got '{}'", o.output_every));
  }
  run.output_every = static_cast<long>(every);
  if (o.omega.empty() == o.omega_file.empty()) {
    throw InputError(
        "--omega, --omega-file: give exactly one (initial body rates for torque-free motion, "
        "or a CSV body-rate series t,wx,wy,wz)");
  }
  if (!o.omega.empty()) {
    run.omega0_b = parse_vector3("--omega", o.omega);
    check_invariants_finite(run.inertia, *run.omega0_b);
  } else {
    run.series = read_series(o.omega_file, run.t_end);
  }
  run.output = o.output;
  return run;
}

// ---------------------------------------------------------------------------------------
// Output

class CsvOutput {
 public:
  explicit CsvOutput(const std::string& path)
      : file_(path.empty() ? stdout : std::fopen(path.c_str(), "w")), path_(path) {
    if (file_ == nullptr) throw InputError(fmt::format("-o: cannot open '{}' for writing", path));
    fmt::print(file_,
               "t,wx,wy,wz,psi,theta,gamma,psi_r,theta_r,gamma_r,euler_set,"
               "R11,R12,R13,R21,R22,R23,R31,R32,R33,energy,angular_momentum\n");
  }
  CsvOutput(const CsvOutput&) = delete;
  CsvOutput& operator=(const CsvOutput&) = delete;
  ~CsvOutput() {
    if (file_ != nullptr && file_ != stdout) std::fclose(file_);
  }

  void row(double t, const Eigen::Vector3d& omega_b, const Attitude& attitude, attitude::EulerSet set,
           const Eigen::Vector3d& inertia) {
    // Adding +0.0 turns a negative zero (e.g. -sin(0)) into 0, so the CSV reads "0".
    const Eigen::Vector3d set1 = attitude.set1_angles().array() + 0.0;
    const Eigen::Vector3d set2 = attitude.set2_angles().array() + 0.0;
    const Eigen::Matrix3d r = attitude.body_to_inertial().array() + 0.0;
    const Eigen::Vector3d momentum = inertia.cwiseProduct(omega_b);
    const double energy = 0.5 * omega_b.dot(momentum);
    fmt::print(file_, "{:.17g},{:.17g},{:.17g},{:.17g},{:.17g},{:.17g},{:.17g},{:.17g},{:.17g},{:.17g},{},", t,
               omega_b[0], omega_b[1], omega_b[2], set1[0], set1[1], set1[2], set2[0], set2[1], set2[2],
               static_cast<int>(set));
    fmt::print(file_, "{:.17g},{:.17g},{:.17g},{:.17g},{:.17g},{:.17g},{:.17g},{:.17g},{:.17g},", r(0, 0), r(0, 1),
               r(0, 2), r(1, 0), r(1, 1), r(1, 2), r(2, 0), r(2, 1), r(2, 2));
    fmt::print(file_, "{:.17g},{:.17g}\n", energy, momentum.norm());
  }

  void finish() {
    if (std::fflush(file_) != 0 || std::ferror(file_) != 0) {
      throw InputError(fmt::format("-o: writing '{}' failed", path_.empty() ? "<stdout>" : path_));
    }
  }

 private:
  std::FILE* file_;
  std::string path_;
};

// ---------------------------------------------------------------------------------------
// Time stepping: steps of dt, the last one shortened to end exactly at t_end.

struct Schedule {
  long steps;
  double dt;
  double t_end;
  [[nodiscard]] double time(long k) const { return k == steps ? t_end : static_cast<double>(k) * dt; }
  [[nodiscard]] double step(long k) const { return time(k + 1) - time(k); }
};

Schedule make_schedule(const AttitudeRun& run) {
  // t_end/dt within rounding of an integer counts as that integer (no sliver of a step).
  const double ratio = run.t_end / run.dt;
  const auto steps = static_cast<long>(std::max(1.0, std::ceil(ratio * (1.0 - 1e-12))));
  return {steps, run.dt, run.t_end};
}

bool output_due(long k, const Schedule& s, long every) { return k % every == 0 || k == s.steps; }

/// The attitude the quaternion represents, reported in the chart the dual-Euler rule picks.
Attitude as_attitude(const Eigen::Quaterniond& q) { return Attitude::from_quaternion(q); }

struct RunSummary {
  long steps = 0;
  long switches = 0;
  double max_energy_drift = 0.0;    // relative, torque-free mode
  double max_momentum_drift = 0.0;  // relative |L_n - L_n(0)|, torque-free mode
};

RunSummary run_torque_free(const AttitudeRun& run, CsvOutput& out) {
  const attitude::BodyInertia inertia(run.inertia.asDiagonal());
  const Schedule schedule = make_schedule(run);
  Attitude start = Attitude::from_set1(run.euler[0], run.euler[1], run.euler[2]);
  attitude::apply_switching_rule(start);  // the chart of the first step, not counted as a switch
  const Eigen::Vector3d momentum0 = start.body_to_inertial() * run.inertia.cwiseProduct(*run.omega0_b);
  const double energy0 = attitude::rotational_energy(inertia, *run.omega0_b);
  RunSummary summary{schedule.steps};
  const auto track = [&](const Eigen::Matrix3d& r, const Eigen::Vector3d& omega) {
    const double energy = attitude::rotational_energy(inertia, omega);
    const Eigen::Vector3d momentum = r * run.inertia.cwiseProduct(omega);
    if (energy0 > 0.0)
      summary.max_energy_drift = std::max(summary.max_energy_drift, std::abs(energy - energy0) / energy0);
    if (momentum0.norm() > 0.0) {
      summary.max_momentum_drift =
          std::max(summary.max_momentum_drift, (momentum - momentum0).norm() / momentum0.norm());
    }
  };

  if (run.method == Method::dual_euler) {
    attitude::SpinState state{*run.omega0_b, start};
    for (long k = 0;; ++k) {
      require_finite_state(schedule.time(k), k, state.omega_b, state.attitude.angles().allFinite());
      track(state.attitude.body_to_inertial(), state.omega_b);
      if (output_due(k, schedule, run.output_every)) {
        out.row(schedule.time(k), state.omega_b, state.attitude, state.attitude.set(), run.inertia);
      }
      if (k == schedule.steps) break;
      if (attitude::dual_euler_spin_step(state, inertia, schedule.time(k), schedule.step(k))) ++summary.switches;
    }
  } else {
    attitude::QuaternionSpinState state{*run.omega0_b, start.quaternion()};
    attitude::EulerSet previous = start.set();
    for (long k = 0;; ++k) {
      require_finite_state(schedule.time(k), k, state.omega_b, state.orientation.coeffs().allFinite());
      const Attitude current = as_attitude(state.orientation);
      track(current.body_to_inertial(), state.omega_b);
      if (current.preferred_set() != previous) ++summary.switches;  // what the rule would do
      previous = current.preferred_set();
      if (output_due(k, schedule, run.output_every)) {
        out.row(schedule.time(k), state.omega_b, current, current.preferred_set(), run.inertia);
      }
      if (k == schedule.steps) break;
      attitude::quaternion_spin_step(state, inertia, schedule.time(k), schedule.step(k));
    }
  }
  return summary;
}

RunSummary run_kinematics(const AttitudeRun& run, CsvOutput& out) {
  const attitude::BodyRateSeries& series = *run.series;
  // RK4's last stage time t + dt can exceed t_end (= possibly the series' end) by one
  // rounding; clamping reads the last sample there instead of failing.
  const attitude::BodyRateFunction omega_b = [&series](double t) {
    return series.at(std::clamp(t, series.start_time(), series.end_time()));
  };
  const Schedule schedule = make_schedule(run);
  Attitude attitude = Attitude::from_set1(run.euler[0], run.euler[1], run.euler[2]);
  attitude::apply_switching_rule(attitude);
  Eigen::Quaterniond q = attitude.quaternion();
  attitude::EulerSet previous = attitude.set();
  RunSummary summary{schedule.steps};
  for (long k = 0;; ++k) {
    const double t = schedule.time(k);
    require_finite_state(t, k, omega_b(t), q.coeffs().allFinite() && attitude.angles().allFinite());
    if (run.method == Method::quaternion) {
      const attitude::EulerSet rule_set = as_attitude(q).preferred_set();
      if (rule_set != previous) ++summary.switches;  // what the rule would do
      previous = rule_set;
    }
    if (output_due(k, schedule, run.output_every)) {
      if (run.method == Method::dual_euler) {
        out.row(t, omega_b(t), attitude, attitude.set(), run.inertia);
      } else {
        const Attitude current = as_attitude(q);
        out.row(t, omega_b(t), current, current.preferred_set(), run.inertia);
      }
    }
    if (k == schedule.steps) break;
    if (run.method == Method::dual_euler) {
      if (attitude::dual_euler_step(attitude, t, schedule.step(k), omega_b)) ++summary.switches;
    } else {
      q = attitude::quaternion_step(q, t, schedule.step(k), omega_b);
    }
  }
  return summary;
}

void run_attitude(const AttitudeOptions& options) {
  const AttitudeRun run = check(options);
  CsvOutput out(run.output);
  const RunSummary summary = run.omega0_b ? run_torque_free(run, out) : run_kinematics(run, out);
  out.finish();
  const bool dual = run.method == Method::dual_euler;
  const std::string switches = dual ? fmt::format("{} set switches", summary.switches)
                                    : fmt::format("{} set changes of the dual-Euler rule", summary.switches);
  if (run.omega0_b) {
    fmt::print(stderr,
               "settle attitude: {} torque-free, {} steps to t = {}, {}, max relative drift: "
               "energy {:.3g}, angular momentum (inertial) {:.3g}\n",
               dual ? "dual-euler" : "quaternion", summary.steps, run.t_end, switches, summary.max_energy_drift,
               summary.max_momentum_drift);
  } else {
    fmt::print(stderr, "settle attitude: {} kinematics from '{}', {} steps to t = {}, {}\n",
               dual ? "dual-euler" : "quaternion", options.omega_file, summary.steps, run.t_end, switches);
  }
}

constexpr const char* attitude_footer = R"(
Modes:
  --omega wx,wy,wz     torque-free motion: Euler's equations I dw/dt = -w x (I w) with the
                       principal moments --inertia, integrated together with the attitude.
  --omega-file F.csv   kinematics only: the attitude from a body-rate series (header
                       t,wx,wy,wz; linear interpolation; times strictly increasing and
                       covering [0, --t-end]). --inertia is still used for energy and
                       angular_momentum.

Methods:
  dual-euler   the dual-Euler whole-attitude solver (Cheng et al. 2023, Phys. Fluids 35,
               doi:10.1063/5.0165555): RK4 on Euler angles of set 1 (psi->theta->gamma)
               while |theta| <= pi/4 or > 3pi/4, otherwise of set 2 (psi_r->gamma_r->
               theta_r), switching through the attitude matrix at step starts.
  quaternion   RK4 on the unit quaternion, normalised every step (the reference).

Output CSV (SI units, angles in rad, full double precision), one row at t = 0, every
--output-every steps and at t = --t-end; the last step is shortened to end at t_end:
  t, wx, wy, wz            body angular velocity
  psi, theta, gamma        set-1 angles of the current attitude
  psi_r, theta_r, gamma_r  set-2 angles of the current attitude
  euler_set                dual-euler: the set the solver is advancing (the first step's set
                           at t = 0); quaternion: the set the dual-Euler rule would pick
  R11 .. R33               body-to-inertial matrix, row-major (v_inertial = R v_body)
  energy                   0.5 w . (I w)
  angular_momentum         |I w|
A summary (steps, set switches, invariant drift) goes to stderr.)";

}  // namespace

void add_attitude_command(CLI::App& app) {
  auto options = std::make_shared<AttitudeOptions>();
  CLI::App* sub = app.add_subcommand(
      "attitude",
      "Rigid-body attitude: torque-free motion from initial body rates, or kinematics from a body-rate series");
  sub->add_option("--inertia", options->inertia,
                  "Principal moments of inertia (kg m^2), each > 0 and <= sum of the others (required)")
      ->type_name("I1,I2,I3");
  sub->add_option("--omega", options->omega, "Initial body angular velocity (rad/s): torque-free motion")
      ->type_name("WX,WY,WZ");
  sub->add_option("--omega-file", options->omega_file, "CSV body-rate series t,wx,wy,wz: kinematics")
      ->type_name("F.csv");
  sub->add_option("--euler", options->euler,
                  "Initial set-1 angles psi,theta,gamma (rad), body to inertial (default 0,0,0)")
      ->type_name("PSI,THETA,GAMMA");
  sub->add_option("--dt", options->dt, "Time step (s), > 0 (required)")->type_name("DT");
  sub->add_option("--t-end", options->t_end, "End time (s), > 0 (required)")->type_name("T");
  sub->add_option("--method", options->method, "dual-euler (default) or quaternion")->type_name("METHOD");
  sub->add_option("-o,--output", options->output, "Output CSV file (default: stdout)")->type_name("F.csv");
  sub->add_option("--output-every", options->output_every, "Write every N-th step (default 1)")->type_name("N");
  sub->footer(attitude_footer);
  sub->callback([options] { run_attitude(*options); });
}

}  // namespace settle::app
