#pragma once
// Numerical health of a running simulation, checked at every output time: a diverging run stops
// with a message naming what went wrong and the setting to change, instead of writing NaN for
// hours.
#include <string>

#include "coupling/simulation.hpp"

namespace settle::coupling {

/// Bounds beyond which the lattice Boltzmann solution is no longer trustworthy.
struct HealthLimits {
  /// Largest lattice speed |u| dt/dx anywhere: 0.25 is Mach 0.43, where the compressibility error
  /// of the weakly compressible lattice Boltzmann equation is O(Ma^2) ~ 20% (Krueger et al. 2017,
  /// The Lattice Boltzmann Method, section 4.5), and BGK/TRT lose stability soon after.
  double max_lattice_speed = 0.25;
  /// Density deviation |rho - 1| anywhere (lattice units): pressure waves of 10% of the reference
  /// density mean the incompressible limit the model stands for is gone.
  double max_density_deviation = 0.1;
};

struct HealthReport {
  bool finite = true;  ///< every density, velocity and the body state are finite
  double max_lattice_speed = 0.0;
  double min_density = 1.0, max_density = 1.0;
  /// Empty when healthy; else what went wrong, the likely cause and the setting to change.
  std::string problem;
};

/// One sweep over the grid (for output times, not every step).
HealthReport check_health(const Simulation& simulation, const HealthLimits& limits = {});

}  // namespace settle::coupling
