// The unit converter (coupling/units.hpp): round trips, the Mach and tau bounds, refusals that
// name the key, and the speed estimates against closed forms.
#include <cmath>
#include <numbers>
#include <string>

#include <gtest/gtest.h>

#include "common/error.hpp"
#include "coupling/setup.hpp"
#include "coupling/units.hpp"
#include "support/default_setup.hpp"

namespace test_units {

using namespace settle::coupling;

// The bounds on the lattice velocity and on tau are a case's defaults (the case schema's).
UnitInputs water_millimetre_sphere(double speed) {
  const SimulationSetup defaults = settle::test::default_setup();
  UnitInputs in;
  in.equivalent_diameter_si = 1.0e-3;
  in.cells_per_diameter = 16.0;
  in.fluid_density_si = 1000.0;
  in.dynamic_viscosity_si = 1.0e-3;
  in.expected_speed_si = speed;
  in.max_lattice_velocity = defaults.max_lattice_velocity;
  in.max_tau = defaults.max_tau;
  return in;
}

std::string message_of(const UnitInputs& in) {
  try {
    (void)make_unit_converter(in);
  } catch (const settle::InputError& e) {
    return e.what();
  }
  return "";
}

TEST(UnitConverter, RoundTripsAreExact) {
  const UnitConverter u = make_unit_converter(water_millimetre_sphere(0.05));
  // Each pair is a multiplication and a division by the same factors: equal to round-off
  // (a few ulp, 1e-14 relative).
  EXPECT_NEAR(u.length_si(u.length(0.0123)), 0.0123, 1e-14 * 0.0123);
  EXPECT_NEAR(u.velocity_si(u.velocity(0.037)), 0.037, 1e-14 * 0.037);
  EXPECT_NEAR(u.time_si(u.time(0.25)), 0.25, 1e-14 * 0.25);
  EXPECT_NEAR(u.force_si(u.force(2.5e-6)), 2.5e-6, 1e-14 * 2.5e-6);
  EXPECT_NEAR(u.force_density_si(u.force_density(12.0)), 12.0, 1e-14 * 12.0);
  // dx from the resolution of the equivalent diameter, exactly.
  EXPECT_DOUBLE_EQ(u.dx_si(), 1.0e-3 / 16.0);
  // tau and the lattice viscosity agree with nu = cs^2 (tau - 1/2) (same formula, round-off).
  EXPECT_NEAR(u.viscosity(), (u.tau() - 0.5) / 3.0, 1e-15);
}

TEST(UnitConverter, ForceScaleIsDensityTimesLengthToTheFourthOverTimeSquared) {
  const UnitConverter u = make_unit_converter(water_millimetre_sphere(0.05));
  // A lattice force of 1 accelerates one cell of fluid (mass rho dx^3) by dx/dt^2.
  const double expected = 1000.0 * std::pow(u.dx_si(), 3) * u.dx_si() / (u.dt_si() * u.dt_si());
  EXPECT_NEAR(u.force_si(1.0), expected, 1e-14 * expected);
  EXPECT_NEAR(u.torque_si(1.0), expected * u.dx_si(), 1e-14 * expected * u.dx_si());
}

TEST(UnitConverter, FastFlowIsLimitedByTheMachBound) {
  UnitInputs in = water_millimetre_sphere(0.05);  // Re = 50
  const UnitConverter u = make_unit_converter(in);
  // The Mach bound binds (tau is well below 2): the lattice velocity equals the bound
  // (round-off only).
  EXPECT_NEAR(u.velocity(in.expected_speed_si), in.max_lattice_velocity, 1e-15);
  EXPECT_LT(u.tau(), in.max_tau);
  EXPECT_GT(u.tau(), in.min_tau);
}

TEST(UnitConverter, SlowFlowIsLimitedByTheTauBound) {
  UnitInputs in = water_millimetre_sphere(1e-5);  // creeping flow
  const UnitConverter u = make_unit_converter(in);
  EXPECT_NEAR(u.tau(), in.max_tau, 1e-12);  // the tau bound binds exactly (round-off)
  EXPECT_LT(u.velocity(in.expected_speed_si), in.max_lattice_velocity);
}

TEST(UnitConverter, GivenTauFixesTheTimeStep) {
  UnitInputs in = water_millimetre_sphere(1e-3);
  in.tau = 0.8;
  EXPECT_NEAR(make_unit_converter(in).tau(), 0.8, 1e-12);
}

TEST(UnitConverter, UnderResolvedFlowIsRefusedNamingCellsPerDiameter) {
  UnitInputs in = water_millimetre_sphere(5.0);  // Re = 5000 at 16 cells per diameter
  const std::string message = message_of(in);
  EXPECT_NE(message.find("numerics.cells_per_diameter"), std::string::npos) << message;
}

TEST(UnitConverter, TauThatBreaksTheMachBoundIsRefusedNamingTau) {
  UnitInputs in = water_millimetre_sphere(0.5);
  in.tau = 1.5;
  const std::string message = message_of(in);
  EXPECT_NE(message.find("numerics.tau"), std::string::npos) << message;
  in.tau = 7.0;  // outside (min_tau, max_tau]
  EXPECT_NE(message_of(in).find("numerics.tau"), std::string::npos);
}

TEST(UnitConverter, BadFluidPropertiesAreRefusedNamingTheKey) {
  UnitInputs in = water_millimetre_sphere(0.01);
  in.dynamic_viscosity_si = -1.0;
  EXPECT_NE(message_of(in).find("fluid.dynamic_viscosity"), std::string::npos);
  in = water_millimetre_sphere(0.01);
  in.fluid_density_si = 0.0;
  EXPECT_NE(message_of(in).find("fluid.density"), std::string::npos);
}

// Inputs of case keys left unassigned (NaN: no default of their own) are refused, not run on.
TEST(UnitConverter, UnassignedCaseKeysAreRefused) {
  UnitInputs in;
  in.equivalent_diameter_si = 1.0e-3;
  in.expected_speed_si = 0.01;
  EXPECT_NE(message_of(in).find("numerics.cells_per_diameter"), std::string::npos);
  in = water_millimetre_sphere(0.01);
  in.max_tau = UnitInputs{}.max_tau;
  EXPECT_NE(message_of(in).find("numerics.max_tau"), std::string::npos);
}

TEST(SpeedEstimates, CreepingTerminalSpeedIsStokesWithTheFirstCorrection) {
  // d = 20 um glass bead in water: Re ~ 6.5e-3. Schiller-Naumann is Stokes drag times
  // (1 + 0.15 Re^0.687), so U = U_Stokes / (1 + 0.15 Re^0.687) with Re from U itself; taking
  // Re from U_Stokes instead errs by 0.687 c^2 ~ 2e-5 for c = 0.15 Re^0.687 ~ 5e-3: 1e-4 bounds it.
  const double d = 20e-6, rho_p = 2500.0, rho_f = 1000.0, mu = 1e-3, g = 9.81;
  const double stokes = (rho_p - rho_f) * g * d * d / (18.0 * mu);
  const double expected = stokes / (1.0 + 0.15 * std::pow(rho_f * stokes * d / mu, 0.687));
  EXPECT_NEAR(estimated_terminal_speed_si(d, rho_p, rho_f, mu, g), expected, 1e-4 * expected);
}

TEST(SpeedEstimates, TerminalSpeedBalancesWeightWithSchillerNaumannDrag) {
  const double d = 2e-3, rho_p = 1200.0, rho_f = 1000.0, mu = 1e-3, g = 9.81;
  const double u = estimated_terminal_speed_si(d, rho_p, rho_f, mu, g);
  const double re = rho_f * u * d / mu;
  const double drag = schiller_naumann_drag_coefficient(re) * 0.5 * rho_f * u * u * std::numbers::pi * d * d / 4.0;
  const double weight = (rho_p - rho_f) * g * std::numbers::pi * d * d * d / 6.0;
  EXPECT_NEAR(drag, weight, 1e-8 * weight);  // bisection to 1e-10 in U; drag ~ U^1.5..2
}

TEST(SpeedEstimates, GalileoNumberOfAKnownCase) {
  // sqrt(0.2 * 9.81 * (2e-3)^3) / 1e-6 = sqrt(1.5696e-8) / 1e-6 = 125.28...
  EXPECT_NEAR(galileo_number(2e-3, 1200.0, 1000.0, 1e-6, 9.81), std::sqrt(0.2 * 9.81 * 8e-9) / 1e-6, 1e-9);
}

}  // namespace test_units
