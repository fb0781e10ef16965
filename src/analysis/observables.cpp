#include "analysis/observables.hpp"

#include <algorithm>
#include <cmath>
#include <limits>
#include <numbers>
#include <optional>
#include <utility>

#include <fmt/core.h>
#include <Eigen/Eigenvalues>
#include <Eigen/QR>

#include "analysis/regime_evidence.hpp"
#include "body/cylinder.hpp"
#include "body/mass_properties.hpp"
#include "body/shape.hpp"
#include "common/error.hpp"
#include "coupling/simulation.hpp"
#include "coupling/units.hpp"

namespace settle::analysis {
namespace {

constexpr double kPi = std::numbers::pi;
constexpr double kDegreesPerRadian = 180.0 / kPi;
// Projected areas of non-convex meshes cost milliseconds each; the mean shadow of a slowly
// turning body is well estimated from this many samples spread over the window.
constexpr std::size_t kMaxProjectedAreaSamples = 64;
// Below this length the mean of the axis direction (which cancels for a tumbling body) no
// longer defines a mean axis; the principal direction of <e e^T> is used instead.
constexpr double kMeanAxisMinLength = 0.2;

double clamp_unit(double x) { return std::clamp(x, -1.0, 1.0); }

// Trapezoidal time mean (the value itself for a single sample).
template <class T>
T time_mean(const std::vector<double>& t, const std::vector<T>& values) {
  if (values.size() == 1) return values.front();
  T sum = 0.5 * (t[1] - t[0]) * (values[0] + values[1]);
  for (std::size_t i = 1; i + 1 < values.size(); ++i) sum += 0.5 * (t[i + 1] - t[i]) * (values[i] + values[i + 1]);
  return sum / (t.back() - t.front());
}

std::vector<double> subtract_mean(const std::vector<double>& t, std::vector<double> values) {
  const double mean = time_mean(t, values);
  for (double& v : values) v -= mean;
  return values;
}

// Central differences (one-sided at the ends) on a possibly non-uniform grid.
std::vector<double> derivative(const std::vector<double>& t, const std::vector<double>& x) {
  const std::size_t n = x.size();
  std::vector<double> dx(n, 0.0);
  if (n < 2) return dx;
  dx[0] = (x[1] - x[0]) / (t[1] - t[0]);
  dx[n - 1] = (x[n - 1] - x[n - 2]) / (t[n - 1] - t[n - 2]);
  for (std::size_t i = 1; i + 1 < n; ++i) dx[i] = (x[i + 1] - x[i - 1]) / (t[i + 1] - t[i - 1]);
  return dx;
}

// Adds multiples of 2 pi so that consecutive angles differ by less than pi.
std::vector<double> unwrap(std::vector<double> angle) {
  for (std::size_t i = 1; i < angle.size(); ++i) {
    const double step = angle[i] - angle[i - 1];
    angle[i] -= 2.0 * kPi * std::round(step / (2.0 * kPi));
  }
  return angle;
}

// Sums of squares of x about its mean (total) and about its least-squares line in t (residual).
struct TrendFit {
  double total = 0.0, residual = 0.0;
};

TrendFit linear_trend(const std::vector<double>& t, const std::vector<double>& x) {
  const auto n = static_cast<double>(x.size());
  double mt = 0.0, mx = 0.0;
  for (std::size_t i = 0; i < x.size(); ++i) mt += t[i] / n, mx += x[i] / n;
  double stt = 0.0, stx = 0.0, sxx = 0.0;
  for (std::size_t i = 0; i < x.size(); ++i) {
    stt += (t[i] - mt) * (t[i] - mt);
    stx += (t[i] - mt) * (x[i] - mx);
    sxx += (x[i] - mx) * (x[i] - mx);
  }
  return {sxx, stt > 0.0 ? std::max(0.0, sxx - stx * stx / stt) : sxx};
}

// Fraction of the variance of the components that a straight line in t explains.
double trend_fraction(const std::vector<double>& t, const std::vector<std::vector<double>>& components) {
  double total = 0.0, residual = 0.0;
  for (const auto& x : components) {
    const TrendFit fit = linear_trend(t, x);
    total += fit.total;
    residual += fit.residual;
  }
  return total > 0.0 ? 1.0 - residual / total : 0.0;
}

// Amplitude of the components' fluctuation over the later half of the span of t against the
// earlier half, each half about its own mean: near 1 for a sustained oscillation or noise, below
// 1 for an oscillation dying away (exp(-T / (2 tau)) for an exponential envelope of time constant
// tau over a span T). 1 when a half has fewer than 2 samples or the earlier half does not move.
double decay_ratio(const std::vector<double>& t, const std::vector<std::vector<double>>& components) {
  const double middle = 0.5 * (t.front() + t.back());
  const auto split = static_cast<std::size_t>(std::lower_bound(t.begin(), t.end(), middle) - t.begin());
  if (split < 2 || t.size() - split < 2) return 1.0;
  const auto power = [&](std::size_t begin, std::size_t end) {
    const std::vector<double> tt(t.begin() + static_cast<std::ptrdiff_t>(begin),
                                 t.begin() + static_cast<std::ptrdiff_t>(end));
    double sum = 0.0;
    for (const auto& x : components) {
      std::vector<double> squares = subtract_mean(
          tt, {x.begin() + static_cast<std::ptrdiff_t>(begin), x.begin() + static_cast<std::ptrdiff_t>(end)});
      for (double& v : squares) v *= v;
      sum += time_mean(tt, squares);
    }
    return sum;
  };
  const double earlier = power(0, split), later = power(split, t.size());
  return earlier > 0.0 ? std::sqrt(later / earlier) : 1.0;
}

Eigen::Vector3d dominant_direction(const Eigen::Matrix3d& symmetric) {
  const Eigen::SelfAdjointEigenSolver<Eigen::Matrix3d> solver(symmetric);
  return solver.eigenvectors().col(2);  // eigenvalues ascending
}

// ------------------------------------------------------------------ the averaging window
// The samples of one window, with the derived per-sample signals the observables use.
struct WindowSeries {
  std::vector<double> t;
  std::vector<Eigen::Vector3d> position, velocity, omega_b, force, torque;
  std::vector<Eigen::Matrix3d> body_to_inertial;
};

WindowSeries window_of(const SettlingSeries& s, double start_si) {
  WindowSeries w;
  for (std::size_t i = 0; i < s.size(); ++i) {
    if (s.t_si[i] < start_si) continue;
    w.t.push_back(s.t_si[i]);
    w.position.push_back(s.position_si[i]);
    w.velocity.push_back(s.velocity_si[i]);
    w.omega_b.push_back(s.angular_velocity_b_si[i]);
    w.force.push_back(s.force_si[i]);
    w.torque.push_back(s.torque_si[i]);
    w.body_to_inertial.push_back(s.body_to_inertial[i]);
  }
  return w;
}

// The unit vector down (along g).
struct VerticalFrame {
  Eigen::Vector3d down;
};

VerticalFrame vertical_frame(const Eigen::Vector3d& gravity_si) {
  const double g = gravity_si.norm();
  if (!(g > 0.0) || !std::isfinite(g))
    throw InputError("fluid.gravity: the settling analysis needs a finite, non-zero gravity vector");
  return {gravity_si / g};
}

// The least-squares slope of the velocity along g over the window, over that velocity's mean
// (1/s); 0 for a single sample or a zero mean.
double relative_trend_per_s(const WindowSeries& w, const VerticalFrame& frame, double mean_vertical_si) {
  const std::size_t n = w.t.size();
  if (n < 2 || mean_vertical_si == 0.0) return 0.0;
  double t_mean = 0.0, u_mean = 0.0;
  for (std::size_t i = 0; i < n; ++i) {
    t_mean += w.t[i];
    u_mean += w.velocity[i].dot(frame.down);
  }
  t_mean /= static_cast<double>(n);
  u_mean /= static_cast<double>(n);
  double covariance = 0.0, variance = 0.0;
  for (std::size_t i = 0; i < n; ++i) {
    covariance += (w.t[i] - t_mean) * (w.velocity[i].dot(frame.down) - u_mean);
    variance += (w.t[i] - t_mean) * (w.t[i] - t_mean);
  }
  return variance > 0.0 ? covariance / variance / mean_vertical_si : 0.0;
}

// ------------------------------------------------------------------ groups of observables
void velocity_and_path(const WindowSeries& w, const VerticalFrame& frame, Analysis& a) {
  a.mean_velocity_si = time_mean(w.t, w.velocity);
  a.terminal_speed_si = a.mean_velocity_si.norm();
  a.vertical_velocity_si = a.mean_velocity_si.dot(frame.down);
  const Eigen::Vector3d horizontal = a.mean_velocity_si - a.vertical_velocity_si * frame.down;
  a.lateral_drift_speed_si = horizontal.norm();
  a.path_angle_deg = std::atan2(a.lateral_drift_speed_si, std::abs(a.vertical_velocity_si)) * kDegreesPerRadian;
  const Eigen::Vector3d moved = w.position.back() - w.position.front();
  a.lateral_displacement_si = (moved - moved.dot(frame.down) * frame.down).norm();
  a.vertical_velocity_trend_per_s = relative_trend_per_s(w, frame, a.vertical_velocity_si);
}

// The horizontal axes azimuths are measured in: x projected on the horizontal plane (y when g is
// nearly along x), and its counter-clockwise normal seen from above.
std::pair<Eigen::Vector3d, Eigen::Vector3d> azimuth_axes(const VerticalFrame& frame) {
  Eigen::Vector3d east = Eigen::Vector3d::UnitX() - frame.down.x() * frame.down;
  if (east.norm() < 0.1) east = Eigen::Vector3d::UnitY() - frame.down.y() * frame.down;
  east.normalize();
  return {east, (-frame.down).cross(east)};
}

struct Drift {
  double azimuth_rad = 0.0;
  bool oblique = false;  // at least the regime's oblique angle from the vertical
};

Drift mean_drift(const std::vector<double>& t, const std::vector<Eigen::Vector3d>& velocity, const VerticalFrame& frame,
                 double oblique_angle_deg) {
  const Eigen::Vector3d mean = time_mean(t, velocity);
  const auto [east, north] = azimuth_axes(frame);
  const double horizontal = std::hypot(mean.dot(east), mean.dot(north));
  const double angle_deg = std::atan2(horizontal, std::abs(mean.dot(frame.down))) * kDegreesPerRadian;
  return {std::atan2(mean.dot(north), mean.dot(east)), angle_deg >= oblique_angle_deg};
}

// The azimuth of an oblique path and its turning between the first and last quarters of the
// window: an oblique path has no preferred azimuth in unbounded fluid, so its plane can drift
// slowly (docs/analysis.md).
void drift_direction(const WindowSeries& w, const VerticalFrame& frame, double oblique_angle_deg, Analysis& a) {
  const Drift whole = mean_drift(w.t, w.velocity, frame, oblique_angle_deg);
  if (!whole.oblique) return;
  a.drift_azimuth_deg = whole.azimuth_rad * kDegreesPerRadian;
  const double quarter = 0.25 * (w.t.back() - w.t.front());
  const auto first_end = std::upper_bound(w.t.begin(), w.t.end(), w.t.front() + quarter) - w.t.begin();
  const auto last_begin = std::lower_bound(w.t.begin(), w.t.end(), w.t.back() - quarter) - w.t.begin();
  if (first_end < 2 || std::ssize(w.t) - last_begin < 2) return;
  const auto part = [&](auto begin, auto end) {
    const std::vector<double> t(w.t.begin() + begin, w.t.begin() + end);
    const std::vector<Eigen::Vector3d> u(w.velocity.begin() + begin, w.velocity.begin() + end);
    return std::pair{mean_drift(t, u, frame, oblique_angle_deg), 0.5 * (t.front() + t.back())};
  };
  const auto [first, first_mid] = part(0, first_end);
  const auto [last, last_mid] = part(last_begin, std::ssize(w.t));
  if (!first.oblique || !last.oblique || !(last_mid > first_mid)) return;
  const double turn = std::remainder(last.azimuth_rad - first.azimuth_rad, 2.0 * kPi);
  a.drift_turn_rate_deg_per_s = turn * kDegreesPerRadian / (last_mid - first_mid);
}

// Mordant and Pinton 2000 (Eur. Phys. J. B 18, 343, doi:10.1007/s100510070066) characterise a
// sphere's transient by t_95, the time to 95% of the terminal velocity, from a fit
// u = U_t (1 - exp(-3 t / t_95)); here it is the first crossing of 0.95 U_t in the samples, which
// equals the fit's t_95 for an exactly exponential approach (the fit itself: below).
void time_to_95_percent(const SettlingSeries& series, const VerticalFrame& frame, Analysis& a) {
  if (!a.terminal.reached || !(a.vertical_velocity_si > 0.0)) return;
  const double target = 0.95 * a.vertical_velocity_si;
  double previous = series.velocity_si.front().dot(frame.down);
  if (previous >= target) return;
  for (std::size_t k = 1; k < series.size(); ++k) {
    const double u = series.velocity_si[k].dot(frame.down);
    if (u >= target) {
      const double fraction = (target - previous) / (u - previous);
      const double t = series.t_si[k - 1] + fraction * (series.t_si[k] - series.t_si[k - 1]);
      a.time_to_95_percent_si = t - series.t_si.front();
      return;
    }
    previous = u;
  }
}

// The least-squares U of u = U phi for a given T, phi = 1 - exp(-3 t / T), and the sum of squared
// residuals it leaves.
struct ExponentialFit {
  double speed = 0.0, squared_residual = 0.0;
};

ExponentialFit exponential_fit(const std::vector<double>& t, const std::vector<double>& u, double time_to_95) {
  const auto phi = [&](std::size_t k) { return -std::expm1(-3.0 * t[k] / time_to_95); };
  double phi_u = 0.0, phi_phi = 0.0;
  for (std::size_t k = 0; k < t.size(); ++k) {
    phi_u += phi(k) * u[k];
    phi_phi += phi(k) * phi(k);
  }
  ExponentialFit fit;
  fit.speed = phi_phi > 0.0 ? phi_u / phi_phi : 0.0;
  for (std::size_t k = 0; k < t.size(); ++k) fit.squared_residual += std::pow(u[k] - fit.speed * phi(k), 2);
  return fit;
}

// The minimum of f over [lo, hi]: a scan of a uniform grid, then golden-section search between
// the best grid point's neighbours (f need only be unimodal near its minimum).
template <class F>
double minimum_on_interval(const F& f, double lo, double hi) {
  constexpr int kGridPoints = 200;
  const double step = (hi - lo) / (kGridPoints - 1);
  int best = 0;
  double best_value = f(lo);
  for (int i = 1; i < kGridPoints; ++i) {
    if (const double value = f(lo + i * step); value < best_value) {
      best = i;
      best_value = value;
    }
  }
  double left = lo + std::max(best - 1, 0) * step, right = lo + std::min(best + 1, kGridPoints - 1) * step;
  const double shrink = 0.5 * (std::sqrt(5.0) - 1.0);
  for (int iteration = 0; iteration < 80; ++iteration) {
    const double x1 = right - shrink * (right - left), x2 = left + shrink * (right - left);
    if (f(x1) < f(x2)) {
      right = x2;
    } else {
      left = x1;
    }
  }
  return 0.5 * (left + right);
}

// Mordant and Pinton's fit (above) of the whole record: U solved in closed form for each T, T
// searched in log T from the sampling interval to the record's length.
void fitted_time_to_95_percent(const SettlingSeries& series, const VerticalFrame& frame, Analysis& a) {
  if (!a.terminal.reached || !(a.vertical_velocity_si > 0.0) || series.size() < 3) return;
  std::vector<double> t(series.size()), u(series.size());
  for (std::size_t k = 0; k < series.size(); ++k) {
    t[k] = series.t_si[k] - series.t_si.front();
    u[k] = series.velocity_si[k].dot(frame.down);
  }
  if (std::abs(u.front()) > 0.05 * a.vertical_velocity_si) return;
  const auto cost = [&](double log_t95) { return exponential_fit(t, u, std::exp(log_t95)).squared_residual; };
  const double time_to_95 = std::exp(minimum_on_interval(cost, std::log(t[1]), std::log(t.back())));
  const ExponentialFit fit = exponential_fit(t, u, time_to_95);
  a.fitted_time_to_95_percent_si = time_to_95;
  a.fitted_terminal_velocity_si = fit.speed;
  a.fit_rms_residual_si = std::sqrt(fit.squared_residual / static_cast<double>(t.size()));
}

void dimensionless_groups(const ParticleProperties& p, Analysis& a) {
  const double d = p.equivalent_diameter_si, nu = p.kinematic_viscosity_si(), g = p.gravity_si.norm();
  a.density_ratio = p.particle_density_si / p.fluid_density_si;
  a.reynolds = a.terminal_speed_si * d / nu;
  a.galileo = coupling::galileo_number(d, p.particle_density_si, p.fluid_density_si, nu, g);
  a.archimedes = a.galileo * a.galileo;
  // ten Cate et al. 2002, Phys. Fluids 14, 4012, doi:10.1063/1.1512918: St = (rho_p/rho_f) Re / 9.
  a.stokes_number = p.particle_density_si * a.terminal_speed_si * d / (9.0 * p.dynamic_viscosity_si);
  // Field et al. 1997, Nature 388, 252, doi:10.1038/40817: I* = I / (rho_f d^5) of a thin disk
  // about a diameter, I = pi rho_d h d^4 / 64 (the thickness term h^2/12 of a finite disk is
  // left out, as in their definition).
  if (p.disk_diameter_si && p.disk_thickness_si)
    a.dimensionless_inertia =
        kPi * p.particle_density_si * *p.disk_thickness_si / (64.0 * p.fluid_density_si * *p.disk_diameter_si);
}

double mean_projected_area(const WindowSeries& w, const ParticleProperties& p, const Eigen::Vector3d& motion) {
  const std::size_t n = w.t.size(), count = std::min(n, kMaxProjectedAreaSamples);
  double sum = 0.0;
  for (std::size_t k = 0; k < count; ++k) {
    const std::size_t i = count == 1 ? 0 : k * (n - 1) / (count - 1);
    sum += p.projected_area_si(w.body_to_inertial[i].transpose() * motion);
  }
  return sum / static_cast<double>(count);
}

void drag(const WindowSeries& w, const ParticleProperties& p, Analysis& a) {
  a.mean_force_si = time_mean(w.t, w.force);
  a.mean_torque_si = time_mean(w.t, w.torque);
  const double speed = a.terminal_speed_si;
  if (!(speed > 0.0)) return;
  const Eigen::Vector3d motion = a.mean_velocity_si / speed;
  const double d = p.equivalent_diameter_si;
  const double reference = 0.5 * p.fluid_density_si * speed * speed * kPi * d * d / 4.0;
  // At the terminal state the mean hydrodynamic force balances the net weight; its component
  // against the motion is the drag (the rest is lift).
  const Eigen::Vector3d net_weight = (p.particle_density_si - p.fluid_density_si) * p.volume_si * p.gravity_si;
  a.drag_coefficient = net_weight.dot(motion) / reference;
  a.drag_coefficient_from_force = -a.mean_force_si.dot(motion) / reference;
  if (!p.projected_area_si) return;
  a.projected_area_si = mean_projected_area(w, p, motion);
  if (*a.projected_area_si > 0.0)
    a.drag_coefficient_projected_area = a.drag_coefficient * (kPi * d * d / 4.0) / *a.projected_area_si;
}

// Degree of the polynomial in time an oblique drift's azimuth is followed with: enough for a plane
// turning from one azimuth to another (the S-shaped turn of Uhlmann and Dusek's case C towards its
// window's diagonal), too low to follow an oscillation of the two or more periods a periodic regime
// needs in the window.
constexpr Eigen::Index kDriftAzimuthDegree = 3;

// Least-squares polynomial of degree kDriftAzimuthDegree in time through y, evaluated at t.
std::vector<double> polynomial_fit(const std::vector<double>& t, const std::vector<double>& y) {
  const double mid = 0.5 * (t.front() + t.back()), half = 0.5 * (t.back() - t.front());
  const auto n = static_cast<Eigen::Index>(t.size());
  Eigen::MatrixXd powers(n, kDriftAzimuthDegree + 1);
  for (Eigen::Index i = 0; i < n; ++i)
    for (Eigen::Index k = 0; k <= kDriftAzimuthDegree; ++k)
      powers(i, k) = std::pow((t[static_cast<std::size_t>(i)] - mid) / half, static_cast<double>(k));
  const Eigen::VectorXd fit =
      powers * powers.colPivHouseholderQr().solve(Eigen::Map<const Eigen::VectorXd>(y.data(), n));
  return {fit.data(), fit.data() + n};
}

// The direction of an oblique drift at each sample: the azimuth of the horizontal velocity,
// smoothed by polynomial_fit. None unless the path is oblique and its horizontal velocity stays
// within 90 degrees of that direction (never reverses): an oscillation about an oblique path that
// reverses the lateral velocity is judged in fixed axes.
std::optional<std::vector<double>> drift_azimuths(const WindowSeries& w, const VerticalFrame& frame,
                                                  double oblique_angle_deg) {
  if (w.t.size() <= static_cast<std::size_t>(kDriftAzimuthDegree) + 1 || !(w.t.back() > w.t.front()) ||
      !mean_drift(w.t, w.velocity, frame, oblique_angle_deg).oblique)
    return std::nullopt;
  const auto [east, north] = azimuth_axes(frame);
  std::vector<double> azimuth;
  for (const auto& u : w.velocity) azimuth.push_back(std::atan2(u.dot(north), u.dot(east)));
  azimuth = unwrap(std::move(azimuth));
  std::vector<double> smooth = polynomial_fit(w.t, azimuth);
  for (std::size_t i = 0; i < azimuth.size(); ++i)
    if (!(std::cos(azimuth[i] - smooth[i]) > 0.0)) return std::nullopt;
  return smooth;
}

// The horizontal velocity in axes that follow an oblique path's drift (drift_azimuths; fixed axes
// otherwise): a steady oblique path whose plane turns slowly then has no fluctuation, and its turn
// does not read as a lateral oscillation.
std::pair<std::vector<double>, std::vector<double>> horizontal_velocity_in_drift_axes(const WindowSeries& w,
                                                                                      const VerticalFrame& frame,
                                                                                      double oblique_angle_deg) {
  const auto [east, north] = azimuth_axes(frame);
  const std::vector<double> turn =
      drift_azimuths(w, frame, oblique_angle_deg).value_or(std::vector<double>(w.t.size(), 0.0));
  std::vector<double> u1, u2;
  for (std::size_t i = 0; i < w.t.size(); ++i) {
    const double e = w.velocity[i].dot(east), n = w.velocity[i].dot(north);
    u1.push_back(std::cos(turn[i]) * e + std::sin(turn[i]) * n);
    u2.push_back(-std::sin(turn[i]) * e + std::cos(turn[i]) * n);
  }
  return {u1, u2};
}

void lateral_motion(const WindowSeries& w, const VerticalFrame& frame, double oblique_angle_deg, Analysis& a) {
  auto [u1, u2] = horizontal_velocity_in_drift_axes(w, frame, oblique_angle_deg);
  u1 = subtract_mean(w.t, std::move(u1));
  u2 = subtract_mean(w.t, std::move(u2));
  std::vector<Eigen::Matrix2d> outer;
  for (std::size_t i = 0; i < u1.size(); ++i) {
    const Eigen::Vector2d du(u1[i], u2[i]);
    outer.push_back(du * du.transpose());
  }
  const Eigen::Matrix2d covariance = time_mean(w.t, outer);
  Eigen::SelfAdjointEigenSolver<Eigen::Matrix2d> solver;
  solver.computeDirect(covariance, Eigen::EigenvaluesOnly);  // the 2 x 2 closed form (src/CMakeLists.txt)
  a.lateral_amplitude_si = std::sqrt(2.0 * std::max(0.0, solver.eigenvalues()[1]));
  a.lateral_minor_amplitude_si = std::sqrt(2.0 * std::max(0.0, solver.eigenvalues()[0]));

  // Circularity: the mean rate at which the fluctuation vector sweeps area, against its size
  // and speed (Cauchy-Schwarz bounds it by 1; 0 for a planar oscillation).
  const std::vector<double> du1 = derivative(w.t, u1), du2 = derivative(w.t, u2);
  std::vector<double> cross, size, rate;
  for (std::size_t i = 0; i < u1.size(); ++i) {
    cross.push_back(u1[i] * du2[i] - u2[i] * du1[i]);
    size.push_back(u1[i] * u1[i] + u2[i] * u2[i]);
    rate.push_back(du1[i] * du1[i] + du2[i] * du2[i]);
  }
  const double scale = std::sqrt(time_mean(w.t, size) * time_mean(w.t, rate));
  a.lateral_circularity = scale > 0.0 ? std::abs(time_mean(w.t, cross)) / scale : 0.0;
  a.lateral_trend_fraction = trend_fraction(w.t, {u1, u2});
  a.lateral_decay_ratio = decay_ratio(w.t, {u1, u2});
  a.lateral_peak = spectral_peak(w.t, {u1, u2});
}

// Unit axis of the body in the inertial frame at each sample.
std::vector<Eigen::Vector3d> axis_directions(const WindowSeries& w, const Eigen::Vector3d& axis_b) {
  std::vector<Eigen::Vector3d> e;
  for (const auto& c : w.body_to_inertial) e.push_back((c * axis_b).normalized());
  return e;
}

Eigen::Vector3d mean_axis(const std::vector<double>& t, const std::vector<Eigen::Vector3d>& e) {
  const Eigen::Vector3d mean = time_mean(t, e);
  if (mean.norm() >= kMeanAxisMinLength) return mean.normalized();
  std::vector<Eigen::Matrix3d> outer;
  for (const auto& v : e) outer.push_back(v * v.transpose());
  return dominant_direction(time_mean(t, outer));
}

void tilt(const WindowSeries& w, const VerticalFrame& frame, const std::vector<Eigen::Vector3d>& e, Analysis& a) {
  std::vector<double> angle_from_vertical;
  for (const auto& v : e) angle_from_vertical.push_back(std::acos(std::abs(clamp_unit(v.dot(frame.down)))));
  a.tilt_mean_deg = time_mean(w.t, angle_from_vertical) * kDegreesPerRadian;
  const Eigen::Vector3d m = mean_axis(w.t, e);
  a.mean_axis_tilt_deg = std::acos(std::abs(clamp_unit(m.dot(frame.down)))) * kDegreesPerRadian;

  // Signed deviation from the mean axis, in the direction in which the axis swings most.
  std::vector<Eigen::Matrix3d> outer;
  std::vector<Eigen::Vector3d> deviation;
  for (const auto& v : e) {
    deviation.push_back(v - v.dot(m) * m);
    outer.push_back(deviation.back() * deviation.back().transpose());
  }
  const Eigen::Vector3d swing = dominant_direction(time_mean(w.t, outer));
  std::vector<double> alpha;
  for (std::size_t i = 0; i < e.size(); ++i) alpha.push_back(std::atan2(deviation[i].dot(swing), e[i].dot(m)));
  alpha = subtract_mean(w.t, unwrap(std::move(alpha)));
  std::vector<double> squares;
  for (double x : alpha) squares.push_back(x * x);
  a.tilt_amplitude_deg = std::sqrt(2.0 * time_mean(w.t, squares)) * kDegreesPerRadian;
  a.tilt_trend_fraction = trend_fraction(w.t, {alpha});
  a.tilt_decay_ratio = decay_ratio(w.t, {alpha});
  a.tilt_peak = spectral_peak(w.t, {alpha});
}

// The net turn of the axis about the axis it turns about on average (e x de summed), the total
// angle it sweeps, and how far that rotation axis rises above the horizontal.
void axis_rotation(const WindowSeries& w, const VerticalFrame& frame, const std::vector<Eigen::Vector3d>& e,
                   Analysis& a) {
  Eigen::Vector3d swept = Eigen::Vector3d::Zero();
  double total = 0.0;
  for (std::size_t i = 0; i + 1 < e.size(); ++i) {
    const Eigen::Vector3d c = e[i].cross(e[i + 1]);
    swept += c;
    total += std::atan2(c.norm(), e[i].dot(e[i + 1]));
  }
  if (!(swept.norm() > 0.0) || !(total > 0.0)) return;
  const Eigen::Vector3d h = swept.normalized();
  double net = 0.0;
  for (std::size_t i = 0; i + 1 < e.size(); ++i) {
    const Eigen::Vector3d p0 = e[i] - e[i].dot(h) * h, p1 = e[i + 1] - e[i + 1].dot(h) * h;
    net += std::atan2(p0.cross(p1).dot(h), p0.dot(p1));
  }
  a.axis_net_rotation = net;
  a.axis_rotation_rate_si = net / (w.t.back() - w.t.front());
  a.axis_rotation_monotonicity = std::abs(net) / total;
  a.axis_rotation_elevation_deg = std::asin(std::abs(clamp_unit(h.dot(frame.down)))) * kDegreesPerRadian;
}

void frequencies(const ParticleProperties& p, const RegimeThresholds& th, Analysis& a) {
  const double speed = a.terminal_speed_si, d = p.equivalent_diameter_si;
  // A spectral peak of a fluctuation below the steadiness thresholds is noise, not a frequency.
  const bool lateral_moves = speed > 0.0 && a.lateral_amplitude_si >= th.steady_lateral_amplitude * speed;
  if (lateral_moves && a.lateral_peak.found) {
    a.lateral_frequency_hz = a.lateral_peak.frequency_hz;
    a.lateral_strouhal = a.lateral_peak.frequency_hz * d / speed;
  }
  const bool tilt_moves = a.tilt_amplitude_deg && *a.tilt_amplitude_deg >= th.steady_tilt_amplitude_deg;
  if (tilt_moves && a.tilt_peak.found) {
    a.tilt_frequency_hz = a.tilt_peak.frequency_hz;
    if (speed > 0.0) a.tilt_strouhal = a.tilt_peak.frequency_hz * d / speed;
  }
}

bool is_periodic(Regime regime) {
  return regime == Regime::zigzag || regime == Regime::fluttering || regime == Regime::spiral ||
         regime == Regime::oblique_oscillating;
}

// A periodic regime's frequency tells whether the detection window held the two periods its
// Hann weighting needs (terminal_state.hpp).
void window_warnings(Analysis& a) {
  const double window = a.criteria.window_si();
  if (!(window > 0.0)) return;
  const auto check = [&](const std::optional<double>& f, const char* what) {
    if (!f || *f * window >= 2.0) return;
    a.warnings.push_back(fmt::format(
        "the terminal-state window ({:.4g} s = {:.3g} response times) holds only {:.2f} periods of the {} oscillation "
        "({:.4g} Hz); detection and the window mean need two: use a window of {:.3g} response times or more",
        window, a.criteria.window_response_times, *f * window, what, *f, 2.0 / (*f * a.criteria.response_time_si)));
  };
  check(a.lateral_frequency_hz, "lateral");
  check(a.tilt_frequency_hz, "tilt");
}

// The criterion is only judged on windows with enough samples: say so when the output was too
// sparse for it in a run long enough for detection.
void sampling_warning(const SettlingSeries& series, Analysis& a) {
  if (a.terminal.reached || !(a.criteria.response_time_si > 0.0)) return;
  const bool long_enough = series.t_si.back() - series.t_si.front() >= 2.0 * a.criteria.window_si();
  if (!long_enough || a.terminal.samples_per_window >= a.criteria.min_samples_per_window) return;
  a.warnings.push_back(
      fmt::format("the output has at most {} samples per terminal-state window (< {}): the criterion "
                  "could not be judged; write samples more often (run.output_interval)",
                  a.terminal.samples_per_window, a.criteria.min_samples_per_window));
}

// A body in contact with a wall over the averaging window (resting on the floor, or striking a
// wall) is not settling freely: its mean velocity is no terminal velocity, and the net weight is
// carried by the wall as well as by the drag, so the drag coefficient of the force balance would be
// wrong (a resting sphere gave C_D = 1.7e6, and a negative one). Without contact columns (a series
// written before they existed) nothing can be told.
void wall_contact(const SettlingSeries& series, Analysis& a) {
  if (series.contact_force_si.size() != series.size()) return;
  for (std::size_t i = 0; i < series.size(); ++i)
    if (series.t_si[i] >= a.window_start_si && !series.contact_force_si[i].isZero(0.0)) ++a.wall_contact_samples;
  if (a.wall_contact_samples == 0) return;
  a.drag_coefficient = a.drag_coefficient_from_force = std::numeric_limits<double>::quiet_NaN();
  a.drag_coefficient_projected_area.reset();
  a.warnings.push_back(fmt::format(
      "the particle touches a wall in {} of the {} samples averaged (t = {:.4g} .. {:.4g} s): it is not settling "
      "freely there, so its mean velocity is no terminal velocity and no drag coefficient is given; end the run "
      "before it reaches the wall, or enlarge domain.size along its path",
      a.wall_contact_samples, a.window_samples, a.window_start_si, a.window_end_si));
}

void choose_window(const SettlingSeries& series, Analysis& a) {
  const double t0 = series.t_si.front(), t1 = series.t_si.back();
  a.averaged_over_terminal_window = a.terminal.reached;
  a.window_start_si = a.terminal.reached ? a.terminal.terminal_time_si : t0 + 0.5 * (t1 - t0);
  a.window_end_si = t1;
}

// The observables of the motion's fluctuation over the samples of w, and the regime they show.
void judge_motion(const WindowSeries& w, const VerticalFrame& frame, const ParticleProperties& p,
                  const RegimeThresholds& th, Analysis& a) {
  a.regime_window_start_si = w.t.front();
  a.regime_window_samples = w.t.size();
  lateral_motion(w, frame, th.oblique_path_angle_deg, a);
  if (a.axis.kind != AxisKind::none) {
    const std::vector<Eigen::Vector3d> e = axis_directions(w, a.axis.axis_b);
    tilt(w, frame, e, a);
    axis_rotation(w, frame, e, a);
  }
  a.lateral_frequency_hz.reset();
  a.lateral_strouhal.reset();
  a.tilt_frequency_hz.reset();
  a.tilt_strouhal.reset();
  frequencies(p, th, a);
  a.evidence = regime_evidence(a);
  a.regime = classify_regime(a.evidence, th);
}

}  // namespace

TerminalCriteria terminal_criteria(const ParticleProperties& p, const AnalysisOptions& options) {
  TerminalCriteria c;
  c.response_time_si = options.response_time_si.value_or(
      estimated_response_time_si(p.equivalent_diameter_si, p.particle_density_si, p.fluid_density_si,
                                 p.dynamic_viscosity_si, p.gravity_si.norm()));
  c.window_response_times = options.window_response_times;
  c.tolerance = options.tolerance;
  c.min_samples_per_window = options.min_samples_per_window;
  return c;
}

BodyAxis body_axis(const body::MassProperties& mass) {
  const Eigen::Vector3d& m = mass.principal.moments;  // ascending
  const Eigen::Matrix3d& axes = mass.principal.axes;
  const double low_gap = m[1] - m[0], high_gap = m[2] - m[1];
  if (m[2] - m[0] <= 1e-6 * m[2]) return {AxisKind::none, Eigen::Vector3d::UnitZ()};
  if (low_gap <= 1e-2 * high_gap) return {AxisKind::symmetry, axes.col(2)};
  if (high_gap <= 1e-2 * low_gap) return {AxisKind::symmetry, axes.col(0)};
  return {AxisKind::longest, axes.col(0)};
}

ParticleProperties particle_properties(std::shared_ptr<const body::Shape> shape, double particle_density_si,
                                       double fluid_density_si, double dynamic_viscosity_si,
                                       const Eigen::Vector3d& gravity_si) {
  ParticleProperties p;
  p.fluid_density_si = fluid_density_si;
  p.dynamic_viscosity_si = dynamic_viscosity_si;
  p.gravity_si = gravity_si;
  p.particle_density_si = particle_density_si;
  p.volume_si = shape->volume();
  p.equivalent_diameter_si = shape->equivalent_diameter();
  p.axis = body_axis(shape->mass_properties(particle_density_si));
  if (const auto* cylinder = dynamic_cast<const body::Cylinder*>(shape.get());
      cylinder != nullptr && cylinder->length() < 2.0 * cylinder->radius()) {
    p.disk_diameter_si = 2.0 * cylinder->radius();
    p.disk_thickness_si = cylinder->length();
  }
  p.projected_area_si = [shape](const Eigen::Vector3d& direction_b) { return shape->projected_area(direction_b); };
  return p;
}

ParticleProperties particle_properties(const coupling::SimulationSetup& setup) {
  return particle_properties(setup.shape, setup.particle_density_si, setup.fluid_density_si, setup.dynamic_viscosity_si,
                             setup.gravity_si);
}

Analysis analyse(const SettlingSeries& series, const ParticleProperties& properties, const AnalysisOptions& options) {
  if (series.size() < 2) throw InputError("the analysis needs at least 2 samples");
  const VerticalFrame frame = vertical_frame(properties.gravity_si);
  Analysis a;
  a.criteria = terminal_criteria(properties, options);
  if (a.criteria.response_time_si > 0.0) {
    a.terminal = detect_terminal_state(series.t_si, series.velocity_si, a.criteria);
  } else {
    a.warnings.emplace_back("no net weight (particle density equals fluid density): no terminal-state detection");
  }
  choose_window(series, a);
  const WindowSeries w = window_of(series, a.window_start_si);
  a.window_samples = w.t.size();
  a.window_start_si = w.t.front();  // the first sample averaged
  a.axis = properties.axis;

  velocity_and_path(w, frame, a);
  drift_direction(w, frame, options.thresholds.oblique_path_angle_deg, a);
  time_to_95_percent(series, frame, a);
  fitted_time_to_95_percent(series, frame, a);
  dimensionless_groups(properties, a);
  drag(w, properties, a);
  a.mean_body_rotation_rate_si = time_mean(w.t, w.omega_b);
  wall_contact(series, a);
  judge_motion(w, frame, properties, options.thresholds, a);
  // An oscillation dying away is the way into a regime, not the regime (a body that turned
  // broadside before its velocity settled still swings about its final attitude): judge the part
  // of the window after it, halving the window from its start while the oscillation still decays.
  while (is_decaying(a.evidence, options.thresholds)) {
    const WindowSeries later = window_of(series, 0.5 * (a.regime_window_start_si + a.window_end_si));
    if (later.t.size() < kMinClassifiableSamples || later.t.front() <= a.regime_window_start_si) break;
    judge_motion(later, frame, properties, options.thresholds, a);
  }
  if (a.regime.regime == Regime::tumbling) {
    a.mean_axis_tilt_deg.reset();
    a.tilt_amplitude_deg.reset();
    a.tilt_frequency_hz.reset();
    a.tilt_strouhal.reset();
  }
  if (is_periodic(a.regime.regime)) window_warnings(a);
  sampling_warning(series, a);
  return a;
}

std::string velocity_statement(const Analysis& a) {
  if (a.terminal.reached)
    return fmt::format("terminal velocity along g {:.5g} m/s (|U| = {:.5g} m/s), reached at t = {:.4g} s",
                       a.vertical_velocity_si, a.terminal_speed_si, a.terminal.terminal_time_si);
  // The change across the averaging window, what the samples show (no extrapolation past them).
  const double per_si = a.window_end_si - a.window_start_si;
  const double change = a.vertical_velocity_trend_per_s * per_si;
  const std::string criterion =
      a.criteria.window_si() > 0.0
          ? fmt::format(" (terminal means a change below {:g}% per window of {:g} response times)",
                        100.0 * a.criteria.tolerance, a.criteria.window_response_times)
          : std::string();
  const std::string mean =
      fmt::format("not terminal: mean velocity along g over the second half (t = {:.4g} .. {:.4g} s) {:.5g} m/s",
                  a.window_start_si, a.window_end_si, a.vertical_velocity_si);
  if (a.window_samples < 3)
    return mean + fmt::format(" ({} samples: too few for a trend){}", a.window_samples, criterion);
  return fmt::format("{}, {} {:.3g}% over these {:.3g} s{}", mean, change >= 0.0 ? "speeding up" : "slowing down",
                     100.0 * std::abs(change), per_si, criterion);
}

}  // namespace settle::analysis
