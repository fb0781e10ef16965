#pragma once
// Fits of a coefficient map against the incidence angle phi to the functional forms of the
// published correlations for non-spherical particles (Zastawny, Mallouppas, Zhao and van Wachem
// 2012, Int. J. Multiphase Flow 39, 227, doi:10.1016/j.ijmultiphaseflow.2011.09.004; Sanjeevi,
// Kuipers and Padding 2018, Int. J. Multiphase Flow 106, 325,
// doi:10.1016/j.ijmultiphaseflow.2018.05.011) at one Reynolds number:
//   drag               C_D(phi) = C_D,0 + (C_D,90 - C_D,0) sin^a(phi)
//   lift and torque    C(phi)   = A sin^b1(phi) cos^b2(phi)
// Least squares: the linear coefficients in closed form for given exponents, the exponents by a
// grid scan refined by a pattern search (the residual has one minimum in practice, but the scan
// keeps a poor start from finding a side one).
#include <span>

namespace settle::study {

struct DragIncidenceFit {
  double c_0 = 0.0;       ///< C_D at phi = 0
  double c_90 = 0.0;      ///< C_D at phi = 90 degrees
  double exponent = 0.0;  ///< a
  double rms_residual = 0.0;
  double max_residual = 0.0;
};

struct SinCosFit {
  double amplitude = 0.0;     ///< A
  double sin_exponent = 0.0;  ///< b1
  double cos_exponent = 0.0;  ///< b2
  double rms_residual = 0.0;
  double max_residual = 0.0;
};

/// Exponents are sought in [kMinExponent, kMaxExponent].
inline constexpr double kMinExponent = 0.1;
inline constexpr double kMaxExponent = 8.0;

/// Needs at least three incidences in [0, 90] degrees with two distinct; std::invalid_argument otherwise.
DragIncidenceFit fit_drag_incidence(std::span<const double> incidence_deg, std::span<const double> coefficient);
SinCosFit fit_sin_cos(std::span<const double> incidence_deg, std::span<const double> coefficient);

}  // namespace settle::study
