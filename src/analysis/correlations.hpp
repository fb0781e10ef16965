#pragma once
// Empirical terminal-velocity correlations: drag laws C_D(Re, shape) for spheres and
// non-spherical particles, the force balance that turns each into a terminal velocity, and the
// shape descriptors each law needs, taken from settle's exact shape geometry.
//
// Conventions shared by every law here (and by the papers they come from):
//  - d_v is the volume-equivalent diameter (6 V / pi)^(1/3);
//  - Re = rho_f U d_v / mu;
//  - C_D = F_drag / (0.5 rho_f U^2 pi d_v^2 / 4), i.e. referred to the cross-section of the
//    volume-equivalent sphere;
//  - terminal state: |rho_p - rho_f| g pi d_v^3 / 6 = 0.5 rho_f U^2 C_D(Re) pi d_v^2 / 4, which
//    in dimensionless form is C_D(Re) Re^2 = (4/3) Ar with the Archimedes number
//    Ar = |rho_p - rho_f| g d_v^3 rho_f / mu^2 (Dietrich's D*).
// Formulas, validity ranges and the checks against worked values: docs/correlations.md.
#include <functional>
#include <optional>
#include <string>
#include <utility>
#include <vector>

#include <Eigen/Dense>

#include "body/shape.hpp"
#include "common/physical_defaults.hpp"

namespace settle::coupling {
struct SimulationSetup;
}

namespace settle::analysis {

// ------------------------------------------------------------------ drag laws

/// Schiller and Naumann (1933), Z. Ver. Dtsch. Ing. 77, 318-320, sphere:
/// C_D = 24/Re (1 + 0.15 Re^0.687).
double schiller_naumann_drag(double reynolds);

/// Clift, Grace and Weber (1978), Bubbles, Drops, and Particles (Academic Press), Table 5.2:
/// the piecewise "standard drag curve" of a smooth sphere, defined up to Re = 3.38e5 (above,
/// the last piece is extrapolated; callers flag it).
double clift_grace_weber_drag(double reynolds);

/// Haider and Levenspiel (1989), Powder Technol. 58, 63-70, doi:10.1016/0032-5910(89)80008-7,
/// general form for a particle of sphericity phi: C_D = 24/Re (1 + A Re^B) + C / (1 + D/Re)
/// with A, B, C, D polynomials (in exponents) of phi.
double haider_levenspiel_drag(double reynolds, double sphericity);

/// Ganser (1993), Powder Technol. 77, 143-152, doi:10.1016/0032-5910(93)80051-B, unbounded
/// fluid (his wall term dropped): C_D / K2 = 24/(Re K1 K2) (1 + 0.1118 (Re K1 K2)^0.6567)
/// + 0.4305 / (1 + 3305/(Re K1 K2)). d_n is the diameter of the circle of the particle's
/// projected area normal to the motion; d_n/d_v = 1 gives Ganser's isometric K1.
double ganser_drag(double reynolds, double sphericity, double projected_to_volume_diameter);
/// Ganser's Stokes shape factor K1 = (d_n/(3 d_v) + 2/(3 sqrt(phi)))^-1.
double ganser_stokes_factor(double sphericity, double projected_to_volume_diameter);
/// Ganser's Newton shape factor K2 = 10^(1.8148 (-log10 phi)^0.5743).
double ganser_newton_factor(double sphericity);

/// Hoelzer and Sommerfeld (2008), Powder Technol. 184, 361-365,
/// doi:10.1016/j.powtec.2007.08.021:
/// C_D = 8/(Re sqrt(phi_par)) + 16/(Re sqrt(phi)) + 3/(sqrt(Re) phi^(3/4))
///       + 0.42 10^(0.4 (-log10 phi)^0.2) / phi_perp,
/// with the crosswise (phi_perp) and lengthwise (phi_par) sphericities of body/shape_factors.hpp.
/// Passing phi_perp as phi_par gives the variant with the crosswise sphericity in the Stokes
/// term that MFiX and Basilisk implement (see docs/correlations.md for the log base and the
/// first term).
double holzer_sommerfeld_drag(double reynolds, double sphericity, double crosswise_sphericity,
                              double lengthwise_sphericity);

/// The shape corrections of Bagheri and Bonadonna (2016), Powder Technol. 301, 526-544,
/// doi:10.1016/j.powtec.2016.06.015.
struct BagheriBonadonnaFactors {
  double stokes_form_factor = 1.0;  ///< F_S = f e^1.3 (d_v^3 / (L I S))
  double newton_form_factor = 1.0;  ///< F_N = f^2 e (d_v^3 / (L I S))
  double stokes_correction = 1.0;   ///< k_S = (F_S^(1/3) + F_S^(-1/3)) / 2
  double newton_correction = 1.0;   ///< k_N = 10^(alpha2 (-log10 F_N)^beta2)
};
/// Shape corrections from flatness f = S/I, elongation e = I/L, the volume ratio
/// d_v^3 / (L I S) and the density ratio rho_p / rho_f. k_N is undefined (NaN) for F_N > 1
/// (blocky bodies such as cubes), where -log10 F_N < 0 has no real fractional power.
BagheriBonadonnaFactors bagheri_bonadonna_factors(double flatness, double elongation, double volume_ratio,
                                                  double density_ratio);
/// C_D = 24 k_S/Re (1 + 0.125 (Re k_N/k_S)^(2/3)) + 0.46 k_N / (1 + 5330/(Re k_N/k_S)).
double bagheri_bonadonna_drag(double reynolds, const BagheriBonadonnaFactors& factors);

/// Dietrich (1982), Water Resour. Res. 18(6), 1615-1626, doi:10.1029/WR018i006p01615:
/// dimensionless settling velocity W* = rho_f w^3 / ((rho_p - rho_f) g nu) of a natural grain
/// from D* = (rho_p - rho_f) g D^3 / (rho_f nu^2), the Corey shape factor and the Powers
/// roundness P (0..6, 6 = perfectly round): W* = R3 10^(R1 + R2). NaN for a Corey factor at or
/// below 0.15, where R2's logarithm is undefined.
double dietrich_dimensionless_velocity(double dimensionless_diameter, double corey_shape_factor,
                                       double powers_roundness);

// ------------------------------------------------------------------ force balance

/// A particle settling (or rising) in a fluid at rest. SI units.
struct SettlingConditions {
  double fluid_density_si = defaults::fluid_density_si;
  double dynamic_viscosity_si = defaults::dynamic_viscosity_si;
  double gravity_si = defaults::gravity_si;  ///< magnitude
  double particle_density_si = defaults::particle_density_si;
  double equivalent_diameter_si = 1.0e-3;  ///< d_v
};

/// Archimedes number |rho_p - rho_f| g d_v^3 rho_f / mu^2.
double archimedes_number(const SettlingConditions& conditions);

/// The terminal state of one law (the force balance solved for Re).
struct ForceBalanceSolution {
  bool solved = false;  ///< false: no force balance for Re in the bracket, or the law undefined
  double reynolds = 0.0;
  double terminal_velocity_si = 0.0;  ///< speed, m/s
  double drag_coefficient = 0.0;
};

/// The Reynolds numbers the solver searches: wider than any law's validity so that tiny and
/// large particles still get an (out-of-range, flagged) answer.
inline constexpr double kMinReynolds = 1e-10;
inline constexpr double kMaxReynolds = 1e8;

/// Solves C_D(Re) Re^2 = (4/3) Ar for Re by bisection in log Re on [kMinReynolds,
/// kMaxReynolds], until the bracket is a few ulp wide: robust for any law whose drag force
/// C_D Re^2 changes sign once across the bracket (all laws here; it need not be smooth).
ForceBalanceSolution solve_force_balance(const std::function<double(double)>& drag_coefficient,
                                         const SettlingConditions& conditions);

/// (drag - net weight) / net weight at a terminal state (0 at an exact balance).
double force_balance_residual(const ForceBalanceSolution& state, const SettlingConditions& conditions);

// ------------------------------------------------------------------ descriptors and predictions

/// Which side of the body faces the fall, for the orientation-dependent descriptors (crosswise
/// and lengthwise sphericity, Ganser's d_n).
enum class Orientation {
  broadside,  ///< fall along the principal axis of smallest extent: the largest principal
              ///< cross-section faces the flow (the steady orientation of disks, spheroids and
              ///< rods at intermediate Re)
  initial,    ///< fall along gravity seen in the body frame at the initial attitude
  mean,       ///< averaged over all orientations (tumbling): by Cauchy's formula the mean
              ///< shadow of a convex body is A/4, so phi_perp = phi_par = phi
};
/// "broadside", "initial" or "mean".
const char* orientation_name(Orientation orientation);
/// Parses orientation_name's output; std::nullopt otherwise.
std::optional<Orientation> parse_orientation(const std::string& name);

/// Everything the laws need to know about the particle. Lengths in m.
struct ParticleDescriptors {
  double equivalent_diameter_si = 0.0;
  double density_si = 0.0;
  double sphericity = 1.0;
  double crosswise_sphericity = 1.0;
  double lengthwise_sphericity = 1.0;
  double flatness = 1.0;      ///< S / I
  double elongation = 1.0;    ///< I / L
  double volume_ratio = 1.0;  ///< d_v^3 / (L I S), 1 for ellipsoids
  double corey_shape_factor = 1.0;
  double powers_roundness = 6.0;
  Orientation orientation = Orientation::broadside;
  Eigen::Vector3d fall_direction_body = Eigen::Vector3d::UnitZ();  ///< unit; meaningless for mean
  std::string shape_kind = "sphere";
};

/// Descriptors of `shape` (body/shape_factors.hpp) for the chosen orientation.
/// `fall_direction_body` (any non-zero vector, body frame) is used by Orientation::initial only.
/// The Powers roundness is not a property of the geometry: the caller supplies it (6 = smooth).
ParticleDescriptors describe_particle(const body::Shape& shape, double density_si, Orientation orientation,
                                      const Eigen::Vector3d& fall_direction_body, double powers_roundness = 6.0);

/// One law's prediction for one particle.
struct LawPrediction {
  std::string law;       ///< e.g. "haider_levenspiel"
  std::string citation;  ///< authors, year, DOI
  std::string range;     ///< validity range, as text
  ForceBalanceSolution state;
  bool in_range = false;
  std::string reason;                                       ///< why not in range (empty when in range)
  std::vector<std::pair<std::string, double>> descriptors;  ///< the law's inputs, by name
};

/// The laws in the order reported: schiller_naumann, clift_grace_weber, haider_levenspiel,
/// ganser, holzer_sommerfeld, bagheri_bonadonna, dietrich.
const std::vector<std::string>& law_names();

/// Terminal velocity, Reynolds number and drag coefficient from every law. Throws
/// settle::InputError when the densities are equal (no net weight) or a fluid property is not
/// finite and > 0.
std::vector<LawPrediction> predict_terminal_velocities(const ParticleDescriptors& particle, double fluid_density_si,
                                                       double dynamic_viscosity_si, double gravity_si);

/// Descriptors of a case's particle: its shape and density, and for Orientation::initial the
/// gravity direction seen in the body frame at the initial attitude. settle::InputError when
/// the case's gravity is zero.
ParticleDescriptors describe_setup(const coupling::SimulationSetup& setup, Orientation orientation,
                                   double powers_roundness = 6.0);

/// The same for a case's set-up (shape, densities, viscosity, |gravity|, initial attitude for
/// Orientation::initial), so a run's summary can show the predictions next to the simulation.
std::vector<LawPrediction> predict_terminal_velocities(const coupling::SimulationSetup& setup, Orientation orientation,
                                                       double powers_roundness = 6.0);

}  // namespace settle::analysis
