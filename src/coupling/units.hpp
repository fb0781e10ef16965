#pragma once
// The one converter between the SI case and the lattice (docs/architecture.md, "Units").
//
// Lattice units: dx = dt = 1, fluid reference density 1. The grid spacing comes from the
// resolution of the volume-equivalent diameter, dx_si = d_eq_si / cells_per_diameter. The time
// step is the largest one that keeps
//   - the lattice velocity of the expected speed, u = U_si dt_si / dx_si, at or below
//     max_lattice_velocity (compressibility error ~ Ma^2, Ma = u / c_s, c_s = 1/sqrt(3)), and
//   - the relaxation time tau = 1/2 + 3 nu_si dt_si / dx_si^2 at or below max_tau (the immersed
//     boundary's effective size and the TRT/BGK viscosity-dependent errors grow with tau),
// unless the case fixes tau, in which case dt follows from it and the Mach bound is checked.
// A tau below min_tau (under-resolved flow: too few cells for the Reynolds number) is refused
// with a message that names the key to change.
#include <limits>
#include <optional>
#include <string>

namespace settle::coupling {

/// The smallest relaxation time the converter accepts (exclusive): also the lower bound of the case
/// schema's numerics.max_tau and numerics.tau.
inline constexpr double kMinTau = 0.5 + 1.0e-3;

/// What the converter needs. Every quantity in SI. The members of case keys carry no defaults (the
/// case schema declares them; coupling/setup.hpp): NaN until assigned, which make_unit_converter
/// refuses.
struct UnitInputs {
  static constexpr double kUnassigned = std::numeric_limits<double>::quiet_NaN();
  double equivalent_diameter_si = 0.0;        ///< m
  double cells_per_diameter = kUnassigned;    ///< numerics.cells_per_diameter
  double fluid_density_si = kUnassigned;      ///< kg/m^3, fluid.density
  double dynamic_viscosity_si = kUnassigned;  ///< Pa s, fluid.dynamic_viscosity
  double expected_speed_si = 0.0;             ///< m/s, the largest velocity expected in the flow
  double max_lattice_velocity = kUnassigned;  ///< bound on U dt / dx, numerics.max_lattice_velocity
  double min_tau = kMinTau;
  double max_tau = kUnassigned;  ///< numerics.max_tau
  std::optional<double> tau;     ///< fixes tau instead of choosing dt
};

/// Scales between SI and lattice units. Construct with make_unit_converter().
class UnitConverter {
 public:
  UnitConverter(double dx_si, double dt_si, double fluid_density_si, double kinematic_viscosity_si);

  double dx_si() const { return dx_si_; }
  double dt_si() const { return dt_si_; }
  double fluid_density_si() const { return rho_si_; }
  double kinematic_viscosity_si() const { return nu_si_; }
  /// Lattice kinematic viscosity nu_si dt / dx^2 and tau = 1/2 + 3 nu.
  double viscosity() const;
  double tau() const;

  double length(double length_si) const { return length_si / dx_si_; }
  double length_si(double length) const { return length * dx_si_; }
  double time(double time_si) const { return time_si / dt_si_; }
  double time_si(double steps) const { return steps * dt_si_; }
  double velocity(double velocity_si) const { return velocity_si * dt_si_ / dx_si_; }
  double velocity_si(double velocity) const { return velocity * dx_si_ / dt_si_; }
  /// Force (N): lattice force = mass (density 1 per cell) times acceleration.
  double force_si(double force) const {
    return force * rho_si_ * dx_si_ * dx_si_ * dx_si_ * dx_si_ / (dt_si_ * dt_si_);
  }
  double force(double force_si) const { return force_si / force_si_per_lattice(); }
  double torque_si(double torque) const { return force_si(torque) * dx_si_; }
  /// Force density (N/m^3) to lattice force per cell.
  double force_density(double force_density_si) const {
    return force_density_si * dt_si_ * dt_si_ / (rho_si_ * dx_si_);
  }
  double force_density_si(double force_density) const { return force_density * rho_si_ * dx_si_ / (dt_si_ * dt_si_); }

 private:
  double force_si_per_lattice() const { return force_si(1.0); }
  double dx_si_, dt_si_, rho_si_, nu_si_;
};

/// Chooses dx and dt (see the file comment). Throws settle::InputError before any allocation
/// when no dt satisfies the bounds; the message names the case key to change.
UnitConverter make_unit_converter(const UnitInputs& inputs);

/// Mach number of a lattice velocity, u / c_s with c_s = 1/sqrt(3).
double mach_number(double lattice_velocity);

/// Schiller and Naumann 1933 drag coefficient of a sphere, C_D = 24/Re (1 + 0.15 Re^0.687),
/// fitted for Re < 800 (Clift, Grace and Weber 1978, Table 5.2); used here only to estimate
/// speeds for the time step, never as a result.
double schiller_naumann_drag_coefficient(double reynolds);

/// Terminal speed (m/s) of the volume-equivalent sphere of diameter d_si and density
/// particle_density_si from the force balance |rho_p - rho_f| g V = C_D(Re) rho_f U^2 pi d^2 / 8
/// with Schiller-Naumann drag (solved by bisection on U). An estimate for the time step.
double estimated_terminal_speed_si(double d_si, double particle_density_si, double fluid_density_si,
                                   double dynamic_viscosity_si, double gravity_si);

/// Mean speed (m/s) of the flow driven through a periodic box of volume box_volume_si by a force
/// density f_si past one fixed sphere of diameter d_si: the force balance f V_box = drag of the
/// isolated sphere with Schiller-Naumann drag. The neighbours' hindrance only slows the flow
/// (Sangani and Acrivos 1982), so this overestimates the speed, the safe side for the Mach bound.
double estimated_driven_speed_si(double d_si, double force_density_si, double box_volume_si, double fluid_density_si,
                                 double dynamic_viscosity_si);

/// Galileo number sqrt(|rho_p/rho_f - 1| g d^3) / nu.
double galileo_number(double d_si, double particle_density_si, double fluid_density_si, double kinematic_viscosity_si,
                      double gravity_si);

}  // namespace settle::coupling
