#pragma once
// Checks of a case before anything large is allocated: the run either starts with a
// set-up that can work, or stops with a settle::InputError that names the key (or flag) to
// change, the value, and what is allowed. docs/errors.md lists every check with an example.
//
// What is checked, in this order (each in its own function below):
//  1. numbers: every SI quantity of the set-up is finite (the schema already refuses NaN and
//     infinity in a case; this guards set-ups built in code);
//  2. the plan (coupling::plan_case, the same the Simulation is built on): the converter's dt,
//     tau and Mach bounds and the set-up's consistency (a body force on a free particle, the
//     contact parameters);
//  3. net weight: a free particle heavier or lighter than the fluid drifts along or against
//     gravity; the domain must not be periodic along gravity (see check_net_weight);
//  4. grid: at least 4 cells per axis, at most coupling::kMaxGridCells, the
//     memory the run will hold against the memory available;
//  5. the particle at its initial pose: inside the domain, no wider than it, clear of every wall,
//     far enough from the walls for the cells its coupling works on, and outside the wall-contact
//     spring's reach (the last two are the Simulation's own rules: coupling::check_body_box_in_grid
//     and coupling::start_wall_contact);
//  6. surface elements and steps: at most a million immersed-boundary surface markers, a step
//     count that t = n dt counts exactly;
//  7. the output directory: creatable and writable (nothing is created here).
// Preflight only reads: it allocates nothing proportional to the grid and writes no file.
#include <array>
#include <cstdint>
#include <filesystem>
#include <optional>
#include <string>
#include <string_view>
#include <utility>
#include <vector>

#include "coupling/case_plan.hpp"
#include "coupling/simulation.hpp"
#include "coupling/units.hpp"
#include "lbm/config.hpp"

namespace settle::io {

/// Surface markers above this count are refused by body::validate_marker_spacing.
inline constexpr double kMaxMarkers = 1.0e6;
/// Largest step count: t = n dt is exact in double precision up to 2^53 steps.
inline constexpr double kMaxSteps = 9007199254740992.0;

/// Grid cells of a domain per axis (coupling::CasePlan::cells).
struct GridExtent {
  std::array<double, 3> cells{};  ///< per axis, as doubles so absurd requests do not overflow
  double total() const { return cells[0] * cells[1] * cells[2]; }
};

/// What the run will hold in memory, bytes, by part. The lattice Boltzmann parts are exact for
/// lbm::AaSolver (same layout function); the rest are estimates, noted at each term.
struct MemoryEstimate {
  double populations_bytes = 0.0;     ///< Q arrays over the padded grid (lbm/grid.hpp)
  double force_bytes = 0.0;           ///< 3 per-cell force arrays of the storage type
  double flag_bytes = 0.0;            ///< one forced-cell flag byte per cell
  double boundary_links_bytes = 0.0;  ///< the AA copy lists: two 16-byte entries per boundary link
  double body_bytes = 0.0;            ///< the box of cells around the body and its surface elements
  double output_bytes = 0.0;          ///< samples kept for the summary; a fixed body's velocity field
  double total_bytes() const;
};

/// What estimate_memory needs; cells must each fit in an int (checked by preflight first).
struct MemoryInputs {
  std::array<int, 3> cells{};
  lbm::LatticeKind lattice = lbm::LatticeKind::D3Q19;
  lbm::Precision precision = lbm::kDefaultPrecision;
  double body_box_cells = 0.0;  ///< cells of the box around the body (radius + coupling_reach_cells)
  /// Immersed boundary: surface and interior markers; momentum exchange: boundary cells.
  double surface_elements = 0.0;
  double samples = 0.0;                    ///< timeseries rows the run keeps in memory
  bool velocity_field_per_sample = false;  ///< fixed bodies sample the superficial velocity
};
MemoryEstimate estimate_memory(const MemoryInputs& inputs);

/// Boundary links of an nx x ny x nz box: pairs (cell, direction) whose upstream cell lies
/// outside, i.e. sum over directions c of N - prod_a max(0, n_a - |c_a|). Each gives one entry
/// in each of the AA scheme's two copy lists, whatever the boundary kind.
double boundary_link_count(const std::array<int, 3>& cells, lbm::LatticeKind lattice);

/// MemAvailable of /proc/meminfo text, in bytes; nullopt when absent or unreadable.
std::optional<double> parse_mem_available(std::string_view meminfo_text);
/// The machine's available memory (Linux /proc/meminfo MemAvailable), bytes; nullopt elsewhere.
std::optional<double> available_memory_bytes();

/// Refuses an estimate above the budget. `budget_source` names where the budget came from
/// ("MemAvailable in /proc/meminfo" or "--max-memory"), for the message.
void check_memory(const MemoryEstimate& estimate, double budget_bytes, std::string_view budget_source);

/// How far the particle at its initial pose is from each face of the domain, m: the gap between
/// the body (its support function along the axis) and the face; negative = the body crosses it.
struct FaceClearance {
  std::array<double, 3> lower_si{};  ///< to the face at 0
  std::array<double, 3> upper_si{};  ///< to the face at `extent_si`
  std::array<double, 3> width_si{};  ///< the body's width along each axis at this attitude
};
FaceClearance face_clearance(const body::Shape& shape, const Eigen::Vector3d& position_si,
                             const Eigen::Matrix3d& body_to_inertial, const Eigen::Vector3d& extent_si);

/// Step 5 of the file comment. `cells` are the grid's cells per axis: the walls are the grid's
/// faces, at 0 and cells x dx. Periodic axes have no wall; there the body and the cells its
/// coupling works on must only span less than the period (coupling::check_body_box_in_grid).
void check_particle_in_domain(const coupling::SimulationSetup& setup, double dx_si, const std::array<double, 3>& cells);

/// Step 3. A free particle whose net weight (rho_p - rho_f) V g is not zero drifts along
/// sign(rho_p - rho_f) g: a heavy one sinks, a light one rises. With walls, the walls carry the
/// net weight through the pressure, and a particle that reaches one ends the run cleanly
/// ("reached_boundary"). Along a periodic axis nothing carries it: the total momentum of fluid
/// and particle grows by the net weight every second (this version applies no compensating
/// pressure gradient, and fluid.body_force is refused for free particles), so the run would
/// accelerate without bound and its results would be wrong. Refused for every axis along which
/// gravity has a component, whether the particle rises or sinks.
void check_net_weight(const coupling::SimulationSetup& setup);

/// Before the resolution is judged: the particle, at its initial attitude, narrower than the domain
/// along every axis (settle::InputError naming domain.size, and particle.scale for a mesh: a mesh in
/// millimetres read as metres used to be reported as a resolution to raise to 796 952 cells per
/// diameter, or as a domain of 0 cells).
void check_particle_narrower_than_domain(const coupling::SimulationSetup& setup);

/// Step 7: `dir` exists and is a writable directory, or can be created (its nearest existing
/// ancestor is a writable directory). `flag` names the option in messages ("-o").
void check_output_directory(const std::filesystem::path& dir, std::string_view flag = "-o");

struct PreflightOptions {
  /// Checked by check_output_directory when not empty.
  std::filesystem::path output_directory;
  /// Memory budget in bytes, replacing MemAvailable (settle run --max-memory).
  std::optional<double> memory_budget_bytes;
};

/// What preflight found: the numbers the run will use, printed by `settle run` before it starts.
struct PreflightReport {
  explicit PreflightReport(coupling::CasePlan case_plan) : plan(std::move(case_plan)) {}
  coupling::CasePlan plan;  ///< units, dimensionless groups, steps (the Simulation's own plan)
  std::array<int, 3> cells{};
  double cell_count = 0.0;
  double steps = 0.0;
  /// Estimated: surface area / dx^2, the momentum exchange's boundary cells or the immersed
  /// boundary's surface markers, with the latter's interior lattice if any.
  double surface_elements = 0.0;
  std::string surface_element_name = "boundary cells";  ///< what surface_elements counts, plural
  /// "about N boundary cells" (or markers), for the console.
  std::string surface_text() const;
  MemoryEstimate memory;
  std::optional<double> memory_budget_bytes;  ///< nullopt: unknown (no /proc/meminfo)
  std::string memory_budget_source;
  /// Not errors, but worth a look (a body thinner than two cells, a run shorter than one step).
  std::vector<std::string> warnings;
  /// One line: grid, cells, steps, memory estimate against the budget.
  std::string summary() const;
};

/// All checks of the file comment, in order; throws settle::InputError at the first failure.
PreflightReport preflight(const coupling::SimulationSetup& setup, const PreflightOptions& options = {});

}  // namespace settle::io
