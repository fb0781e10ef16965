#pragma once
// The plan of a case: what a run derives from its set-up before it allocates anything, the unit
// conversion, the grid, the step count and the dimensionless groups (docs/architecture.md,
// "Units"). coupling::Simulation is built on it, io::preflight checks it against the machine and
// `settle run --dry-run` prints it; no other code computes these numbers.
#include <array>
#include <cstdint>
#include <optional>

#include <Eigen/Core>

#include "body/contact.hpp"

#include "coupling/setup.hpp"
#include "coupling/units.hpp"

namespace settle::coupling {

/// Largest grid settle allocates: 2e9 cells is about 300 GB of D3Q19 doubles.
inline constexpr double kMaxGridCells = 2.0e9;

/// The speed the time step must resolve (see the file comment of units.hpp): towing speed plus
/// rotation, the estimated driven speed for a fixed body with a body force, or the larger of the
/// Schiller-Naumann terminal speed of the volume-equivalent sphere and the initial speed, plus
/// rotation, for a free body; plus the speed of an inflow.
double expected_speed_si(const SimulationSetup& setup);

struct CasePlan {
  UnitConverter units;             ///< dx, dt, tau
  double expected_speed_si = 0.0;  ///< the speed dt was chosen for
  double mach = 0.0;               ///< of the expected speed
  double reynolds = 0.0;           ///< expected speed x d_eq / nu
  double galileo = 0.0;
  double equivalent_diameter_si = 0.0;
  double cell_reynolds = 0.0;  ///< expected speed x dx / nu
  /// The subgrid model the run uses (numerics.subgrid_model = "auto" chosen from cell_reynolds).
  lbm::SubgridModel subgrid_model = lbm::SubgridModel::none;
  /// round(size / dx) per axis, as doubles so that an absurd request is reported, not overflowed.
  std::array<double, 3> cells{};
  double steps = 0.0;             ///< steps to reach run.end_time (time_control.hpp's count)
  std::int64_t release_step = 0;  ///< a free body is held during the steps before this one
  [[nodiscard]] double cell_count() const { return cells[0] * cells[1] * cells[2]; }
};

/// Checks the set-up's consistency (settle::InputError naming the key: a body force on a free
/// body, forcing iterations, the contact parameters, the converter's bounds) and plans it.
/// Allocates nothing proportional to the grid.
CasePlan plan_case(const SimulationSetup& setup);

/// The coupling's options as the case's keys set them.
CouplingOptions coupling_options(const SimulationSetup& setup);

/// The gap (cells) at which the contact spring starts: the case's, else the reach of the coupling's
/// cells beyond the surface (coupling_reach_cells: the delta kernel's half-width, or one cell). A
/// body resting at that gap is half a cell further from the wall than its coupling needs, which
/// takes the overlap of impacts up to several times the expected speed (docs/rigid-body.md).
double contact_distance_cells(const SimulationSetup& setup);

/// Refuses (settle::InputError naming the key) a body whose coupling box (coupling_box) at its
/// initial pose leaves a grid of `cells` with spacing dx_si: along a walled axis every cell of the
/// box must be in the grid (particle.position), along a periodic one it may span no more cells than
/// the grid (domain.size). The Simulation's constructor and the preflight both apply this one rule.
void check_body_box_in_grid(const SimulationSetup& setup, double dx_si, const std::array<int, 3>& cells);

/// The particle-wall contact model of a free body (none for a towed or fixed one, with the window
/// following the body, with contact off, or without a wall): its walls are the faces of the grid
/// (`cells` at dx_si, corner at window_origin_si) that are neither periodic nor open. Refuses
/// (settle::InputError, particle.position) a body that starts deeper in the contact spring than
/// twice its static compression, which the stored energy would throw off the wall. The Simulation's
/// constructor and the preflight both build it here.
std::optional<body::WallContact> start_wall_contact(const SimulationSetup& setup, double dx_si, double dt_si,
                                                    const std::array<int, 3>& cells,
                                                    const Eigen::Vector3d& window_origin_si);

}  // namespace settle::coupling
