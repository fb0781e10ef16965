#include <gtest/gtest.h>

#include <cmath>
#include <numbers>
#include <stdexcept>
#include <vector>

#include "study/coefficient_fit.hpp"

namespace test_coefficient_fit {

using namespace settle::study;

const std::vector<double> kIncidences{0, 15, 30, 45, 60, 75, 90};

double sin_deg(double p) { return std::sin(p * std::numbers::pi / 180.0); }
double cos_deg(double p) { return std::cos(p * std::numbers::pi / 180.0); }

// Data made exactly from the form: the fit must find its coefficients. The pattern search halves
// its step 60 times from 0.1 in log(exponent), far below the 1e-6 asked; the residual is round-off.
TEST(CoefficientFit, DragFormIsRecoveredFromItsOwnValues) {
  std::vector<double> c;
  for (double p : kIncidences) c.push_back(0.45 + (1.07 - 0.45) * std::pow(sin_deg(p), 1.7));
  const DragIncidenceFit fit = fit_drag_incidence(kIncidences, c);
  EXPECT_NEAR(fit.c_0, 0.45, 1e-8);
  EXPECT_NEAR(fit.c_90, 1.07, 1e-8);
  EXPECT_NEAR(fit.exponent, 1.7, 1e-6);
  EXPECT_LT(fit.max_residual, 1e-9);
}

TEST(CoefficientFit, LiftFormIsRecoveredFromItsOwnValues) {
  std::vector<double> c;
  for (double p : kIncidences) c.push_back(0.36 * std::pow(sin_deg(p), 1.2) * std::pow(cos_deg(p), 0.9));
  const SinCosFit fit = fit_sin_cos(kIncidences, c);
  EXPECT_NEAR(fit.amplitude, 0.36, 1e-6);
  EXPECT_NEAR(fit.sin_exponent, 1.2, 1e-5);
  EXPECT_NEAR(fit.cos_exponent, 0.9, 1e-5);
  EXPECT_LT(fit.max_residual, 1e-8);
}

TEST(CoefficientFit, ReportsTheResidualOfDataOffTheForm) {
  std::vector<double> c;
  for (double p : kIncidences) c.push_back(1.0 + 0.5 * sin_deg(p) + (p == 45.0 ? 0.1 : 0.0));
  const DragIncidenceFit fit = fit_drag_incidence(kIncidences, c);
  // A bump of 0.1 at one point out of seven cannot be absorbed by three smooth parameters.
  EXPECT_GT(fit.max_residual, 0.03);
  EXPECT_THROW(fit_drag_incidence(std::vector<double>{0, 90}, std::vector<double>{1, 2}), std::invalid_argument);
  EXPECT_THROW(fit_sin_cos(std::vector<double>{0, 45, 120}, std::vector<double>{0, 1, 0}), std::invalid_argument);
}

}  // namespace test_coefficient_fit
