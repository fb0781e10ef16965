#pragma once
// Regularised delta functions of the immersed boundary, in lattice units (dx = 1).
//
// Both kernels satisfy the discrete moment conditions sum_j phi(r - j) = 1 and
// sum_j (r - j) phi(r - j) = 0 for every shift r, so interpolation reproduces linear fields exactly
// and spreading conserves force and torque to first order.
//  - Roma, Peskin and Berger 1999, J. Comput. Phys. 153, 509-534, doi:10.1006/jcph.1999.6293:
//    3-point kernel, support |r| < 1.5; the default (narrower, so the body looks sharper).
//  - Peskin 2002, Acta Numerica 11, 479-517, doi:10.1017/S0962492902000077: 4-point kernel with the
//    extra condition sum_j phi(r - j)^2 = 3/8 (translation-invariant interpolation), support |r| < 2.
#include <array>
#include <cmath>
#include <string_view>

namespace settle::ibm {

enum class DeltaKernel { Roma3, Peskin4 };

/// Name as used in case files: "roma3" | "peskin4".
std::string_view to_string(DeltaKernel kernel);
/// Parses a case-file name; throws settle::InputError naming `key` on anything else.
DeltaKernel delta_kernel_from_string(std::string_view name, std::string_view key);

/// Half-width of the kernel's support in cells (1.5 or 2).
constexpr double support_half_width(DeltaKernel kernel) { return kernel == DeltaKernel::Roma3 ? 1.5 : 2.0; }
/// Number of grid points the kernel touches along one axis (3 or 4).
constexpr int stencil_width(DeltaKernel kernel) { return kernel == DeltaKernel::Roma3 ? 3 : 4; }

/// Roma et al. 1999: the 3-point kernel phi(r), r in cells.
inline double roma3(double r) {
  const double a = std::abs(r);
  if (a <= 0.5) return (1.0 + std::sqrt(1.0 - 3.0 * a * a)) / 3.0;
  if (a <= 1.5) {
    const double b = 1.0 - a;
    return (5.0 - 3.0 * a - std::sqrt(std::max(0.0, 1.0 - 3.0 * b * b))) / 6.0;
  }
  return 0.0;
}

/// Peskin 2002, section 6: the 4-point kernel phi(r), r in cells.
inline double peskin4(double r) {
  const double a = std::abs(r);
  if (a <= 1.0) return (3.0 - 2.0 * a + std::sqrt(1.0 + 4.0 * a - 4.0 * a * a)) / 8.0;
  if (a <= 2.0) return (5.0 - 2.0 * a - std::sqrt(std::max(0.0, -7.0 + 12.0 * a - 4.0 * a * a))) / 8.0;
  return 0.0;
}

inline double delta_1d(DeltaKernel kernel, double r) { return kernel == DeltaKernel::Roma3 ? roma3(r) : peskin4(r); }

/// The grid points and weights that a point X (lattice coordinates, cell centres at integers)
/// touches along one axis: first index and `width` weights phi(X - (first + j)).
struct AxisStencil {
  int first = 0;
  int width = 0;
  std::array<double, 4> weight{};
};

AxisStencil axis_stencil(DeltaKernel kernel, double x);

/// The tensor-product stencil of a point: weight(i, j, k) = wx[i] * wy[j] * wz[k].
struct Stencil {
  std::array<AxisStencil, 3> axis;
  double weight(int i, int j, int k) const { return axis[0].weight[i] * axis[1].weight[j] * axis[2].weight[k]; }
};

Stencil stencil_at(DeltaKernel kernel, double x, double y, double z);

}  // namespace settle::ibm
