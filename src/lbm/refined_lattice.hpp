#pragma once
// A two-level refined D3Q19 lattice: one coarse grid and one static fine box, refinement ratio 2 in
// space and time (issue 71, first step: no body, no coupling, no case keys). docs/lbm.md, "Grid
// refinement (first step: two static levels, no body)", derives the scheme; this header says what
// each function does.
//
// This is the scheme's reference implementation, written for correctness, not speed: plain
// two-array pull streaming on cell-major (cell, direction) arrays, a scalar local BGK collision,
// no threads, no SIMD, no MPI. The AA-pattern solver (aa_solver.hpp) is not used; porting the
// interface to it is a later step.
//
// Units: every quantity is in the coarse level's lattice units (dx_c = dt_c = 1) unless its name
// says `fine`. Acoustic scaling (dx_f = dx_c / 2, dt_f = dt_c / 2): lattice velocities are the
// same on both levels, the force density per lattice unit halves, and the same physical viscosity
// gives tau_f - 1/2 = 2 (tau_c - 1/2).
//
// Interface: the volumetric, cell-centred, mass-conserving scheme of Rohde, Kandhai, Derksen and
// van den Akker (2006, Int. J. Numer. Meth. Fluids 51, 439, doi:10.1002/fld.1140), the one waLBerla
// uses (Schornbaum and Ruede 2016, SIAM J. Sci. Comput. 38, C96, doi:10.1137/15M1035240): a coarse
// cell's post-collision populations are given to its 8 children (explosion; linear in the cell by
// default, as waLBerla, or uniform, as Rohde et al.), what the fine level takes of each is removed
// from what the coarse level streams on, and what the fine cells send out over two fine steps is
// summed into the coarse cell it lands in, weighted by the volume 1/8 (coalescence). Optionally, the
// non-equilibrium part of what crosses is rescaled between the levels (Dupuis and Chopard 2003,
// Phys. Rev. E 67, 066707, doi:10.1103/PhysRevE.67.066707), with the mass it moves between
// directions returned to the receiving cell's rest population so that mass stays exact; off by
// default, because momentum then does not stay exact (docs/lbm.md, "Grid refinement").
#include <array>
#include <functional>
#include <vector>

namespace settle::lbm::refinement {

/// A box of coarse cells, [lo, hi) per axis.
struct CellBox {
  std::array<int, 3> lo{};
  std::array<int, 3> hi{};
  bool contains(int x, int y, int z) const {
    return x >= lo[0] && x < hi[0] && y >= lo[1] && y < hi[1] && z >= lo[2] && z < hi[2];
  }
};

struct RefinedLatticeConfig {
  std::array<int, 3> coarse_cells{16, 16, 16};
  /// The fine box in coarse cells. It keeps one coarse cell from every face of the domain, so that
  /// the coarse cells around it (the interface layer) are fluid cells of the coarse grid.
  CellBox fine_box{{4, 4, 4}, {12, 12, 12}};
  /// Half-way bounce-back walls at y = 0 and y = ny (coarse cell faces); periodic in y otherwise.
  /// x and z are periodic.
  bool walls_y = false;
  double tau_coarse = 0.8;
  /// Force density per coarse lattice unit (Guo forcing), uniform; the fine level uses half of it.
  std::array<double, 3> force_coarse{0.0, 0.0, 0.0};
  /// Rescale the non-equilibrium part of the populations crossing the interface (Dupuis and
  /// Chopard 2003); off: plain copy and average, as in Rohde et al. 2006 and waLBerla. Off by
  /// default: the rescaled populations carry another momentum than the ones the other level gave,
  /// and that momentum source at the interface costs 7.7% of the channel flow at H = 16 (docs/lbm.md).
  bool rescale_non_equilibrium = false;
  /// Explosion with a linear profile in each coarse cell (slopes by central differences of the
  /// neighbours, one-sided next to the box or a wall), whose 8 children average to the coarse value,
  /// as waLBerla's default; off: the same value in all 8 children, as in Rohde et al. 2006.
  bool linear_explosion = true;
};

/// Density and velocity (Guo's half-force included) of one cell, in lattice units of its level,
/// which for the velocity are the same on both levels.
struct CellMoments {
  double rho = 1.0;
  std::array<double, 3> u{0.0, 0.0, 0.0};
};

class RefinedLattice {
 public:
  static constexpr int Q = 19;  // D3Q19 (lattice.hpp)

  explicit RefinedLattice(const RefinedLatticeConfig& config);

  /// Equilibrium populations on both levels from the density and velocity at a point given in
  /// coarse cell units (the cell centre of coarse cell i is i + 1/2).
  using InitialState = std::function<CellMoments(double x, double y, double z)>;
  void initialise(const InitialState& state);

  /// One coarse time step: collide_coarse, explode, two fine_substep, stream_coarse (which applies
  /// the coalescence).
  void step();

  const RefinedLatticeConfig& config() const { return config_; }
  double tau_fine() const { return tau_fine_; }
  std::array<int, 3> fine_cells() const { return fine_cells_; }
  /// Whether coarse cell (x, y, z) is covered by the fine box (its state lives on the fine level).
  bool covered(int x, int y, int z) const { return config_.fine_box.contains(x, y, z); }
  CellMoments coarse_moments(int x, int y, int z) const;
  /// Fine cell (a, b, c) counted from the box's lower corner; its centre in coarse cell units is
  /// lo + (a + 1/2) / 2.
  CellMoments fine_moments(int a, int b, int c) const;
  /// Mass in coarse cell volumes: sum of the populations of the uncovered coarse cells plus 1/8 of
  /// those of the fine cells, minus the rest-state mass (so that a fluid at rho = 1 has 0).
  double mass_deviation() const;

 private:
  // The time step's parts, in their order.
  void collide_coarse();
  void explode();
  void fine_substep(int substep);
  void collide_fine();
  void stream_fine(int substep);
  void accumulate_coalescence(int substep);
  void stream_coarse();

  int coarse_index(int x, int y, int z) const;
  int fine_index(int a, int b, int c) const;
  bool in_fine_box(int a, int b, int c) const;
  /// The coarse cell holding the fine-level position (a, b, c) (fine cells from the box corner,
  /// any sign), with the periodic wrap.
  int parent_of_fine(int a, int b, int c) const;
  /// The children of (x, y, z) whose population i enters the box during the coarse step: how many,
  /// and the sum of their offsets from the parent's centre.
  void children_entering(int x, int y, int z, int i, int& count, std::array<double, 3>& offset_sum) const;
  /// Index of coarse cell (x, y, z) after the periodic wrap, or -1 past a wall or inside the box.
  int uncovered_neighbour(int x, int y, int z) const;
  void compute_slopes(const std::vector<double>& values, std::vector<double>& slopes, int x, int y, int z) const;

  RefinedLatticeConfig config_;
  double tau_fine_ = 1.0;
  std::array<int, 3> fine_cells_{};
  // Coarse level: populations before collision (`coarse_`), after (`coarse_post_`), the explosion
  // values of the cells around the box (`coarse_exploded_`), the slopes (3 per population) of both
  // for the linear explosion, for each population of the interface cells the share of children that
  // enter the box and the sum of their offsets, and the coalescence gathered over the two fine steps.
  std::vector<double> coarse_, coarse_post_, coarse_exploded_, coarse_coalesced_;
  std::vector<double> coarse_post_slope_, coarse_exploded_slope_;
  std::vector<double> coarse_fine_share_, coarse_entering_offset_;
  // Fine level: before collision, after, and the post-collision state expressed on the coarse level
  // (what the coalescence sends).
  std::vector<double> fine_, fine_post_, fine_post_as_coarse_;
};

}  // namespace settle::lbm::refinement
