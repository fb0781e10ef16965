#pragma once
// The sharp-interface coupling behind BodyCoupling (coupling/body_coupling.hpp), lattice units.
//
// At each step's pose the cells whose centres lie inside the body are solid; every link from a
// fluid cell x along c_i to a solid cell crosses the surface at x + q c_i, q in (0, 1], found by
// the shape (Shape::surface_crossings: a closed form, Newton's method on a superellipsoid's gauge,
// a mesh's triangles, else a root search on the signed distance; docs/coupling.md, "Finding the
// walls"). A mesh's inside test is first asked of a body-frame table of its distance. The fluid closes
// those links by interpolated bounce-back with the wall's rigid-body velocity at the crossing
// (Bouzidi, Firdaouss and Lallemand 2001, doi:10.1063/1.1399290; lbm::WallRule), and the force
// and torque on the body are the momentum the links exchange, in the Galilean-invariant form of
// Wen, Zhang, Tang, Wang and Fang 2014 (doi:10.1016/j.jcp.2014.02.018), torque about the centre
// with each link's momentum acting at its crossing point.
//
// A uniform body force on the fluid (a mean pressure gradient) also acts on the solid cells'
// volume and is added to the force.
//
// Cells the body uncovers become fluid with the equilibrium at the mean density of their fluid
// neighbours and the wall's velocity there, plus the non-equilibrium part of the fluid neighbour
// that lies farthest along the direction away from the body (Caiazzo 2008, Prog. Comput. Fluid
// Dyn. 8, 3, doi:10.1504/PCFD.2008.018074, "equilibrium plus non-equilibrium refill", with the
// non-equilibrium part taken from one neighbour instead of extrapolated). Cells the body covers
// leave the fluid; their content is dropped. Approximation: the momentum the covered and
// uncovered cells carry is not added to the body's force (Wen et al. 2014 show that their
// Galilean-invariant exchange leaves these terms' effect small; in Uhlmann and Dusek's case B,
// adding them in balance left the path as it was: docs/notes.md, 2026-11-26, "Case B's spin",
// controls 9 and 10). With CouplingOptions::covered_cell_torque the torque does take, at the step
// of covering, the angular momentum by which the covered cells' fluid lags the rigid motion, r x
// rho (u - u_body): without it the resistance to spin is first order in the cell size and at 16
// cells nearly absent at Re = 188; on the force the same term would spoil a drag that is right
// without it (docs/coupling.md, "The covered cells' spin": an empirical choice).
//
// On a block of a split lattice (docs/parallel.md) every rank finds the body's walls on the whole
// lattice and keeps its part: its own solid cells, those of adjacent blocks in its ghost layer, and
// the links of its own fluid cells. The cells next to an uncovered cell that lie in another block
// come from that block in an exchange each step (their solidity, density and non-equilibrium
// part, for the cells of the body's box along the block faces), and the link momenta are gathered
// from every rank and added in the order of the links on the whole lattice, so the wrench, the
// refill and with them the whole run are the same bits for any number of ranks.
//
// The wrench a step reports is the mean of the link sums of that step and the one before. A body
// that moves across the grid makes the link sum alternate from one step to the next (measured: the
// drag coefficient of a sphere towed at Re = 243, tau = 0.51, 0.46 after one kind of step and 1.00
// after the other; docs/notes.md, 2026-11-26); the mean of two consecutive steps cancels that
// period-two part, as waLBerla's running average does for the same benchmark (Rettinger and Ruede
// 2017, doi:10.1016/j.compfluid.2017.05.033). Approximation: the earlier step's torque was taken
// about the centre of that step, a twentieth of a cell away at the lattice speeds used. The first
// step averages with a zero wrench (the body and the fluid start at rest relative to each other or
// held); checkpoints carry the earlier step's link sum.
//
// With CouplingOptions::lattice_steps_per_body_step = 2 the walls are placed once per two lattice
// steps and held for both, and the mean the second step reports is the mean over the pair: the
// scheme of Rettinger and Ruede 2017 (the body moves once per two steps with the averaged force).
// waLBerla's later reproduction of their benchmark (lssfau/walberla,
// apps/benchmarks/FluidParticleCoupling/MotionSettlingSphere.cpp, head comment) notes that holding
// the walls breaks Galilean invariance a little and moved its linear-rule results; it is here as a
// control (docs/coupling.md, "Force averaging").
#include <memory>
#include <span>
#include <unordered_map>
#include <vector>

#include "body/distance_table.hpp"
#include "coupling/body_coupling.hpp"
#include "parallel/communicator.hpp"

namespace settle::coupling {

/// The body's solid cells and wall links at a pose, and the crossing point of each link.
struct BodyWalls {
  lbm::Obstacle obstacle;
  std::vector<Eigen::Vector3d> crossing;  ///< x + q c_i of each link, lattice units
};

/// Solid cells and links of the body inside `box` (which must hold every solid cell and one
/// layer of cells around them), for the lattice's velocities, with the wall velocities of `pose`.
/// With `inside_table` (a table of the shape's signed distance, inside_table_for), the cells it
/// settles skip the shape's inside test: the walls are the same, found faster where that test is
/// a tree walk (a mesh).
BodyWalls body_walls(const body::Shape& shape, double dx_si, const CellBox& box, const LatticePose& pose,
                     std::span<const std::array<int, 3>> velocities, lbm::WallRule rule,
                     const body::DistanceTable* inside_table = nullptr);

/// The table body_walls takes for a shape whose inside test is not a closed form
/// (Shape::contains_is_closed_form), at a quarter of the cell size dx_si; null for the others.
std::shared_ptr<const body::DistanceTable> inside_table_for(std::shared_ptr<const body::Shape> shape, double dx_si);

/// The cells the momentum exchange works on for a body at `centre` (lattice units) with this
/// attitude: every cell whose centre can lie inside the body and one layer around them
/// (MomentumExchangeCoupling::box_at, computed without building the coupling). The cells it
/// needs, the fluid ends of the links, lie within one cell of the surface: the box fits a grid
/// while the body is more than half a cell from each wall (one fluid cell between them).
CellBox momentum_exchange_box(const body::Shape& shape, double dx_si, const Eigen::Vector3d& centre,
                              const Eigen::Matrix3d& body_to_inertial);
/// The reach of those cells beyond the surface (coupling_reach_cells).
inline constexpr double kMomentumExchangeReachCells = 1.0;

class MomentumExchangeCoupling final : public BodyCoupling {
 public:
  MomentumExchangeCoupling(std::shared_ptr<const body::Shape> shape, double dx_si, const CouplingOptions& options,
                           parallel::Communicator& communicator);

  CouplingKind kind() const override { return CouplingKind::momentum_exchange; }
  CellBox box_at(const Eigen::Vector3d& centre, const Eigen::Matrix3d& body_to_inertial) const override;
  void start(lbm::Solver& fluid, const LatticePose& pose) override;
  void place(const lbm::Solver& fluid, const LatticePose& pose) override;
  void impose(lbm::Solver& fluid) override;
  CouplingForces measure(const lbm::Solver& fluid) override;
  bool fluid_inside() const override { return false; }
  std::size_t surface_element_count() const override { return whole_link_count_; }
  const char* surface_element_name() const override { return "wall links"; }
  /// The body mapped onto the lattice (solid cells, wall links and their q; waLBerla's "particle
  /// mapping"), the uncovered cells refilled and the walls handed to the fluid (its "PDF restore"),
  /// the momentum the links exchanged.
  SubStepNames sub_step_names() const override { return {"body_mapping", "refill", "hydrodynamic_force"}; }
  /// The previous step's link sum (force, torque), for the two-step mean.
  std::array<double, 6> carried_state() const override;
  void restore_carried_state(const std::array<double, 6>& state) override;

 private:
  struct NeighbourCell {
    bool solid = false;
    double density = 1.0;
    std::vector<double> non_equilibrium;
  };
  void refill_uncovered(lbm::Solver& fluid) const;
  /// Sum over the cells the body covers at this step (solid at this pose, fluid until now) of
  /// r x rho (u - u_body(x)) about the centre, in the whole lattice's cell order (the same bits for
  /// any number of ranks); CouplingOptions::covered_cell_torque.
  Eigen::Vector3d covered_cell_torque(const lbm::Solver& fluid) const;
  /// Whether any block of the lattice holds solid cells (every rank must call it).
  bool lattice_has_solid_cells(const lbm::Solver& fluid) const;
  /// The cells of other blocks in this block's ghost layer within the body's box (by their index on
  /// the whole lattice), from an exchange with the adjacent blocks.
  std::unordered_map<std::size_t, NeighbourCell> neighbour_cells(const lbm::Solver& fluid) const;
  LatticeWrench link_sum(const lbm::Solver& fluid) const;
  /// Every block's link momenta (this block's are `momentum`) in the whole lattice's link order.
  std::vector<Eigen::Vector3d> gathered_link_momenta(const std::vector<Eigen::Vector3d>& momentum) const;

  std::shared_ptr<const body::Shape> shape_;
  double dx_si_;
  std::shared_ptr<const body::DistanceTable> inside_table_;
  CouplingOptions options_;
  parallel::Communicator& communicator_;
  LatticePose pose_;
  /// This block's solid cells and links (all of them when unsplit) with the crossing points of
  /// every link of the whole lattice (the sum adds them all); each of this block's links' index
  /// among the whole lattice's links (empty when unsplit: the same); the whole lattice's solid
  /// cells (wrapped indices, ascending) and link count.
  BodyWalls walls_;
  std::vector<std::size_t> link_index_;
  std::vector<std::size_t> whole_solids_;
  std::size_t whole_link_count_ = 0;
  LatticeWrench previous_links_;
  /// With covered_cell_torque: the whole lattice's solid cells, unwrapped, in the order of
  /// whole_solids_; the covered cells' torque of this step; whether no impose has run yet (the
  /// first may be the one that makes the body's own cells solid: they are not covered fluid).
  std::vector<std::array<int, 3>> whole_solid_cells_;
  Eigen::Vector3d covered_torque_ = Eigen::Vector3d::Zero();
  bool first_impose_ = true;
  /// Whether place() ran since the last impose(): a placement held for a second lattice step is not
  /// imposed again.
  bool placed_since_impose_ = false;
};

}  // namespace settle::coupling
