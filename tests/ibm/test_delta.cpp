// Moment conditions of the regularised delta kernels (Roma et al. 1999; Peskin 2002): these are
// the properties the kernels are built from, so they hold to round-off for every shift.
#include <gtest/gtest.h>

#include <random>

#include "common/error.hpp"
#include "ibm/delta.hpp"

namespace settle::ibm {
namespace test_delta {

constexpr DeltaKernel kKernels[] = {DeltaKernel::Roma3, DeltaKernel::Peskin4};

// The kernels are sums of a few square roots and products: 1e-14 allows a few ulps of round-off
// in sums of at most 4 terms of order 1.
constexpr double kRoundoff = 1e-14;

std::vector<double> shifts() {
  std::vector<double> r{0.0, 0.5, -0.5, 1.0, 1.5, -1.5, 2.0, 1e-12, 0.25, 0.999999999};
  std::mt19937_64 rng(7);
  std::uniform_real_distribution<double> u(-20.0, 20.0);
  for (int i = 0; i < 200; ++i) r.push_back(u(rng));
  return r;
}

TEST(DeltaKernel, ZerothAndFirstMomentsHoldForEveryShift) {
  for (DeltaKernel kernel : kKernels)
    for (double x : shifts()) {
      const AxisStencil s = axis_stencil(kernel, x);
      double m0 = 0.0, m1 = 0.0;
      for (int j = 0; j < s.width; ++j) {
        m0 += s.weight[j];
        m1 += (x - (s.first + j)) * s.weight[j];
      }
      EXPECT_NEAR(m0, 1.0, kRoundoff) << to_string(kernel) << " x=" << x;
      EXPECT_NEAR(m1, 0.0, 20 * kRoundoff) << to_string(kernel) << " x=" << x;  // |x| up to 20
    }
}

TEST(DeltaKernel, SumOfSquaresMatchesTheKernelDesign) {
  // Peskin 2002: the 4-point kernel has sum phi^2 = 3/8 for every shift. Roma's 3-point kernel
  // has sum phi^2 = 1/2 for every shift (its defining condition, Roma et al. 1999).
  for (double x : shifts()) {
    const AxisStencil p = axis_stencil(DeltaKernel::Peskin4, x);
    const AxisStencil r = axis_stencil(DeltaKernel::Roma3, x);
    double sp = 0.0, sr = 0.0;
    for (int j = 0; j < p.width; ++j) sp += p.weight[j] * p.weight[j];
    for (int j = 0; j < r.width; ++j) sr += r.weight[j] * r.weight[j];
    EXPECT_NEAR(sp, 3.0 / 8.0, kRoundoff) << x;
    EXPECT_NEAR(sr, 1.0 / 2.0, kRoundoff) << x;
  }
}

TEST(DeltaKernel, StencilCoversTheWholeSupport) {
  // Every integer strictly inside the support must be in the stencil, else weight is lost.
  for (DeltaKernel kernel : kKernels)
    for (double x : shifts()) {
      const AxisStencil s = axis_stencil(kernel, x);
      const double h = support_half_width(kernel);
      EXPECT_LE(static_cast<double>(s.first), x - h + 1.0);
      EXPECT_GE(static_cast<double>(s.first + s.width - 1), x + h - 1.0 - 1e-12);
    }
}

TEST(DeltaKernel, NamesRoundTripAndBadNamesNameTheKey) {
  for (DeltaKernel kernel : kKernels) EXPECT_EQ(delta_kernel_from_string(to_string(kernel), "k"), kernel);
  try {
    delta_kernel_from_string("gauss", "[ibm] delta");
    FAIL() << "expected an InputError";
  } catch (const InputError& e) {
    EXPECT_NE(std::string(e.what()).find("[ibm] delta"), std::string::npos);
  }
}

}  // namespace test_delta
}  // namespace settle::ibm
