#pragma once
// Settling regimes and the rules that tell them apart.
//
// The regimes are those of the path-instability literature:
//  - Ern, Risso, Fabre and Magnaudet 2012, "Wake-induced oscillatory paths of bodies freely
//    rising or falling in fluids", Annu. Rev. Fluid Mech. 44, 97-121,
//    doi:10.1146/annurev-fluid-120710-101250 (steady vertical, steady oblique, planar zigzag,
//    fluttering, spiral, tumbling and chaotic paths of spheres, disks and cylinders);
//  - Jenny, Dusek and Bouchet 2004, "Instabilities and transition of a sphere falling or
//    ascending freely in a Newtonian fluid", J. Fluid Mech. 508, 201-239,
//    doi:10.1017/S0022112004009164 (spheres: steady vertical, steady oblique, oblique
//    oscillating, chaotic);
//  - Field, Klaus, Moore and Nori 1997, "Chaotic dynamics of falling disks", Nature 388,
//    252-254, doi:10.1038/40817 (disks: steady, periodic fluttering, chaotic, tumbling).
//
// The literature names regimes from the look of the path and orientation; it gives no
// numerical thresholds. The rules below turn that look into measurements over the averaging
// window (observables.hpp), with thresholds stated as named parameters (RegimeThresholds):
//
//  1. tumbling: the body's axis turns continually about a near-horizontal axis: its net
//     rotation is at least half a turn (the axis line back on itself), it turns one way most of
//     the time, and the rotation axis is within 30 degrees of horizontal.
//  2. steady: lateral velocity fluctuation amplitude below 1% of the mean speed and tilt
//     oscillation amplitude below 1 degree; then steady_oblique when the mean path is more than
//     1 degree from vertical (the steady oblique sphere of Uhlmann and Dusek 2014, Int. J.
//     Multiphase Flow 59, 221-243, doi:10.1016/j.ijmultiphaseflow.2013.10.010, falls 5.2-5.3
//     degrees from vertical), otherwise steady_vertical.
//  3. still drifting: when 90% or more of the variance of the unsteady signal (the lateral
//     velocity, or the tilt when only the tilt is unsteady) is a linear trend over the window,
//     the body is still on its way to a regime (e.g. turning slowly broadside): not classified.
//  3b. dying away: when the amplitude of that signal over the later half of the window is less
//     than half of that over the earlier half, the oscillation is the body's way into its regime
//     (a sustained oscillation or noise keeps a ratio near 1; an exponential envelope of time
//     constant tau over a window T gives exp(-T / (2 tau))). analyse() then judges the later
//     half alone, again while the oscillation still decays there; when too few samples are left,
//     not classified.
//  4. periodic: at least half of the fluctuation power of that signal lies within two spectral
//     bins of its peak, and the window holds at least two periods of it. A concentrated peak
//     with fewer periods in the window is not classified (too short to tell); a broadband
//     fluctuation is chaotic.
//  5. spiral: periodic, and the lateral velocity fluctuation turns round the vertical (its
//     circularity, 2 a2 a1 / (a1^2 + a2^2) for an ellipse of semi-axes a1 >= a2 traversed one
//     way, is at least 0.8, i.e. a2 / a1 >= 1/2); otherwise the oscillation is planar:
//  6. oblique_oscillating: planar, the mean path more than 1 degree from vertical and the
//     lateral oscillation smaller than the mean lateral drift (the lateral velocity never
//     reverses: the oscillating oblique path of Jenny et al. 2004);
//  7. fluttering: planar with a tilt oscillation of 20 degrees or more (the large swings of
//     Field et al. 1997's disks); zigzag below that (and for bodies without an axis, spheres).
#include <string>
#include <string_view>

namespace settle::analysis {

enum class Regime {
  not_classified,
  steady_vertical,
  steady_oblique,
  oblique_oscillating,
  zigzag,
  fluttering,
  tumbling,
  spiral,
  chaotic,
};

/// "steady_vertical", "zigzag", ... (the values of summary.json's regime).
std::string_view regime_name(Regime regime);

/// The thresholds of the rules (file comment), with their defaults.
struct RegimeThresholds {
  double steady_lateral_amplitude = 0.01;  ///< lateral amplitude / mean speed
  double steady_tilt_amplitude_deg = 1.0;
  double oblique_path_angle_deg = 1.0;        ///< mean path from vertical
  double drift_min_trend_fraction = 0.9;      ///< variance fraction of a linear trend
  double decaying_max_amplitude_ratio = 0.5;  ///< later half's amplitude / earlier half's
  double periodic_min_concentration = 0.5;    ///< spectral power fraction near the peak
  double periodic_min_cycles = 2.0;           ///< periods in the averaging window
  double spiral_min_circularity = 0.8;        ///< 2 a1 a2 / (a1^2 + a2^2)
  double flutter_min_tilt_amplitude_deg = 20.0;
  double tumbling_min_net_rotation = 3.141592653589793;  ///< rad, half a turn
  double tumbling_min_monotonicity = 0.8;                ///< |net rotation| / total rotation
  double tumbling_max_axis_elevation_deg = 30.0;         ///< rotation axis from horizontal
};

/// What the rules look at, measured over the averaging window (observables.cpp).
struct RegimeEvidence {
  bool classifiable = false;
  std::string not_classifiable_reason;

  double path_angle_deg = 0.0;           ///< mean velocity from the vertical
  double lateral_drift_ratio = 0.0;      ///< |mean horizontal velocity| / |mean velocity|
  double lateral_amplitude_ratio = 0.0;  ///< a1 / |mean velocity|
  double lateral_circularity = 0.0;
  double lateral_concentration = 0.0;
  double lateral_cycles = 0.0;
  double lateral_trend_fraction = 0.0;  ///< variance fraction explained by a linear trend
  double lateral_decay_ratio = 1.0;     ///< amplitude over the later half / the earlier half

  bool has_axis = false;  ///< false for bodies without a symmetry or longest axis (spheres)
  double tilt_amplitude_deg = 0.0;
  double tilt_concentration = 0.0;
  double tilt_cycles = 0.0;
  double tilt_trend_fraction = 0.0;
  double tilt_decay_ratio = 1.0;
  double axis_net_rotation = 0.0;             ///< rad, signed
  double axis_rotation_monotonicity = 0.0;    ///< |net| / total rotation of the axis
  double axis_rotation_elevation_deg = 90.0;  ///< of the mean rotation axis above horizontal
};

struct RegimeResult {
  Regime regime = Regime::not_classified;
  std::string reason;  ///< the rule that decided, with the numbers
};

/// Rule 3b of the file comment: the window is classifiable, not steady, not tumbling, not
/// drifting, and its unsteady signal dies away over it.
bool is_decaying(const RegimeEvidence& evidence, const RegimeThresholds& thresholds = {});

RegimeResult classify_regime(const RegimeEvidence& evidence, const RegimeThresholds& thresholds = {});

}  // namespace settle::analysis
