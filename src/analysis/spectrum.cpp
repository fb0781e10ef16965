#include "analysis/spectrum.hpp"

#include <algorithm>
#include <cmath>
#include <complex>
#include <numbers>

namespace settle::analysis {
namespace {

constexpr double kPi = std::numbers::pi;
// The direct DFT costs points^2 / 2 per component: 4096 points keep it near 10^7 operations
// while resolving hundreds of periods per window.
constexpr std::size_t kMaxSpectralPoints = 4096;

std::vector<double> resample_uniform(const std::vector<double>& t, const std::vector<double>& x, std::size_t points) {
  std::vector<double> y(points);
  const double t0 = t.front(), step = (t.back() - t.front()) / static_cast<double>(points - 1);
  std::size_t k = 0;
  for (std::size_t j = 0; j < points; ++j) {
    const double tj = j + 1 == points ? t.back() : t0 + step * static_cast<double>(j);
    while (k + 2 < t.size() && t[k + 1] < tj) ++k;
    const double s = (tj - t[k]) / (t[k + 1] - t[k]);
    y[j] = x[k] + s * (x[k + 1] - x[k]);
  }
  return y;
}

// Hann-windowed components with the Hann-weighted mean removed (the windowed signal then has
// no power at zero frequency).
std::vector<std::vector<double>> windowed_components(const std::vector<double>& t,
                                                     const std::vector<std::vector<double>>& components,
                                                     std::size_t points) {
  std::vector<double> hann(points);
  double hann_sum = 0.0;
  for (std::size_t j = 0; j < points; ++j) {
    hann[j] = std::pow(std::sin(kPi * static_cast<double>(j) / static_cast<double>(points - 1)), 2);
    hann_sum += hann[j];
  }
  std::vector<std::vector<double>> windowed;
  for (const auto& x : components) {
    std::vector<double> y = resample_uniform(t, x, points);
    double mean = 0.0;
    for (std::size_t j = 0; j < points; ++j) mean += hann[j] * y[j];
    mean /= hann_sum;
    for (std::size_t j = 0; j < points; ++j) y[j] = hann[j] * (y[j] - mean);
    windowed.push_back(std::move(y));
  }
  return windowed;
}

// Summed power of the components at a frequency given in cycles per sample.
double power_at(const std::vector<std::vector<double>>& windowed, double cycles_per_sample) {
  double power = 0.0;
  for (const auto& y : windowed) {
    std::complex<double> sum = 0.0;
    for (std::size_t j = 0; j < y.size(); ++j)
      sum += y[j] * std::polar(1.0, -2.0 * kPi * cycles_per_sample * static_cast<double>(j));
    power += std::norm(sum);
  }
  return power;
}

// Power in the DFT bins k = 0 .. points/2 (one-sided), summed over the components.
std::vector<double> bin_powers(const std::vector<std::vector<double>>& windowed, std::size_t points) {
  std::vector<std::complex<double>> twiddle(points);
  for (std::size_t r = 0; r < points; ++r)
    twiddle[r] = std::polar(1.0, -2.0 * kPi * static_cast<double>(r) / static_cast<double>(points));
  std::vector<double> power(points / 2 + 1, 0.0);
  for (const auto& y : windowed)
    for (std::size_t k = 0; k < power.size(); ++k) {
      std::complex<double> sum = 0.0;
      for (std::size_t j = 0; j < points; ++j) sum += y[j] * twiddle[(k * j) % points];
      power[k] += std::norm(sum);
    }
  return power;
}

// Golden-section search for the maximum of the power between two frequencies (cycles/sample).
double refine_peak(const std::vector<std::vector<double>>& windowed, double low, double high) {
  const double ratio = (std::sqrt(5.0) - 1.0) / 2.0;
  double a = low, b = high;
  double c = b - ratio * (b - a), d = a + ratio * (b - a);
  double pc = power_at(windowed, c), pd = power_at(windowed, d);
  for (int iteration = 0; iteration < 60 && b - a > 1e-9 * (high - low); ++iteration) {
    if (pc > pd) {
      b = d, d = c, pd = pc;
      c = b - ratio * (b - a), pc = power_at(windowed, c);
    } else {
      a = c, c = d, pc = pd;
      d = a + ratio * (b - a), pd = power_at(windowed, d);
    }
  }
  return 0.5 * (a + b);
}

}  // namespace

SpectralPeak spectral_peak(const std::vector<double>& t_si, const std::vector<std::vector<double>>& components) {
  SpectralPeak peak;
  if (t_si.size() < 4 || components.empty()) return peak;
  const std::size_t points = std::min(t_si.size(), kMaxSpectralPoints);
  const auto windowed = windowed_components(t_si, components, points);
  // A constant signal leaves only the round-off of its mean: no peak to find.
  double signal = 0.0, fluctuation = 0.0;
  for (std::size_t c = 0; c < components.size(); ++c) {
    for (double x : components[c]) signal = std::max(signal, std::abs(x));
    for (double y : windowed[c]) fluctuation = std::max(fluctuation, std::abs(y));
  }
  if (!(fluctuation > 1e-12 * signal)) return peak;
  const std::vector<double> power = bin_powers(windowed, points);
  double total = 0.0;
  for (double p : power) total += p;
  if (!(total > 0.0)) return peak;
  const auto highest = std::max_element(power.begin() + 1, power.end());
  const auto k = static_cast<double>(highest - power.begin());
  const double n = static_cast<double>(points);
  const double cycles_per_sample =
      refine_peak(windowed, std::max(0.0, k - 1.0) / n, std::min(static_cast<double>(power.size() - 1), k + 1.0) / n);
  const double sample_step = (t_si.back() - t_si.front()) / (n - 1.0);
  double near_peak = 0.0;
  for (std::size_t b = 0; b < power.size(); ++b)
    if (std::abs(static_cast<double>(b) - cycles_per_sample * n) <= 2.0) near_peak += power[b];
  peak.found = true;
  peak.frequency_hz = cycles_per_sample / sample_step;
  peak.concentration = near_peak / total;
  peak.cycles = peak.frequency_hz * (t_si.back() - t_si.front());
  return peak;
}

}  // namespace settle::analysis
