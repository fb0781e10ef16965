#include "study/coefficient_fit.hpp"

#include <algorithm>
#include <cmath>
#include <functional>
#include <limits>
#include <numbers>
#include <stdexcept>
#include <vector>

namespace settle::study {
namespace {

constexpr int kScanPoints = 48;     // per exponent, log-spaced over [kMinExponent, kMaxExponent]
constexpr int kPatternRounds = 60;  // step halvings of the pattern search

void check(std::span<const double> phi_deg, std::span<const double> c) {
  if (phi_deg.size() != c.size() || phi_deg.size() < 3)
    throw std::invalid_argument("coefficient fit: needs at least three (incidence, coefficient) pairs");
  for (double p : phi_deg)
    if (!(p >= 0.0 && p <= 90.0)) throw std::invalid_argument("coefficient fit: incidence outside [0, 90] degrees");
}

double sin_deg(double phi) { return std::sin(phi * std::numbers::pi / 180.0); }
double cos_deg(double phi) {
  return phi >= 90.0 ? 0.0 : std::cos(phi * std::numbers::pi / 180.0);  // exactly 0 at 90 degrees
}

// Least-squares fit of c ~ sum_k x_k basis_k for two basis functions (or one when basis2 is empty);
// returns the residual sum of squares and the coefficients.
struct Linear {
  double x1 = 0.0, x2 = 0.0, rss = std::numeric_limits<double>::infinity();
};

Linear solve(const std::vector<double>& b1, const std::vector<double>& b2, std::span<const double> c) {
  double a11 = 0, a12 = 0, a22 = 0, r1 = 0, r2 = 0;
  for (std::size_t i = 0; i < c.size(); ++i) {
    a11 += b1[i] * b1[i];
    r1 += b1[i] * c[i];
    if (!b2.empty()) a12 += b1[i] * b2[i], a22 += b2[i] * b2[i], r2 += b2[i] * c[i];
  }
  Linear out;
  if (b2.empty()) {
    if (a11 <= 0.0) return out;
    out.x1 = r1 / a11;
  } else {
    const double det = a11 * a22 - a12 * a12;
    if (!(std::abs(det) > 1e-14 * a11 * a22)) return out;
    out.x1 = (r1 * a22 - r2 * a12) / det;
    out.x2 = (a11 * r2 - a12 * r1) / det;
  }
  out.rss = 0.0;
  for (std::size_t i = 0; i < c.size(); ++i) {
    const double model = out.x1 * b1[i] + (b2.empty() ? 0.0 : out.x2 * b2[i]);
    out.rss += (c[i] - model) * (c[i] - model);
  }
  return out;
}

double scan_value(int i) {
  return kMinExponent * std::pow(kMaxExponent / kMinExponent, static_cast<double>(i) / (kScanPoints - 1));
}

// Minimises f over the exponents (1 or 2 of them) in the box: a log-spaced scan, then a pattern
// search on the logarithms from the best point.
std::vector<double> minimise(int dimensions, const std::function<double(const std::vector<double>&)>& f) {
  std::vector<double> best(dimensions, 1.0);
  double best_value = std::numeric_limits<double>::infinity();
  const int n = dimensions == 1 ? kScanPoints : kScanPoints * kScanPoints;
  for (int k = 0; k < n; ++k) {
    std::vector<double> x{scan_value(k % kScanPoints)};
    if (dimensions == 2) x.push_back(scan_value(k / kScanPoints));
    const double v = f(x);
    if (v < best_value) best_value = v, best = x;
  }
  double step = std::log(kMaxExponent / kMinExponent) / (kScanPoints - 1);
  for (int round = 0; round < kPatternRounds; ++round) {
    bool moved = false;
    for (int d = 0; d < dimensions; ++d)
      for (double sign : {-1.0, 1.0}) {
        std::vector<double> x = best;
        x[d] = std::clamp(x[d] * std::exp(sign * step), kMinExponent, kMaxExponent);
        const double v = f(x);
        if (v < best_value) best_value = v, best = x, moved = true;
      }
    if (!moved) step *= 0.5;
  }
  return best;
}

template <class Model>
void residuals(std::span<const double> phi, std::span<const double> c, Model model, double& rms, double& max) {
  double sum = 0.0;
  max = 0.0;
  for (std::size_t i = 0; i < c.size(); ++i) {
    const double r = c[i] - model(phi[i]);
    sum += r * r;
    max = std::max(max, std::abs(r));
  }
  rms = std::sqrt(sum / static_cast<double>(c.size()));
}

}  // namespace

DragIncidenceFit fit_drag_incidence(std::span<const double> phi, std::span<const double> c) {
  check(phi, c);
  // C_D = C_D,0 (1 - sin^a) + C_D,90 sin^a: linear in the two end values for a given a.
  const auto linear = [&](double a) {
    std::vector<double> b0, b90;
    for (double p : phi) {
      const double s = std::pow(sin_deg(p), a);
      b0.push_back(1.0 - s);
      b90.push_back(s);
    }
    return solve(b0, b90, c);
  };
  const double a = minimise(1, [&](const std::vector<double>& x) { return linear(x[0]).rss; })[0];
  const Linear l = linear(a);
  DragIncidenceFit fit{l.x1, l.x2, a, 0.0, 0.0};
  residuals(
      phi, c, [&](double p) { return fit.c_0 + (fit.c_90 - fit.c_0) * std::pow(sin_deg(p), a); }, fit.rms_residual,
      fit.max_residual);
  return fit;
}

SinCosFit fit_sin_cos(std::span<const double> phi, std::span<const double> c) {
  check(phi, c);
  const auto basis = [](double p, double b1, double b2) { return std::pow(sin_deg(p), b1) * std::pow(cos_deg(p), b2); };
  const auto linear = [&](const std::vector<double>& x) {
    std::vector<double> b;
    for (double p : phi) b.push_back(basis(p, x[0], x[1]));
    return solve(b, {}, c);
  };
  const std::vector<double> x = minimise(2, [&](const std::vector<double>& e) { return linear(e).rss; });
  SinCosFit fit{linear(x).x1, x[0], x[1], 0.0, 0.0};
  residuals(
      phi, c, [&](double p) { return fit.amplitude * basis(p, x[0], x[1]); }, fit.rms_residual, fit.max_residual);
  return fit;
}

}  // namespace settle::study
