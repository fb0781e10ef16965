#include "lbm/config.hpp"

#include <fmt/format.h>

#include <cmath>

#include "common/error.hpp"
#include "lbm/lattice.hpp"

namespace settle::lbm {

double viscosity_from_tau(double tau) { return cs2 * (tau - 0.5); }
double tau_from_viscosity(double nu) { return nu / cs2 + 0.5; }

void validate(const SolverConfig& config) {
  const auto check_extent = [](int n, const char* name) {
    if (n < 1) throw InputError(fmt::format("lbm.{}: must be >= 1, got {}", name, n));
  };
  check_extent(config.nx, "nx");
  check_extent(config.ny, "ny");
  check_extent(config.nz, "nz");
  if (!(config.tau > 0.5) || !std::isfinite(config.tau)) {
    throw InputError(fmt::format("lbm.tau: must be > 0.5 (positive viscosity), got {}", config.tau));
  }
  if (config.collision == CollisionKind::trt && !(config.magic > 0.0 && std::isfinite(config.magic))) {
    throw InputError(fmt::format("lbm.magic: must be > 0, got {}", config.magic));
  }
  if (!config.body_force.allFinite()) {
    throw InputError("lbm.body_force: must be finite");
  }
}

std::string to_string(LatticeKind kind) {
  return kind == LatticeKind::D3Q19 ? "D3Q19" : "D3Q27";
}

std::string to_string(CollisionKind kind) {
  switch (kind) {
    case CollisionKind::bgk: return "bgk";
    case CollisionKind::trt: return "trt";
    case CollisionKind::recursive_regularized: return "rr";
  }
  return "?";
}

std::string to_string(Precision kind) { return kind == Precision::float32 ? "float" : "double"; }

std::string to_string(Boundary kind) {
  switch (kind) {
    case Boundary::periodic: return "periodic";
    case Boundary::no_slip: return "no-slip";
    case Boundary::free_slip: return "free-slip";
  }
  return "?";
}

LatticeKind parse_lattice(const std::string& name, const std::string& what) {
  if (name == "D3Q19" || name == "d3q19") return LatticeKind::D3Q19;
  if (name == "D3Q27" || name == "d3q27") return LatticeKind::D3Q27;
  throw InputError(fmt::format("{}: must be D3Q19 or D3Q27, got '{}'", what, name));
}

CollisionKind parse_collision(const std::string& name, const std::string& what) {
  if (name == "bgk") return CollisionKind::bgk;
  if (name == "trt") return CollisionKind::trt;
  // The case schema's spelling is recursive_regularized; rr is the short name bench prints.
  if (name == "recursive_regularized" || name == "rr" || name == "recursive-regularized") {
    return CollisionKind::recursive_regularized;
  }
  throw InputError(fmt::format("{}: must be bgk, trt or recursive_regularized (rr), got '{}'",
                               what, name));
}

Precision parse_precision(const std::string& name, const std::string& what) {
  if (name == "double") return Precision::float64;
  if (name == "float") return Precision::float32;
  throw InputError(fmt::format("{}: must be double or float, got '{}'", what, name));
}

Boundary parse_boundary(const std::string& name, const std::string& what) {
  if (name == "periodic") return Boundary::periodic;
  if (name == "no-slip") return Boundary::no_slip;
  if (name == "free-slip") return Boundary::free_slip;
  throw InputError(
      fmt::format("{}: must be periodic, no-slip or free-slip, got '{}'", what, name));
}

}  // namespace settle::lbm
