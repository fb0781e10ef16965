#pragma once
// Run-time configuration of the fluid solver (lattice units throughout: dx = dt = 1,
// reference density 1).
#include <Eigen/Core>
#include <array>
#include <string>

namespace settle::lbm {

enum class LatticeKind { D3Q19, D3Q27 };

/// Collision operator.
/// - bgk: single relaxation time (Bhatnagar, Gross & Krook 1954).
/// - trt: two relaxation times with a fixed magic parameter (Ginzburg et al. 2008).
/// - recursive_regularized: Hermite-regularised BGK with the third-order non-equilibrium
///   moments rebuilt recursively (Malaspinas 2015; Coreixas et al. 2017): stable close to
///   tau = 1/2.
enum class CollisionKind { bgk, trt, recursive_regularized };

/// Storage type of the populations and of the per-cell force (arithmetic is double).
enum class Precision { float32, float64 };

/// Boundary condition of one pair of opposite faces.
enum class Boundary { periodic, no_slip, free_slip };

/// Everything the factory needs. Axis order of `boundaries` is x, y, z.
struct SolverConfig {
  LatticeKind lattice = LatticeKind::D3Q19;
  CollisionKind collision = CollisionKind::trt;
  Precision precision = Precision::float64;
  int nx = 32, ny = 32, nz = 32;  ///< interior cells per axis
  std::array<Boundary, 3> boundaries{Boundary::periodic, Boundary::periodic, Boundary::periodic};
  double tau = 0.8;  ///< relaxation time of the shear viscosity, nu = cs^2 (tau - 1/2)
  /// TRT magic parameter Lambda = (tau+ - 1/2)(tau- - 1/2). 3/16 puts half-way bounce-back
  /// walls exactly mid-way between nodes for any viscosity (Ginzburg et al. 2008).
  double magic = 3.0 / 16.0;
  Eigen::Vector3d body_force = Eigen::Vector3d::Zero();  ///< uniform force density
};

/// Kinematic viscosity of relaxation time tau, nu = cs^2 (tau - 1/2).
double viscosity_from_tau(double tau);
/// Relaxation time giving kinematic viscosity nu (lattice units).
double tau_from_viscosity(double nu);

/// Throws settle::InputError naming the offending field when the configuration is unusable.
void validate(const SolverConfig& config);

std::string to_string(LatticeKind kind);
std::string to_string(CollisionKind kind);
std::string to_string(Precision kind);
std::string to_string(Boundary kind);
/// Parsers for the front end and the case file; throw settle::InputError listing the
/// allowed names. `what` names the flag or key for the message.
LatticeKind parse_lattice(const std::string& name, const std::string& what);
CollisionKind parse_collision(const std::string& name, const std::string& what);
Precision parse_precision(const std::string& name, const std::string& what);
Boundary parse_boundary(const std::string& name, const std::string& what);

}  // namespace settle::lbm
