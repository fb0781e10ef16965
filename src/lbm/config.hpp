#pragma once
// Run-time configuration of the fluid solver (lattice units throughout: dx = dt = 1,
// reference density 1).
#include <Eigen/Core>
#include <array>
#include <optional>
#include <string>
#include <vector>

#include "lbm/decomposition.hpp"

namespace settle::lbm {

enum class LatticeKind { D3Q19, D3Q27 };

/// Collision operator.
/// - bgk: single relaxation time (Bhatnagar, Gross & Krook 1954).
/// - trt: two relaxation times with a fixed magic parameter (Ginzburg et al. 2008).
/// - recursive_regularized: Hermite-regularised BGK with the third-order non-equilibrium
///   moments rebuilt recursively (Malaspinas 2015; Coreixas et al. 2017): stable close to
///   tau = 1/2.
/// - cumulant: the cumulant operator of Geier, Schoenherr, Pasquali & Krafczyk 2015 (lbm/cumulant.hpp);
///   D3Q27 only.
enum class CollisionKind { bgk, trt, recursive_regularized, cumulant };

/// Subgrid model: none, or Smagorinsky's eddy viscosity set per cell from the cell's own
/// non-equilibrium momentum flux (Hou, Sterling, Chen & Doolen 1996; lbm/collision.hpp,
/// smagorinsky_tau), with every collision operator but the cumulant one; automatic: the choice of
/// chosen_subgrid_model from the case's cell Reynolds number, made before a solver is built (a
/// solver refuses it).
enum class SubgridModel { none, smagorinsky, automatic };

/// Above this cell Reynolds number U dx / nu (U the expected settling speed) TRT without a subgrid
/// model diverged on a free sphere released from rest: it held at 18 (Ga 120, 8 cells per
/// diameter) and 25 (Mordant and Pinton's bead, 16 cells) and diverged from 31 up (Ga 250 at 12
/// cells, Ga 360 and 600 at 8 and 12, a 2 mm quartz grain at 8), where with the Smagorinsky model
/// every run completed (docs/lbm.md, "The default subgrid model"). Below it the model is left off:
/// there it only adds viscosity to a resolved boundary layer (3% slower at Ga 120, 8 cells). The
/// threshold is measured on spheres, with a margin below the first divergence, not derived.
inline constexpr double kTrtStableCellReynolds = 20.0;

/// The model a run uses: `requested`, or for SubgridModel::automatic the Smagorinsky model when
/// the collision operator is TRT and the cell Reynolds number exceeds kTrtStableCellReynolds, none
/// otherwise (BGK and the regularised operators held without it on the same runs).
SubgridModel chosen_subgrid_model(SubgridModel requested, CollisionKind collision, double cell_reynolds);

/// The Smagorinsky constant C_S of a case that does not choose (nu_t = (C_S dx)^2 |S|): 0.1, the
/// value Deardorff (1970, J. Fluid Mech. 41, 453-480, doi:10.1017/S0022112070000691) found for
/// channel flow and the usual one in wall-bounded and sheared flows, rather than Lilly's (1967)
/// 0.17 for isotropic turbulence in the inertial range, which over-damps shear layers and, with
/// no wall damping here, the boundary layer of a body (Pope 2000, Turbulent Flows, Sec. 13.4).
inline constexpr double kDefaultSmagorinskyConstant = 0.1;

/// Storage type of the populations and of the per-cell force (arithmetic is double).
enum class Precision { float32, float64 };

/// Storage of the populations when a run does not choose: float. Every figure of the validation set
/// agrees with double storage within 0.3% (docs/performance.md, "Storage precision"), and a float
/// population moves half the bytes of the memory-bound kernel. Float storage collides in float
/// (aa_kernel.hpp says why that loses nothing); the rigid body and the coupling compute in double.
inline constexpr Precision kDefaultPrecision = Precision::float32;

/// Boundary condition of a face. The first three are set per pair of opposite faces
/// (SolverConfig::boundaries); the open kinds replace that on one face (SolverConfig::open_faces):
/// - velocity: an inlet of prescribed velocity, bounce-back from a wall moving with it (Ladd 1994);
/// - outflow: a pressure outlet, the unknown populations at the equilibrium of density 1 and the
///   velocity of the neighbouring cell (lbm/grid.hpp, pull_source).
enum class Boundary { periodic, no_slip, free_slip, velocity, outflow };

/// One face of the box: `axis` 0-2 and `side` 0 (the lower face, at coordinate -1/2) or 1 (the
/// upper face, at n - 1/2).
struct Face {
  int axis = 2;
  int side = 0;
  bool operator==(const Face&) const = default;
};

/// A face whose kind replaces the pair's: Boundary::velocity or Boundary::outflow.
struct OpenFace {
  Face face;
  Boundary kind = Boundary::outflow;
};

/// The TRT magic parameter that puts half-way bounce-back walls exactly mid-way between nodes for
/// any viscosity (Ginzburg et al. 2008): the default of the solver and of a case.
inline constexpr double kWallExactTrtMagic = 3.0 / 16.0;

/// Everything the factory needs. Axis order of `boundaries` is x, y, z.
struct SolverConfig {
  LatticeKind lattice = LatticeKind::D3Q19;
  CollisionKind collision = CollisionKind::trt;
  /// Double for code that builds a solver directly (the kernel's tests compare it with a reference at
  /// round-off); a run takes kDefaultPrecision through its setup unless its case chooses.
  Precision precision = Precision::float64;
  int nx = 32, ny = 32, nz = 32;  ///< interior cells per axis
  std::array<Boundary, 3> boundaries{Boundary::periodic, Boundary::periodic, Boundary::periodic};
  /// Inlets and outlets, each on a face of a non-periodic axis (at most one entry per face).
  std::vector<OpenFace> open_faces;
  /// Velocity of every velocity face (lattice units; |u| below 0.3 for a Mach number under 0.5).
  Eigen::Vector3d inflow_velocity = Eigen::Vector3d::Zero();
  double tau = 0.8;  ///< relaxation time of the shear viscosity, nu = cs^2 (tau - 1/2)
  /// TRT magic parameter Lambda = (tau+ - 1/2)(tau- - 1/2).
  double magic = kWallExactTrtMagic;
  SubgridModel subgrid = SubgridModel::none;
  double smagorinsky_constant = kDefaultSmagorinskyConstant;  ///< C_S, read with SubgridModel::smagorinsky
  Eigen::Vector3d body_force = Eigen::Vector3d::Zero();       ///< uniform force density
  /// Set when the solver holds one block of a split lattice: nx, ny, nz are then that block's
  /// extent, while `boundaries` and `open_faces` describe the faces of the whole lattice.
  std::optional<BlockSplit> split;
};

/// The kind of each face, [axis][side]: the pair's kind unless an open face replaces it.
using FaceKinds = std::array<std::array<Boundary, 2>, 3>;
FaceKinds face_kinds(const SolverConfig& config);
/// "x-", "x+", "y-", ... for a face; parse_face reads them (settle::InputError naming `what`).
std::string to_string(const Face& face);
Face parse_face(const std::string& name, const std::string& what);

/// Kinematic viscosity of relaxation time tau, nu = cs^2 (tau - 1/2).
double viscosity_from_tau(double tau);
/// Relaxation time giving kinematic viscosity nu (lattice units).
double tau_from_viscosity(double nu);

/// Throws settle::InputError naming the offending field when the configuration is unusable.
void validate(const SolverConfig& config);
/// Throws settle::InputError, naming the case keys, when the collision operator needs a lattice
/// other than `lattice` (the cumulant operator needs D3Q27's 27 moments). Part of validate; the
/// preflight calls it too, before anything is planned.
void check_collision_lattice(CollisionKind collision, LatticeKind lattice);
/// Throws settle::InputError, naming the case keys, when the subgrid model cannot act on the
/// collision operator (the Smagorinsky model is built into BGK, TRT and the recursive regularised
/// operator only). Part of validate; the preflight calls it too.
void check_collision_subgrid(CollisionKind collision, SubgridModel subgrid);

std::string to_string(LatticeKind kind);
std::string to_string(CollisionKind kind);
std::string to_string(Precision kind);
std::string to_string(Boundary kind);
std::string to_string(SubgridModel kind);
/// Parsers for the front end and the case file; throw settle::InputError listing the
/// allowed names. `what` names the flag or key for the message.
LatticeKind parse_lattice(const std::string& name, const std::string& what);
CollisionKind parse_collision(const std::string& name, const std::string& what);
Precision parse_precision(const std::string& name, const std::string& what);
Boundary parse_boundary(const std::string& name, const std::string& what);
SubgridModel parse_subgrid_model(const std::string& name, const std::string& what);

}  // namespace settle::lbm
