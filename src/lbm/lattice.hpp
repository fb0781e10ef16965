#pragma once
// Lattice descriptors D3Q19 and D3Q27 as compile-time constants.
//
// Velocities are ordered as the rest velocity followed by opposite pairs: direction 2k-1 and
// 2k (k >= 1) are each other's opposite. The kernels rely on this pairing (TRT splits each
// pair into symmetric and antisymmetric parts), the boundary lists rely on opposite(). The
// lattice speed of sound is cs^2 = 1/3 for both (dx = dt = 1).
// Weights: Qian, d'Humieres & Lallemand 1992, doi:10.1209/0295-5075/17/6/001.
#include <array>
#include <concepts>
#include <cstddef>

namespace settle::lbm {

inline constexpr double cs2 = 1.0 / 3.0;  ///< lattice speed of sound squared

/// A discrete velocity set. `c[i]` is the integer velocity of direction i, `w[i]` its weight.
template <int Q_>
struct VelocitySet {
  static constexpr int Q = Q_;
  std::array<std::array<int, 3>, Q_> c;
  std::array<double, Q_> w;
};

namespace detail {

// Face, edge and corner neighbours in the pair order described at the top of the file.
inline constexpr std::array<std::array<int, 3>, 27> kVelocities27 = {{
    {0, 0, 0},                                                                 // rest
    {1, 0, 0},  {-1, 0, 0},   {0, 1, 0},  {0, -1, 0},  {0, 0, 1}, {0, 0, -1},  // faces
    {1, 1, 0},  {-1, -1, 0},  {1, -1, 0}, {-1, 1, 0},                          // xy edges
    {1, 0, 1},  {-1, 0, -1},  {1, 0, -1}, {-1, 0, 1},                          // xz edges
    {0, 1, 1},  {0, -1, -1},  {0, 1, -1}, {0, -1, 1},                          // yz edges
    {1, 1, 1},  {-1, -1, -1}, {1, 1, -1}, {-1, -1, 1},                         // corners
    {1, -1, 1}, {-1, 1, -1},  {-1, 1, 1}, {1, -1, -1},
}};

template <int Q>
constexpr VelocitySet<Q> make_velocity_set(double w_rest, double w_face, double w_edge, double w_corner) {
  VelocitySet<Q> set{};
  for (int i = 0; i < Q; ++i) {
    set.c[i] = kVelocities27[i];
    const int nonzero = (set.c[i][0] != 0) + (set.c[i][1] != 0) + (set.c[i][2] != 0);
    set.w[i] = nonzero == 0 ? w_rest : nonzero == 1 ? w_face : nonzero == 2 ? w_edge : w_corner;
  }
  return set;
}

}  // namespace detail

/// D3Q19: rest, 6 faces (1/18), 12 edges (1/36).
struct D3Q19 {
  static constexpr int Q = 19;
  static constexpr const char* name = "D3Q19";
  static constexpr VelocitySet<19> set = detail::make_velocity_set<19>(1.0 / 3.0, 1.0 / 18.0, 1.0 / 36.0, 0.0);
};

/// D3Q27: rest (8/27), 6 faces (2/27), 12 edges (1/54), 8 corners (1/216).
struct D3Q27 {
  static constexpr int Q = 27;
  static constexpr const char* name = "D3Q27";
  static constexpr VelocitySet<27> set = detail::make_velocity_set<27>(8.0 / 27.0, 2.0 / 27.0, 1.0 / 54.0, 1.0 / 216.0);
};

/// The lattice concept used by the kernels: a type with Q and a VelocitySet<Q> `set`.
template <class L>
concept Lattice = requires {
  { L::Q } -> std::convertible_to<int>;
  L::set.c;
  L::set.w;
};

/// Index of the direction opposite to i (pair order: 2k-1 <-> 2k).
constexpr int opposite(int i) { return i == 0 ? 0 : (i % 2 == 1 ? i + 1 : i - 1); }

/// Index of the velocity (cx, cy, cz) in lattice L, or -1 if L does not have it.
template <Lattice L>
constexpr int direction_index(int cx, int cy, int cz) {
  for (int i = 0; i < L::Q; ++i) {
    if (L::set.c[i][0] == cx && L::set.c[i][1] == cy && L::set.c[i][2] == cz) return i;
  }
  return -1;
}

}  // namespace settle::lbm
