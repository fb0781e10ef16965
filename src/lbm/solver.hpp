#pragma once
// The fluid solver's run-time interface. One virtual call per step (or per query); the hot
// loop lives in AaKernel (lbm/aa_kernel.hpp), a part of AaSolver<Lattice, Collision, Real>
// (lbm/aa_solver.hpp), instantiated for every combination by make_solver().
//
// Cell coordinates (x, y, z) are interior cell indices, 0 <= x < nx etc.; cell (x, y, z)
// has its centre at (x + 1/2, y + 1/2, z + 1/2) in lattice units, so half-way walls lie at
// 0 and nx. The linear cell index used by every field returned here and by the force array
// is  x + nx * (y + ny * z)  (x fastest).
#include <Eigen/Core>
#include <array>
#include <cstddef>
#include <cstdint>
#include <functional>
#include <memory>
#include <optional>
#include <span>
#include <string>
#include <vector>

#include "lbm/config.hpp"

namespace settle::lbm {

/// A vector field on the interior cells, one array per component (SoA), linear cell index
/// x + nx * (y + ny * z).
struct VectorField {
  std::vector<double> x, y, z;
};

/// Extremes of the macroscopic fields over the interior cells, from one pass (Solver::extrema).
struct FieldExtrema {
  double min_density = 1.0;
  double max_density = 1.0;
  double max_speed = 0.0;  ///< largest |u| (with Guo's half-force correction)
  bool finite = true;      ///< no NaN or infinity in any density or velocity
  /// Interior cells (x, y, z) where each extreme sits (the first in x, y, z order on ties), so a
  /// failing health check can say where the fluid went wrong, not only how far.
  std::array<int, 3> min_density_cell{}, max_density_cell{}, max_speed_cell{};

  /// Takes in the extremes of a part that comes after this one in x, y, z order (a row, a rank's
  /// block): strictly more extreme values replace, so the first extreme keeps a tie.
  void merge_later(const FieldExtrema& later) {
    finite = finite && later.finite;
    if (later.min_density < min_density) min_density = later.min_density, min_density_cell = later.min_density_cell;
    if (later.max_density > max_density) max_density = later.max_density, max_density_cell = later.max_density_cell;
    if (later.max_speed > max_speed) max_speed = later.max_speed, max_speed_cell = later.max_speed_cell;
  }
};

/// Density and velocity of one cell (velocity includes Guo's half-force correction).
struct CellState {
  double density = 1.0;
  Eigen::Vector3d velocity = Eigen::Vector3d::Zero();
};

/// Mass bookkeeping of one moving-window shift (lattice units: density times cell volume 1).
struct ShiftMass {
  double left = 0.0;     ///< mass of the layer that left the window
  double entered = 0.0;  ///< mass of the rest-fluid layer that entered
};

/// How a solver lays out its population buffer (lbm/grid.hpp): a saved state fits a solver only
/// when these agree, so that a checkpoint from another build or case is refused, not misread.
struct StateLayout {
  int nx = 0, ny = 0, nz = 0;
  int q = 0;                        ///< velocities of the lattice
  std::uint32_t element_bytes = 0;  ///< storage precision: 4 (float) or 8 (double)
  std::uint64_t x_begin = 0, sx = 0, sxy = 0, pop_stride = 0;
  std::uint64_t population_elements = 0;  ///< q * pop_stride
  bool operator==(const StateLayout&) const = default;
};

/// The complete mutable state of a solver: with the same SolverConfig, a solver that imports it
/// steps on bit for bit as the one that exported it (and answers every query the same way).
struct FluidState {
  StateLayout layout;
  /// Steps taken since initialise(); its parity selects the next AA kernel.
  std::int64_t step_count = 0;
  /// The raw population buffer in storage precision (f - w, all Q arrays over the padded grid).
  /// The ghost layer is included: at an odd step_count it holds the boundary copies that the
  /// next (odd) kernel reads, so it is state, not scratch. A view: valid while the exporting solver
  /// is alive and unchanged.
  std::span<const std::byte> populations;
  /// Cells holding a force written since the last clear_forces() (linear index x + nx (y + ny z)),
  /// in the order they were first written, and their force density, three values per cell
  /// (x, y, z). Doubles hold float storage exactly, so the round trip is exact at either precision.
  std::vector<std::uint64_t> forced_cells;
  std::vector<double> forced_values;
  /// The obstacle's solid cells (linear index, ascending). Its links are not state: the owner of
  /// the obstacle sets them again before the next step.
  std::vector<std::uint64_t> solid_cells;
};

/// A link from fluid cell `cell` along direction `dir` to a solid cell of an obstacle, the wall
/// crossing the link at the fraction q in (0, 1] of its length from the fluid cell's centre and
/// moving there with `wall_velocity` (lattice units).
struct WallLink {
  std::array<int, 3> cell{};
  int dir = 0;
  double q = 0.5;
  Eigen::Vector3d wall_velocity = Eigen::Vector3d::Zero();
};

/// How the populations coming back from an obstacle's wall are made (docs/lbm.md, "Walls inside
/// the grid"):
/// - halfway: bounce-back as if every wall sat half-way along its links (q ignored), a
///   staircase of the cells' faces, first order in the wall's true position;
/// - bouzidi: linear interpolation along the link at the true q (Bouzidi, Firdaouss and
///   Lallemand 2001, Phys. Fluids 13, 3452, doi:10.1063/1.1399290), second order;
/// - quadratic: their quadratic interpolation, from three points along the link, where x - c_i and
///   x - 2 c_i are fluid cells of the lattice (else the linear rule). On a split lattice a link
///   whose x - c_i is a ghost reads its third value from the block that holds that cell (the far
///   values, exchanged around the step: BlockExchange::exchanges_far_values).
/// - central_linear: Ginzburg's central linear interpolation (CLI; Ginzburg, Verhaeghe and
///   d'Humieres 2008, Commun. Comput. Phys. 3, 427), one formula for every q from f*_i at x and
///   x - c_i and f*_opp(i) at x, second order; where x - c_i is not fluid, half-way at that link.
enum class WallRule { halfway, bouzidi, quadratic, central_linear };
/// The rule a case gets unless it chooses (docs/coupling.md says why).
inline constexpr WallRule kDefaultWallRule = WallRule::bouzidi;
std::string to_string(WallRule rule);
/// The case file's names (bouzidi, quadratic, central_linear, halfway); throws settle::InputError
/// naming `what`.
WallRule parse_wall_rule(const std::string& name, const std::string& what);

/// Solid cells inside the grid and the links of fluid cells into them. The solid cells are not
/// fluid: their content is reset to rest after every odd step and never reaches the fluid. On a
/// block of a split lattice the cells are the block's (its coordinates), and the solid cells of
/// the adjacent blocks in its ghost layer (-1 or n along an axis with a block beyond) where its
/// links end; the links are those of its own fluid cells. With the quadratic rule the block also
/// needs the solid cells one layer further out (-2 or n + 1 along an axis with a block beyond):
/// `far_solid_cells`, where a link's x - 2 c_i may lie.
struct Obstacle {
  std::vector<std::array<int, 3>> solid_cells;
  std::vector<WallLink> links;
  WallRule rule = WallRule::bouzidi;
  std::vector<std::array<int, 3>> far_solid_cells;
};

/// The exchange protocol of a block of a split lattice (lbm/block_exchange.hpp, which only the
/// parallel module includes).
class BlockExchange;

/// Initial condition: density and velocity of interior cell (x, y, z).
using InitialField = std::function<CellState(int x, int y, int z)>;

class Solver {
 public:
  virtual ~Solver() = default;

  virtual const SolverConfig& config() const = 0;
  int nx() const { return config().nx; }
  int ny() const { return config().ny; }
  int nz() const { return config().nz; }
  std::size_t cell_count() const {
    return static_cast<std::size_t>(nx()) * static_cast<std::size_t>(ny()) * static_cast<std::size_t>(nz());
  }
  std::size_t linear_index(int x, int y, int z) const {
    return static_cast<std::size_t>(x) +
           static_cast<std::size_t>(nx()) *
               (static_cast<std::size_t>(y) + static_cast<std::size_t>(ny()) * static_cast<std::size_t>(z));
  }

  /// One collide-and-stream step (AA pattern: alternately the even and odd kernel), threads
  /// from OpenMP (omp_set_num_threads / OMP_NUM_THREADS).
  virtual void step() = 0;
  void run(std::int64_t steps) {
    for (std::int64_t s = 0; s < steps; ++s) step();
  }
  virtual std::int64_t step_count() const = 0;

  /// A block of a split lattice (lbm/decomposition.hpp) steps and shifts in halves around its
  /// exchanges with the adjacent blocks: parallel::step and parallel::shift drive them through this
  /// (lbm/block_exchange.hpp). step() and shift() refuse to run on a block with neighbours.
  virtual BlockExchange& block_exchange() = 0;
  virtual const BlockExchange& block_exchange() const = 0;

  /// Sets every cell to the equilibrium of the given density and velocity. The stored
  /// momentum is rho u - F/2 with the force present now, so that velocity() returns u.
  /// Resets step_count() to 0.
  virtual void initialise(const InitialField& field) = 0;

  /// Moving window: the window moves one cell along `axis` (0, 1, 2) in direction `sign`
  /// (+1 or -1), so the fluid content moves by -sign cells relative to the grid. The layer
  /// that leaves is dropped, the entering layer is fluid at rest at density 1 (the rest
  /// equilibrium is symmetric, so it is valid at either AA parity). Forces are not shifted.
  /// Solid cells move with the content (those that leave are dropped); the obstacle's links are
  /// dropped, to be set again at its new place. Refuses a block with neighbours (std::logic_error):
  /// those shift through parallel::shift.
  virtual ShiftMass shift(int axis, int sign) = 0;

  /// Total mass sum(rho) over the interior cells (exact to round-off at either parity).
  virtual double total_mass() const = 0;

  // --- single-cell queries (cheap; safe: periodic axes wrap, others throw std::out_of_range)
  virtual CellState cell_state(int x, int y, int z) const = 0;
  double cell_density(int x, int y, int z) const { return cell_state(x, y, z).density; }
  Eigen::Vector3d cell_velocity(int x, int y, int z) const { return cell_state(x, y, z).velocity; }
  /// cell_state of every cell of the box [origin, origin + extent), x fastest, into density[n] and
  /// velocity[a][n] (each holding the box's cell count): the same values as cell_state, read a row
  /// at a time where the row lies inside the lattice, which is what the couplings' gathers need.
  virtual void box_states(const std::array<int, 3>& origin, const std::array<int, 3>& extent, double* density,
                          const std::array<double*, 3>& velocity) const = 0;
  /// The current post-streaming (pre-collision) populations f_i of a cell, whatever the AA
  /// parity; `f` must hold Q values (direction order of lbm/lattice.hpp).
  virtual void cell_populations(int x, int y, int z, std::span<double> f) const = 0;
  /// Makes f the populations the cell's next collision starts from. At an even step_count() they
  /// are the cell's own slots; at an odd one the slots its neighbours' (or a wall's) populations
  /// stream in from, which only this cell reads, so either parity refills one cell alone.
  virtual void set_cell_populations(int x, int y, int z, std::span<const double> f) = 0;
  /// Number of discrete velocities of the instantiated lattice.
  virtual int velocity_count() const = 0;

  // --- whole fields (linear index x + nx (y + ny z))
  virtual std::vector<double> density_field() const = 0;
  /// Pressure p = cs^2 (rho - 1) (lattice units, relative to the reference density 1).
  std::vector<double> pressure_field() const;
  virtual VectorField velocity_field() const = 0;
  /// The extremes of density and speed in one parallel pass without allocating the fields: what
  /// the run's health check needs at every output sample, at the cost of about one streaming step.
  virtual FieldExtrema extrema() const = 0;
  /// Vorticity curl(u) by second-order central differences (periodic axes wrap; one-sided
  /// second-order differences at the faces of non-periodic axes).
  VectorField vorticity_field() const;

  // --- per-cell force density (lattice units), added to config().body_force in the kernel.
  // Stored in the storage precision as three SoA arrays over the interior cells with the
  // linear index above. The kernel reads it for every cell; only cells written through
  // add_force/set_force since the last clear_forces() are non-zero, and clear_forces()
  // zeroes just those (a sparse list), so the coupling pays only for the cells near the
  // body. Not thread-safe: call from one thread.
  virtual void add_force(int x, int y, int z, const Eigen::Vector3d& force) = 0;
  virtual void set_force(int x, int y, int z, const Eigen::Vector3d& force) = 0;
  virtual Eigen::Vector3d force(int x, int y, int z) const = 0;
  virtual void clear_forces() = 0;
  /// Number of cells holding a force written since the last clear_forces().
  virtual std::size_t forced_cell_count() const = 0;

  /// Makes a cell fluid again after an obstacle left it: the equilibrium at density rho and
  /// velocity u plus the non-equilibrium part f - f_eq of the fluid cell `donor` (Caiazzo 2008's
  /// refill, the non-equilibrium part copied from one neighbour; the equilibrium alone without
  /// a donor). Either parity.
  void refill_cell(const std::array<int, 3>& cell, double rho, const Eigen::Vector3d& u,
                   const std::optional<std::array<int, 3>>& donor);
  /// The same with the donor's non-equilibrium part given (Q values: non_equilibrium() of a cell
  /// that may live in another block).
  virtual void refill_cell_with(const std::array<int, 3>& cell, double rho, const Eigen::Vector3d& u,
                                std::span<const double> non_equilibrium) = 0;
  /// The non-equilibrium part f - f_eq of a fluid cell's populations (Q values into `f_neq`, Guo's
  /// velocity in f_eq), and its density as the return value: what a refill takes from a donor.
  virtual double non_equilibrium(int x, int y, int z, std::span<double> f_neq) const = 0;

  /// The velocity of the velocity faces from the next step on (config().inflow_velocity at the
  /// start): a stream can be ramped up. Throws std::invalid_argument beyond magnitude 0.3.
  virtual void set_inflow_velocity(const Eigen::Vector3d& velocity) = 0;
  virtual const Eigen::Vector3d& inflow_velocity() const = 0;

  // --- an obstacle inside the grid (a body coupled by momentum exchange)
  /// Replaces the obstacle. Every link must start at a fluid cell and end, one step along
  /// c_dir, at a solid cell (periodic axes wrap; a ghost of an adjacent block counts); throws
  /// std::invalid_argument otherwise.
  /// Cells that were solid and are not any more keep what they hold: refill them first
  /// (set_cell_populations).
  virtual void set_obstacle(const Obstacle& obstacle) = 0;
  virtual bool is_solid(int x, int y, int z) const = 0;
  virtual std::size_t solid_cell_count() const = 0;
  /// The solid cells, in linear-index order.
  virtual std::vector<std::array<int, 3>> solid_cell_list() const = 0;
  /// The momentum the fluid gave to the wall through each link of the obstacle in the last
  /// step, in link order (lattice units; momentum exchange in the Galilean-invariant form of Wen,
  /// Zhang, Tang, Wang and Fang 2014, J. Comput. Phys. 266, 161, doi:10.1016/j.jcp.2014.02.018).
  virtual const std::vector<Eigen::Vector3d>& wall_momentum() const = 0;

  // --- checkpoints
  /// The complete state (see FluidState); the populations are a view, not a copy.
  virtual FluidState export_state() const = 0;
  /// Replaces the state with an exported one. Throws std::invalid_argument when its layout differs
  /// from this solver's, a size does not match it, or a forced cell is out of range or repeated;
  /// the solver is unchanged then.
  virtual void import_state(const FluidState& state) = 0;

  /// Bytes moved from/to memory per cell update by the kernel: Q populations read and
  /// written plus the three force components read (storage precision). For the roofline.
  virtual std::size_t bytes_per_cell_update() const = 0;
};

/// The discrete velocities of a lattice in the solvers' direction order (lbm/lattice.hpp).
std::span<const std::array<int, 3>> velocity_set(LatticeKind kind);

/// curl u by second-order central differences on a lattice of this extent (linear index x + nx (y +
/// ny z)): periodic axes wrap, other faces take one-sided second-order differences. What
/// Solver::vorticity_field computes, for a field gathered from the blocks of a split lattice.
VectorField vorticity_of(const VectorField& u, const std::array<int, 3>& extent,
                         const std::array<Boundary, 3>& boundaries);

/// Builds the solver for `config` (validated first; throws settle::InputError).
std::unique_ptr<Solver> make_solver(const SolverConfig& config);

}  // namespace settle::lbm
