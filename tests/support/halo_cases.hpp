#pragma once
// The lattices on which a split must step exactly as the unsplit lattice (tests/lbm/test_halo.cpp in
// one process, tests/parallel/test_mpi_halo.cpp across MPI ranks): every kind of face, uneven
// extents, a smooth initial flow across every block face.
#include <array>
#include <bit>
#include <cmath>
#include <cstdint>
#include <vector>

#include "lbm/solver.hpp"

namespace settle::test::halo {

using lbm::Boundary;

struct FaceSet {
  const char* name;
  std::array<Boundary, 3> boundaries;
  std::vector<lbm::OpenFace> open_faces;
};

inline const std::vector<FaceSet>& face_sets() {
  static const std::vector<FaceSet> sets = {
      {"periodic", {Boundary::periodic, Boundary::periodic, Boundary::periodic}, {}},
      {"no_slip_z", {Boundary::periodic, Boundary::periodic, Boundary::no_slip}, {}},
      {"free_slip_x_no_slip_y", {Boundary::free_slip, Boundary::no_slip, Boundary::periodic}, {}},
      {"channel_inlet_outlet",
       {Boundary::free_slip, Boundary::periodic, Boundary::no_slip},
       {{{2, 0}, Boundary::velocity}, {{2, 1}, Boundary::outflow}}},
  };
  return sets;
}

// Uneven extents, so that blocks differ in size and no block face sits at a symmetric position.
inline lbm::SolverConfig lattice_of(const FaceSet& faces, lbm::LatticeKind lattice, lbm::Precision precision) {
  lbm::SolverConfig cfg;
  cfg.lattice = lattice;
  cfg.precision = precision;
  cfg.collision = lbm::CollisionKind::trt;
  cfg.nx = 7, cfg.ny = 6, cfg.nz = 11;
  cfg.tau = 0.62;
  cfg.boundaries = faces.boundaries;
  cfg.open_faces = faces.open_faces;
  if (!faces.open_faces.empty()) cfg.inflow_velocity = Eigen::Vector3d(0.0, 0.0, 0.04);
  cfg.body_force = Eigen::Vector3d(2e-6, -1e-6, 3e-6);
  return cfg;
}

// A smooth field with flow across every block face (global coordinates).
inline lbm::CellState initial_state(int x, int y, int z) {
  return {1.0 + 0.01 * std::sin(0.9 * x + 0.4 * y) * std::cos(0.3 * z),
          Eigen::Vector3d(0.02 * std::cos(0.5 * y + 0.2 * z), 0.015 * std::sin(0.7 * x - 0.3 * z),
                          0.03 + 0.01 * std::sin(0.6 * x + 0.5 * y))};
}

inline std::uint64_t bits(double v) { return std::bit_cast<std::uint64_t>(v); }

// Populations of a block (its first cell at `offset` of the whole lattice) that differ in any bit
// from the unsplit lattice's.
inline int differing_populations(const lbm::Solver& whole, const lbm::Solver& block, const std::array<int, 3>& offset) {
  int differing = 0;
  std::vector<double> a(static_cast<std::size_t>(whole.velocity_count())), b(a.size());
  for (int z = 0; z < block.nz(); ++z)
    for (int y = 0; y < block.ny(); ++y)
      for (int x = 0; x < block.nx(); ++x) {
        whole.cell_populations(x + offset[0], y + offset[1], z + offset[2], a);
        block.cell_populations(x, y, z, b);
        for (std::size_t i = 0; i < a.size(); ++i) differing += bits(a[i]) != bits(b[i]);
      }
  return differing;
}

}  // namespace settle::test::halo
