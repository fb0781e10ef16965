#include "analysis/terminal_state.hpp"

#include <algorithm>
#include <cmath>
#include <numbers>
#include <stdexcept>
#include <string>

#include "coupling/units.hpp"

namespace settle::analysis {
namespace {

struct WindowMean {
  Eigen::Vector3d mean = Eigen::Vector3d::Zero();
  std::size_t samples = 0;
};

// Windows with more samples than this are summed over every k-th sample (k = ceil(n / 512)):
// the cost of a check stays bounded when every time step is written, and a trapezoidal sum of a
// smooth signal over 512 points of a Hann window is accurate far beyond the tolerance.
constexpr std::size_t kMaxSummedSamples = 512;

// Hann-weighted mean over the samples with begin <= t <= end (header comment): trapezoidal
// sums of w u and of w over the same samples, so a constant has exactly its value as mean.
template <class Samples>
WindowMean hann_window_mean(const Samples& samples, double begin, double end) {
  using Sample = typename Samples::value_type;
  const auto first =
      std::lower_bound(samples.begin(), samples.end(), begin, [](const Sample& s, double t) { return s.t < t; });
  const auto last = std::upper_bound(first, samples.end(), end, [](double t, const Sample& s) { return t < s.t; });
  WindowMean result;
  result.samples = static_cast<std::size_t>(last - first);
  const std::size_t stride = std::max<std::size_t>(1, (result.samples + kMaxSummedSamples - 1) / kMaxSummedSamples);
  const double length = end - begin;
  const auto weight_at = [&](double t) { return std::pow(std::sin(std::numbers::pi * (t - begin) / length), 2); };
  Eigen::Vector3d weighted = Eigen::Vector3d::Zero();
  double weight = 0.0;
  const Sample* previous = nullptr;
  for (std::size_t i = 0; i < result.samples; i += stride) {
    const Sample& s = first[static_cast<std::ptrdiff_t>(i)];
    if (previous != nullptr) {
      const double dt = s.t - previous->t, w0 = weight_at(previous->t), w1 = weight_at(s.t);
      weighted += 0.5 * dt * (w0 * previous->u + w1 * s.u);
      weight += 0.5 * dt * (w0 + w1);
    }
    previous = &s;
  }
  if (result.samples >= 2 && weight > 0.0) result.mean = weighted / weight;
  return result;
}

}  // namespace

void TerminalCriteria::validate() const {
  const auto require = [](bool ok, const std::string& what) {
    if (!ok) throw std::invalid_argument("TerminalCriteria: " + what);
  };
  require(std::isfinite(response_time_si) && response_time_si > 0.0, "response_time_si must be finite and > 0");
  require(std::isfinite(window_response_times) && window_response_times > 0.0,
          "window_response_times must be finite and > 0");
  require(std::isfinite(tolerance) && tolerance > 0.0, "tolerance must be finite and > 0");
  require(min_samples_per_window >= 2, "min_samples_per_window must be >= 2");
}

TerminalStateDetector::TerminalStateDetector(const TerminalCriteria& criteria) : criteria_(criteria) {
  criteria_.validate();
}

void TerminalStateDetector::add(double t_si, const Eigen::Vector3d& velocity_si) {
  if (last_t_ && !(t_si > *last_t_))
    throw std::invalid_argument("TerminalStateDetector::add: t must increase, got " + std::to_string(t_si) + " after " +
                                std::to_string(*last_t_));
  last_t_ = t_si;
  if (state_.reached) return;
  if (!first_t_) first_t_ = t_si;
  samples_.push_back({t_si, velocity_si});
  // Only the two windows ending at t_si are ever needed again.
  const double two_windows = 2.0 * criteria_.window_si();
  while (samples_.size() > 1 && samples_.front().t < t_si - two_windows) samples_.pop_front();
  check(t_si);
}

void TerminalStateDetector::check(double t_si) {
  const double w = criteria_.window_si();
  // The series must cover both windows completely.
  if (t_si - *first_t_ < criteria_.earliest_detection_si()) return;
  const WindowMean previous = hann_window_mean(samples_, t_si - 2.0 * w, t_si - w);
  const WindowMean current = hann_window_mean(samples_, t_si - w, t_si);
  state_.samples_per_window = std::max(state_.samples_per_window, std::min(previous.samples, current.samples));
  if (previous.samples < criteria_.min_samples_per_window || current.samples < criteria_.min_samples_per_window) return;
  const double speed = current.mean.norm();
  if (!(speed > 0.0)) return;
  const double change = (current.mean - previous.mean).norm() / speed;
  if (!(change < criteria_.tolerance)) return;
  state_.reached = true;
  state_.detected_at_si = t_si;
  state_.terminal_time_si = t_si - w;
  state_.window_mean_velocity_si = current.mean;
  state_.relative_change = change;
  samples_.clear();
}

TerminalState detect_terminal_state(const std::vector<double>& t_si, const std::vector<Eigen::Vector3d>& velocity_si,
                                    const TerminalCriteria& criteria) {
  if (t_si.size() != velocity_si.size())
    throw std::invalid_argument("detect_terminal_state: t and velocity differ in length");
  TerminalStateDetector detector(criteria);
  for (std::size_t i = 0; i < t_si.size() && !detector.reached(); ++i) detector.add(t_si[i], velocity_si[i]);
  return detector.state();
}

double response_time_si(double particle_density_si, double fluid_density_si, double gravity_si,
                        double terminal_speed_si, double added_mass_coefficient) {
  const double net_acceleration_density = std::abs(particle_density_si - fluid_density_si) * gravity_si;
  if (!(net_acceleration_density > 0.0)) return 0.0;
  return (particle_density_si + added_mass_coefficient * fluid_density_si) * terminal_speed_si /
         net_acceleration_density;
}

double estimated_response_time_si(double equivalent_diameter_si, double particle_density_si, double fluid_density_si,
                                  double dynamic_viscosity_si, double gravity_si, double added_mass_coefficient) {
  const double speed = coupling::estimated_terminal_speed_si(equivalent_diameter_si, particle_density_si,
                                                             fluid_density_si, dynamic_viscosity_si, gravity_si);
  return response_time_si(particle_density_si, fluid_density_si, gravity_si, speed, added_mass_coefficient);
}

}  // namespace settle::analysis
