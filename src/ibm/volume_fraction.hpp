#pragma once
// Solid volume fraction of a grid cell from the body's signed distance at the cell's eight
// corners: Kempe and Froehlich 2012, J. Comput. Phys. 231, 3663-3684,
// doi:10.1016/j.jcp.2012.01.021, eq. (29):
//   alpha = sum_m -phi_m H(-phi_m) / sum_m |phi_m|,  phi < 0 inside the body.
// It is exact for a plane cutting the cell parallel to a face and first-order accurate otherwise;
// the fluid momentum inside the body is sum over cells of alpha * rho * u * dV, which enters the
// hydrodynamic force as its rate of change (needed for density ratios near 1).
#include <array>

namespace settle::ibm {

/// Volume fraction in [0, 1] from the signed distances at the 8 corners (any order).
inline double cell_volume_fraction(const std::array<double, 8>& corner_distance) {
  double inside = 0.0, total = 0.0;
  for (double phi : corner_distance) {
    if (phi < 0.0) inside -= phi;
    total += phi < 0.0 ? -phi : phi;
  }
  if (total == 0.0) return 0.5;  // all corners on the surface: no information, split evenly
  return inside / total;
}

}  // namespace settle::ibm
