#include "analysis/correlations.hpp"

#include <algorithm>
#include <cmath>
#include <limits>
#include <numbers>
#include <stdexcept>

#include <fmt/core.h>

#include "body/shape_factors.hpp"
#include "common/bisection.hpp"
#include "common/error.hpp"
#include "common/require.hpp"
#include "coupling/simulation.hpp"

namespace settle::analysis {
namespace {

constexpr double kNaN = std::numeric_limits<double>::quiet_NaN();

// A sphericity cannot exceed 1; a sphere built from a mesh or a round-off may report 1 + 1e-16,
// which would make -log(phi) negative and its fractional powers NaN.
double clamp_sphericity(double sphericity) { return std::min(sphericity, 1.0); }

}  // namespace

// ------------------------------------------------------------------ drag laws

// The unit converter needs the same law to choose dt and may not depend on analysis, so the
// formula lives there.
double schiller_naumann_drag(double reynolds) { return coupling::schiller_naumann_drag_coefficient(reynolds); }

double clift_grace_weber_drag(double re) {
  // Clift, Grace and Weber 1978, Table 5.2; w = log10 Re. Below Re = 0.01 Oseen's correction.
  const double w = std::log10(re);
  if (re < 0.01) return 24.0 / re + 3.0 / 16.0;
  if (re <= 20.0) return 24.0 / re * (1.0 + 0.1315 * std::pow(re, 0.82 - 0.05 * w));
  if (re <= 260.0) return 24.0 / re * (1.0 + 0.1935 * std::pow(re, 0.6305));
  if (re <= 1500.0) return std::pow(10.0, 1.6435 - 1.1242 * w + 0.1558 * w * w);
  if (re <= 1.2e4) return std::pow(10.0, -2.4571 + 2.5558 * w - 0.9295 * w * w + 0.1049 * w * w * w);
  if (re <= 4.4e4) return std::pow(10.0, -1.9181 + 0.6370 * w - 0.0636 * w * w);
  // 4.4e4 < Re <= 3.38e5; extrapolated above (the drag crisis is not modelled).
  return std::pow(10.0, -4.3390 + 1.5809 * w - 0.1546 * w * w);
}

double haider_levenspiel_drag(double reynolds, double sphericity) {
  const double p = clamp_sphericity(sphericity);
  const double a = std::exp(2.3288 - 6.4581 * p + 2.4486 * p * p);
  const double b = 0.0964 + 0.5565 * p;
  const double c = std::exp(4.905 - 13.8944 * p + 18.4222 * p * p - 10.2599 * p * p * p);
  const double d = std::exp(1.4681 + 12.2584 * p - 20.7322 * p * p + 15.8855 * p * p * p);
  return 24.0 / reynolds * (1.0 + a * std::pow(reynolds, b)) + c / (1.0 + d / reynolds);
}

double ganser_stokes_factor(double sphericity, double projected_to_volume_diameter) {
  return 1.0 / (projected_to_volume_diameter / 3.0 + 2.0 / (3.0 * std::sqrt(clamp_sphericity(sphericity))));
}

double ganser_newton_factor(double sphericity) {
  return std::pow(10.0, 1.8148 * std::pow(-std::log10(clamp_sphericity(sphericity)), 0.5743));
}

double ganser_drag(double reynolds, double sphericity, double projected_to_volume_diameter) {
  const double k1 = ganser_stokes_factor(sphericity, projected_to_volume_diameter);
  const double k2 = ganser_newton_factor(sphericity);
  const double generalized = reynolds * k1 * k2;  // Ganser's Re K1 K2
  return k2 *
         (24.0 / generalized * (1.0 + 0.1118 * std::pow(generalized, 0.6567)) + 0.4305 / (1.0 + 3305.0 / generalized));
}

double holzer_sommerfeld_drag(double reynolds, double sphericity, double crosswise_sphericity,
                              double lengthwise_sphericity) {
  const double phi = clamp_sphericity(sphericity);
  // Decimal logarithm: see docs/correlations.md ("Hoelzer and Sommerfeld") for why.
  const double newton = 0.42 * std::pow(10.0, 0.4 * std::pow(-std::log10(phi), 0.2));
  return 8.0 / (reynolds * std::sqrt(lengthwise_sphericity)) + 16.0 / (reynolds * std::sqrt(phi)) +
         3.0 / (std::sqrt(reynolds) * std::pow(phi, 0.75)) + newton / crosswise_sphericity;
}

BagheriBonadonnaFactors bagheri_bonadonna_factors(double flatness, double elongation, double volume_ratio,
                                                  double density_ratio) {
  BagheriBonadonnaFactors k;
  k.stokes_form_factor = flatness * std::pow(elongation, 1.3) * volume_ratio;
  k.newton_form_factor = flatness * flatness * elongation * volume_ratio;
  k.stokes_correction = 0.5 * (std::cbrt(k.stokes_form_factor) + 1.0 / std::cbrt(k.stokes_form_factor));
  // Decimal logarithms inside exp(): with the natural one, exp(2.5 ln rho') would just be
  // rho'^2.5, which nobody would write this way (docs/correlations.md).
  const double log_density_ratio = std::log10(density_ratio);
  const double alpha2 = 0.45 + 10.0 / (std::exp(2.5 * log_density_ratio) + 30.0);
  const double beta2 = 1.0 - 37.0 / (std::exp(3.0 * log_density_ratio) + 100.0);
  const double minus_log_fn = -std::log10(k.newton_form_factor);
  // F_N > 1: a negative base to a fractional power has no real value.
  k.newton_correction = minus_log_fn < 0.0 ? kNaN : std::pow(10.0, alpha2 * std::pow(minus_log_fn, beta2));
  return k;
}

double bagheri_bonadonna_drag(double reynolds, const BagheriBonadonnaFactors& k) {
  const double ks = k.stokes_correction, kn = k.newton_correction;
  const double scaled = reynolds * kn / ks;
  return 24.0 * ks / reynolds * (1.0 + 0.125 * std::pow(scaled, 2.0 / 3.0)) + 0.46 * kn / (1.0 + 5330.0 / scaled);
}

double dietrich_dimensionless_velocity(double dimensionless_diameter, double corey_shape_factor,
                                       double powers_roundness) {
  const double x = std::log10(dimensionless_diameter);
  const double csf = corey_shape_factor, flat = 1.0 - csf;
  if (1.0 - flat / 0.85 <= 0.0) return kNaN;  // Corey factor <= 0.15: log of a non-positive number
  const double r1 = -3.76715 + 1.92944 * x - 0.09815 * x * x - 0.00575 * x * x * x + 0.00056 * x * x * x * x;
  const double r2 = std::log10(1.0 - flat / 0.85) - std::pow(flat, 2.3) * std::tanh(x - 4.6) +
                    0.3 * (0.5 - csf) * flat * flat * (x - 4.6);
  const double r3 = std::pow(0.65 - csf / 2.83 * std::tanh(x - 4.6), 1.0 + (3.5 - powers_roundness) / 2.5);
  return r3 * std::pow(10.0, r1 + r2);
}

// ------------------------------------------------------------------ force balance

double archimedes_number(const SettlingConditions& c) {
  const double d = c.equivalent_diameter_si;
  return std::abs(c.particle_density_si - c.fluid_density_si) * c.gravity_si * d * d * d * c.fluid_density_si /
         (c.dynamic_viscosity_si * c.dynamic_viscosity_si);
}

namespace {

double velocity_of_reynolds(double reynolds, const SettlingConditions& c) {
  return reynolds * c.dynamic_viscosity_si / (c.fluid_density_si * c.equivalent_diameter_si);
}

// C_D(Re) Re^2 - (4/3) Ar: drag minus net weight, both divided by (pi/8) mu^2 / rho_f.
double scaled_force_excess(const std::function<double(double)>& drag_coefficient, double reynolds, double target) {
  return drag_coefficient(reynolds) * reynolds * reynolds - target;
}

}  // namespace

ForceBalanceSolution solve_force_balance(const std::function<double(double)>& drag_coefficient,
                                         const SettlingConditions& conditions) {
  const double target = 4.0 / 3.0 * archimedes_number(conditions);
  const auto excess = [&](double reynolds) { return scaled_force_excess(drag_coefficient, reynolds, target); };
  ForceBalanceSolution state;
  // Not bracketed (or NaN): no terminal state here.
  if (!(excess(kMinReynolds) < 0.0 && excess(kMaxReynolds) > 0.0)) return state;
  // Bisection at the geometric mean: the bracket spans 18 decades, so halving it in log Re
  // reaches round-off in about 60 steps; 200 is a guard against an ill-behaved law.
  const auto side = [&](double reynolds) {
    const double f = excess(reynolds);
    if (std::isnan(f)) return BisectionSide::undefined;
    return f < 0.0 ? BisectionSide::below : BisectionSide::above;
  };
  const auto converged = [](double lo, double hi) {
    return !(hi > lo * (1.0 + 4.0 * std::numeric_limits<double>::epsilon()));
  };
  const BisectionBracket root = bisect({kMinReynolds, kMaxReynolds}, side, converged, 200, geometric_midpoint);
  if (root.undefined) return state;
  state.reynolds = std::abs(excess(root.low)) <= std::abs(excess(root.high)) ? root.low : root.high;
  state.drag_coefficient = drag_coefficient(state.reynolds);
  state.terminal_velocity_si = velocity_of_reynolds(state.reynolds, conditions);
  state.solved = std::isfinite(state.drag_coefficient);
  return state;
}

double force_balance_residual(const ForceBalanceSolution& state, const SettlingConditions& c) {
  const double d = c.equivalent_diameter_si, u = state.terminal_velocity_si;
  const double weight =
      std::abs(c.particle_density_si - c.fluid_density_si) * c.gravity_si * std::numbers::pi * d * d * d / 6.0;
  const double drag = 0.5 * c.fluid_density_si * u * u * state.drag_coefficient * std::numbers::pi * d * d / 4.0;
  return (drag - weight) / weight;
}

// ------------------------------------------------------------------ descriptors

const char* orientation_name(Orientation orientation) {
  switch (orientation) {
    case Orientation::initial:
      return "initial";
    case Orientation::mean:
      return "mean";
    case Orientation::broadside:
      break;
  }
  return "broadside";
}

std::optional<Orientation> parse_orientation(const std::string& name) {
  for (Orientation o : {Orientation::broadside, Orientation::initial, Orientation::mean}) {
    if (name == orientation_name(o)) return o;
  }
  return std::nullopt;
}

namespace {

// The principal axis (body frame) along which the body is thinnest.
Eigen::Vector3d thinnest_principal_axis(const body::Shape& shape) {
  const Eigen::Matrix3d axes = shape.mass_properties(1.0).principal.axes;
  int thinnest = 0;
  for (int i = 1; i < 3; ++i) {
    if (shape.width(axes.col(i)) < shape.width(axes.col(thinnest))) thinnest = i;
  }
  return axes.col(thinnest);
}

}  // namespace

ParticleDescriptors describe_particle(const body::Shape& shape, double density_si, Orientation orientation,
                                      const Eigen::Vector3d& fall_direction_body, double powers_roundness) {
  require_positive(density_si, "particle density");
  Eigen::Vector3d fall = Eigen::Vector3d::UnitZ();
  if (orientation == Orientation::broadside) fall = thinnest_principal_axis(shape);
  if (orientation == Orientation::initial) fall = body::unit_direction(fall_direction_body, "fall direction");
  const body::ShapeFactors f = body::compute_shape_factors(shape, fall);

  ParticleDescriptors p;
  p.equivalent_diameter_si = f.equivalent_diameter;
  p.density_si = density_si;
  p.sphericity = f.sphericity;
  p.crosswise_sphericity = f.crosswise_sphericity;
  p.lengthwise_sphericity = f.lengthwise_sphericity;
  if (orientation == Orientation::mean) {
    // Cauchy: the orientation-averaged shadow of a convex body is A/4, and so is the mean of
    // A_par; then phi_perp = phi_par = (pi d_v^2/4)/(A/4) = phi. For a non-convex mesh A/4
    // overestimates the mean shadow (approximation, docs/correlations.md).
    p.crosswise_sphericity = p.sphericity;
    p.lengthwise_sphericity = p.sphericity;
  }
  const Eigen::Vector3d& lis = f.principal_extents;
  p.flatness = f.flatness;
  p.elongation = f.elongation;
  p.volume_ratio = std::pow(f.equivalent_diameter, 3) / (lis(0) * lis(1) * lis(2));
  p.corey_shape_factor = f.corey_shape_factor;
  p.powers_roundness = powers_roundness;
  p.orientation = orientation;
  p.fall_direction_body = f.flow_direction;
  p.shape_kind = shape.kind();
  return p;
}

// ------------------------------------------------------------------ predictions

namespace {

constexpr double kSphereLikeSphericity = 0.99;  // below: not a sphere for a sphere-only law

// Range bounds are inclusive and compared with a relative slack of 1e-12, so that a descriptor
// sitting exactly on a bound (a Corey factor of 0.6/3) is not flagged for its last bit.
bool at_most(double value, double bound) { return value <= bound * (1.0 + 1e-12); }
bool at_least(double value, double bound) { return value >= bound * (1.0 - 1e-12); }

struct Checks {
  std::vector<std::string> problems;
  void require(bool ok, std::string problem) {
    if (!ok) problems.push_back(std::move(problem));
  }
};

LawPrediction make_prediction(std::string law, std::string citation, std::string range, ForceBalanceSolution state,
                              std::vector<std::pair<std::string, double>> descriptors) {
  LawPrediction p;
  p.law = std::move(law);
  p.citation = std::move(citation);
  p.range = std::move(range);
  p.state = state;
  p.descriptors = std::move(descriptors);
  return p;
}

void conclude(LawPrediction& p, const Checks& checks, const std::string& unsolved_reason) {
  if (!p.state.solved) {
    p.in_range = false;
    p.reason = unsolved_reason;
    return;
  }
  p.in_range = checks.problems.empty();
  for (const std::string& problem : checks.problems) p.reason += (p.reason.empty() ? "" : "; ") + problem;
}

const char* kNoBalance = "no force balance for Re in [1e-10, 1e8]";

std::string sphere_problem(double sphericity) {
  return fmt::format("sphere law, particle sphericity {:.4g} < {}", sphericity, kSphereLikeSphericity);
}

LawPrediction schiller_naumann(const SettlingConditions& c, const ParticleDescriptors& d) {
  LawPrediction p = make_prediction("schiller_naumann", "Schiller and Naumann 1933, Z. Ver. Dtsch. Ing. 77, 318-320",
                                    "sphere (sphericity >= 0.99), Re <= 800",
                                    solve_force_balance(schiller_naumann_drag, c), {{"sphericity", d.sphericity}});
  Checks checks;
  checks.require(at_least(d.sphericity, kSphereLikeSphericity), sphere_problem(d.sphericity));
  checks.require(at_most(p.state.reynolds, 800.0), fmt::format("Re = {:.4g} > 800", p.state.reynolds));
  conclude(p, checks, kNoBalance);
  return p;
}

LawPrediction clift_grace_weber(const SettlingConditions& c, const ParticleDescriptors& d) {
  LawPrediction p =
      make_prediction("clift_grace_weber", "Clift, Grace and Weber 1978, Bubbles, Drops, and Particles, Table 5.2",
                      "sphere (sphericity >= 0.99), Re <= 3.38e5", solve_force_balance(clift_grace_weber_drag, c),
                      {{"sphericity", d.sphericity}});
  Checks checks;
  checks.require(at_least(d.sphericity, kSphereLikeSphericity), sphere_problem(d.sphericity));
  checks.require(at_most(p.state.reynolds, 3.38e5), fmt::format("Re = {:.4g} > 3.38e5", p.state.reynolds));
  conclude(p, checks, kNoBalance);
  return p;
}

LawPrediction haider_levenspiel(const SettlingConditions& c, const ParticleDescriptors& d) {
  const double phi = d.sphericity;
  LawPrediction p = make_prediction(
      "haider_levenspiel", "Haider and Levenspiel 1989, Powder Technol. 58, 63-70, doi:10.1016/0032-5910(89)80008-7",
      "Re <= 2.6e5", solve_force_balance([phi](double re) { return haider_levenspiel_drag(re, phi); }, c),
      {{"sphericity", phi}});
  Checks checks;
  checks.require(at_most(p.state.reynolds, 2.6e5), fmt::format("Re = {:.4g} > 2.6e5", p.state.reynolds));
  conclude(p, checks, kNoBalance);
  return p;
}

LawPrediction ganser(const SettlingConditions& c, const ParticleDescriptors& d) {
  const double phi = d.sphericity;
  // d_n / d_v: the shadow normal to the fall is pi d_n^2/4 = (pi d_v^2/4) / phi_perp.
  const double dn_over_dv = 1.0 / std::sqrt(d.crosswise_sphericity);
  const double k1 = ganser_stokes_factor(phi, dn_over_dv), k2 = ganser_newton_factor(phi);
  LawPrediction p = make_prediction(
      "ganser", "Ganser 1993, Powder Technol. 77, 143-152, doi:10.1016/0032-5910(93)80051-B", "Re K1 K2 <= 1e5",
      solve_force_balance([phi, dn_over_dv](double re) { return ganser_drag(re, phi, dn_over_dv); }, c),
      {{"sphericity", phi}, {"projected_to_volume_diameter", dn_over_dv}, {"K1", k1}, {"K2", k2}});
  Checks checks;
  const double generalized = p.state.reynolds * k1 * k2;
  checks.require(at_most(generalized, 1e5), fmt::format("Re K1 K2 = {:.4g} > 1e5", generalized));
  conclude(p, checks, kNoBalance);
  return p;
}

LawPrediction holzer_sommerfeld(const SettlingConditions& c, const ParticleDescriptors& d) {
  const double phi = d.sphericity, cross = d.crosswise_sphericity, length = d.lengthwise_sphericity;
  LawPrediction p =
      make_prediction("holzer_sommerfeld",
                      "Hoelzer and Sommerfeld 2008, Powder Technol. 184, 361-365, doi:10.1016/j.powtec.2007.08.021",
                      "Re <= 2e5 (subcritical)",
                      solve_force_balance([=](double re) { return holzer_sommerfeld_drag(re, phi, cross, length); }, c),
                      {{"sphericity", phi}, {"crosswise_sphericity", cross}, {"lengthwise_sphericity", length}});
  Checks checks;
  checks.require(at_most(p.state.reynolds, 2e5), fmt::format("Re = {:.4g} > 2e5", p.state.reynolds));
  conclude(p, checks, kNoBalance);
  return p;
}

LawPrediction bagheri_bonadonna(const SettlingConditions& c, const ParticleDescriptors& d) {
  const double density_ratio = c.particle_density_si / c.fluid_density_si;
  const BagheriBonadonnaFactors k = bagheri_bonadonna_factors(d.flatness, d.elongation, d.volume_ratio, density_ratio);
  ForceBalanceSolution state;
  if (std::isfinite(k.newton_correction)) {
    state = solve_force_balance([k](double re) { return bagheri_bonadonna_drag(re, k); }, c);
  }
  LawPrediction p = make_prediction(
      "bagheri_bonadonna", "Bagheri and Bonadonna 2016, Powder Technol. 301, 526-544, doi:10.1016/j.powtec.2016.06.015",
      "Re <= 3e5, F_N <= 1, rho_p/rho_f > 1", state,
      {{"flatness", d.flatness},
       {"elongation", d.elongation},
       {"volume_ratio", d.volume_ratio},
       {"density_ratio", density_ratio},
       {"F_S", k.stokes_form_factor},
       {"F_N", k.newton_form_factor},
       {"k_S", k.stokes_correction},
       {"k_N", k.newton_correction}});
  Checks checks;
  checks.require(at_most(p.state.reynolds, 3e5), fmt::format("Re = {:.4g} > 3e5", p.state.reynolds));
  checks.require(density_ratio > 1.0,
                 fmt::format("rho_p/rho_f = {:.4g}: the data were falling particles", density_ratio));
  const std::string unsolved =
      std::isfinite(k.newton_correction)
          ? std::string(kNoBalance)
          : fmt::format("F_N = {:.4g} > 1: k_N = 10^(alpha2 (-log10 F_N)^beta2) is undefined", k.newton_form_factor);
  conclude(p, checks, unsolved);
  return p;
}

LawPrediction dietrich(const SettlingConditions& c, const ParticleDescriptors& d) {
  // Explicit in Dietrich's variables; D* is the Archimedes number and W* = Re^3 / D*.
  const double dstar = archimedes_number(c);
  const double wstar = dietrich_dimensionless_velocity(dstar, d.corey_shape_factor, d.powers_roundness);
  ForceBalanceSolution state;
  if (std::isfinite(wstar) && wstar > 0.0) {
    state.solved = true;
    state.reynolds = std::cbrt(wstar * dstar);
    state.terminal_velocity_si = velocity_of_reynolds(state.reynolds, c);
    state.drag_coefficient = 4.0 / 3.0 * dstar / (state.reynolds * state.reynolds);
  }
  LawPrediction p =
      make_prediction("dietrich", "Dietrich 1982, Water Resour. Res. 18(6), 1615-1626, doi:10.1029/WR018i006p01615",
                      "0.05 <= D* <= 5e9, Corey shape factor >= 0.2", state,
                      {{"corey_shape_factor", d.corey_shape_factor},
                       {"powers_roundness", d.powers_roundness},
                       {"dimensionless_diameter", dstar},
                       {"dimensionless_velocity", wstar}});
  Checks checks;
  checks.require(at_least(dstar, 0.05) && at_most(dstar, 5e9), fmt::format("D* = {:.4g} outside [0.05, 5e9]", dstar));
  checks.require(at_least(d.corey_shape_factor, 0.2),
                 fmt::format("Corey shape factor {:.4g} < 0.2", d.corey_shape_factor));
  // Unsolved: either R2's logarithm has no value (a Corey factor at or below 0.15), or the fit
  // gives no positive finite W* at this D* (an extreme fluid: D* = inf at a viscosity of 1e-300).
  conclude(p, checks,
           d.corey_shape_factor <= 0.15
               ? fmt::format("Corey shape factor {:.4g} <= 0.15: R2 = log10(1 - (1 - CSF)/0.85) is undefined",
                             d.corey_shape_factor)
               : fmt::format("no settling velocity: W* = {:.4g} at D* = {:.4g} (the fit covers 0.05 <= D* <= 5e9)",
                             wstar, dstar));
  return p;
}

}  // namespace

const std::vector<std::string>& law_names() {
  static const std::vector<std::string> names{"schiller_naumann",  "clift_grace_weber", "haider_levenspiel", "ganser",
                                              "holzer_sommerfeld", "bagheri_bonadonna", "dietrich"};
  return names;
}

std::vector<LawPrediction> predict_terminal_velocities(const ParticleDescriptors& particle, double fluid_density_si,
                                                       double dynamic_viscosity_si, double gravity_si) {
  const auto check = [](double value, const char* what) {
    if (!(value > 0.0) || !std::isfinite(value)) {
      throw InputError(fmt::format("{}: must be finite and > 0, got {}", what, value));
    }
  };
  check(fluid_density_si, "fluid density");
  check(dynamic_viscosity_si, "dynamic viscosity");
  check(gravity_si, "gravity");
  check(particle.density_si, "particle density");
  check(particle.equivalent_diameter_si, "equivalent diameter");
  if (particle.density_si == fluid_density_si) {
    throw InputError(fmt::format(
        "particle density equals fluid density ({} kg/m^3): no net weight, no terminal velocity", fluid_density_si));
  }
  const SettlingConditions c{fluid_density_si, dynamic_viscosity_si, gravity_si, particle.density_si,
                             particle.equivalent_diameter_si};
  return {schiller_naumann(c, particle), clift_grace_weber(c, particle), haider_levenspiel(c, particle),
          ganser(c, particle),           holzer_sommerfeld(c, particle), bagheri_bonadonna(c, particle),
          dietrich(c, particle)};
}

ParticleDescriptors describe_setup(const coupling::SimulationSetup& setup, Orientation orientation,
                                   double powers_roundness) {
  if (!setup.shape) throw std::invalid_argument("describe_setup: the set-up has no shape");
  const double gravity = setup.gravity_si.norm();
  if (!(gravity > 0.0)) throw InputError("fluid.gravity: must be non-zero for a terminal velocity");
  // The body frame sees gravity along C_n^b g; the sign (falling or rising) does not change a shadow.
  const Eigen::Vector3d fall_body = setup.initial.attitude.inertial_to_body() * (setup.gravity_si / gravity);
  return describe_particle(*setup.shape, setup.particle_density_si, orientation, fall_body, powers_roundness);
}

std::vector<LawPrediction> predict_terminal_velocities(const coupling::SimulationSetup& setup, Orientation orientation,
                                                       double powers_roundness) {
  return predict_terminal_velocities(describe_setup(setup, orientation, powers_roundness), setup.fluid_density_si,
                                     setup.dynamic_viscosity_si, setup.gravity_si.norm());
}

}  // namespace settle::analysis
