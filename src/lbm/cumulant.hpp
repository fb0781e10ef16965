#pragma once
// The cumulant collision operator on D3Q27: Geier, Schoenherr, Pasquali & Krafczyk 2015, "The
// cumulant lattice Boltzmann equation in three dimensions: theory and validation", Comput. Math.
// Appl. 70, 507-547, doi:10.1016/j.camwa.2015.05.001 (below "G15").
//
// One collision:
//  1. density and velocity u = (sum f c + F/2) / rho (G15's half-force shift; Guo's velocity);
//  2. central moments kappa_abg = sum f (c_x - u_x)^a (c_y - u_y)^b (c_z - u_z)^g, a, b, g in
//     {0, 1, 2}, by the forward Chimera transform: three passes of a one-dimensional transform
//     along z, then y, then x (G15, Appendix J);
//  3. cumulants from central moments and their relaxation: the deviatoric second-order cumulants
//     C200 - C020, C200 - C002, C110, C101, C011 with omega_1 = 1/tau (shear viscosity
//     nu = cs^2 (tau - 1/2), as for the other operators), the trace C200 + C020 + C002 with
//     omega_2 = 1 (bulk viscosity 1/9, as the recursive regularised operator's), and every
//     cumulant of order 3 to 6 with rate 1;
//  4. post-collision central moments from the cumulants, first-order ones set to +F/2;
//  5. backward Chimera transform (x, y, z passes) to populations.
//
// Representation: the kernels pass g = f - w (collision.hpp), which is G15's "well-conditioned"
// form (Appendix J). The D3Q27 weights factorise into one-dimensional weights (1/6, 2/3, 1/6),
// so each line of a Chimera pass carries a known rest part K (the weights' share of that line);
// the pass adds it back only where the velocity multiplies it, and the moments it produces are
// the central moments of f less the raw moments of w (1/3 per squared direction). Every stored
// and intermediate value is thus a deviation from rest, and nothing of O(1) cancels in float.
//
// Relaxation with rate 1 takes a cumulant to its equilibrium value, zero for orders 3 to 6,
// whatever its value before: the pre-collision cumulants of those orders are therefore not formed
// (the post-collision ones are zero), and the forward transform keeps only what orders 0-2 need
// (the compiler drops the rest). The post-collision central moments are then
// those of the second-order cumulants alone: with k_ab = kappa_ab / rho and zero cumulants above
// order 2, kappa_3 = kappa_5 = 0 and, by G15's relations between cumulants and central moments,
//   kappa_220 = rho (k_xx k_yy + 2 k_xy^2),   kappa_211 = rho (k_xx k_yz + 2 k_xy k_xz),
//   kappa_222 = rho (k_xx k_yy k_zz + 2 (k_xx k_yz^2 + k_yy k_xz^2 + k_zz k_xy^2) + 8 k_xy k_xz k_yz),
// and their permutations.
//
// Second order with G15's correction of D3Q27's cubic-velocity defect (G15, Appendix H; in the
// form of Geier, Pasquali & Schoenherr 2017, doi:10.1016/j.jcp.2017.05.040, Eqs. 27-35): the
// lattice's third moments c_x^3 = c_x cannot carry the Maxwellian's rho u_x^3, which adds
// 3 nu rho u_x^2 d_x u_x to the normal stresses; the relaxation subtracts it again with the
// velocity gradients estimated from the pre-collision second-order cumulants,
//   rho d_x u_x = -omega_1/2 (Dxy + Dxz) + omega_2/2 (drho - T),  with Dxy = C200 - C020,
//   Dxz = C200 - C002, T = C200 + C020 + C002 (the well-conditioned values),
//   rho d_y u_y = rho d_x u_x + 3/2 omega_1 Dxy,  rho d_z u_z = rho d_x u_x + 3/2 omega_1 Dxz,
//   Dxy* = (1 - omega_1) Dxy - 3 (1 - omega_1/2) (u_x^2 rho d_x u_x - u_y^2 rho d_y u_y),
//   Dxz* likewise, and
//   T* = drho + (1 - omega_2) (T - drho)
//        - 3 (1 - omega_2/2) (u_x^2 rho d_x u_x + u_y^2 rho d_y u_y + u_z^2 rho d_z u_z).
//
// Forcing (G15, Eq. 42, the velocity shift, and Eqs. 85-87): with u shifted by F/(2 rho) the
// pre-collision first-order central moments are -F/2; the collision sets them to +F/2, so a cell
// gains momentum F per step exactly, and the second-order moments take Guo's forcing term
// (1 - omega/2)(u F + F u) (collision.hpp) to second order. Approximation (G15's): the
// relations between cumulants and central moments are those of zero first-order moments, which
// neglects O(F^2) terms in the moments of order 3 and above.
#include <array>

#include "lbm/collision.hpp"
#include "lbm/lattice.hpp"

namespace settle::lbm {

namespace cumulant_detail {

/// Index of the moment (or population) (a, b, c) in the work array.
constexpr int at(int a, int b, int c) { return a + 3 * b + 9 * c; }

/// D3Q27 index of the velocity (a - 1, b - 1, c - 1), a, b, c in {0, 1, 2}, at [at(a, b, c)]: a
/// table built at compile time, so that the unrolled loops index it with constants (a call of
/// direction_index there would be a search loop at run time, which stops the kernel's vectorisation).
inline constexpr std::array<int, 27> kDirection = [] {
  std::array<int, 27> table{};
  for (int c = 0; c < 3; ++c)
    for (int b = 0; b < 3; ++b)
      for (int a = 0; a < 3; ++a) table[at(a, b, c)] = direction_index<D3Q27>(a - 1, b - 1, c - 1);
  return table;
}();

/// One-dimensional weights of the velocities -1, 0, 1: the D3Q27 weight of (a, b, c) is their product.
inline constexpr double kWeight1d[3] = {1.0 / 6.0, 2.0 / 3.0, 1.0 / 6.0};
/// Raw moments of order 0, 1, 2 of the one-dimensional weights: sum w, sum w c, sum w c^2.
inline constexpr double kRestMoment1d[3] = {1.0, 0.0, 1.0 / 3.0};

/// Forward Chimera step on one line of three values (velocities -1, 0, 1), each shifted by its rest
/// part; `rest` is the rest parts' sum. In place: the zeroth moment (shifted), and the first and
/// second moments about u of the unshifted values, the second less the rest parts' own, rest/3.
/// `rest` is a compile-time constant after unrolling, so the branch on it folds.
template <class T>
SETTLE_LBM_INLINE void forward_line(T& lo, T& mid, T& hi, T u, double rest) {
  const T sum = hi + lo, diff = hi - lo;
  const T m0 = sum + mid;
  const T mass = rest == 0.0 ? m0 : m0 + T(rest);
  lo = m0;
  mid = diff - u * mass;
  hi = sum - u * (diff + mid);
}

/// The inverse of forward_line: raw moments s1 = kappa_1 + u M, s2 = kappa_2 + 2 u kappa_1 + u^2 M
/// (M the full zeroth moment), then the three values. Entries the caller knows to be zero are
/// skipped at compile time (IEEE rules forbid the compiler from dropping 0.0 + x itself): kNoFirst
/// for kappa_1 = 0, kNoSecond for kappa_2 = 0, kNoZeroth for a zeroth moment that is zero with no
/// rest part.
enum LineZeros : unsigned { kNone = 0, kNoZeroth = 1, kNoFirst = 2, kNoSecond = 4 };

template <unsigned Zeros, class T>
SETTLE_LBM_INLINE void backward_line(T& lo, T& mid, T& hi, T u, double rest) {
  const T m0 = lo;
  T s1, s2;
  if constexpr ((Zeros & kNoZeroth) != 0) {  // and no rest part: M = 0
    s1 = mid;
    s2 = (Zeros & kNoSecond) != 0 ? T(2.0) * u * mid : hi + T(2.0) * u * mid;
  } else {
    const T mass = rest == 0.0 ? m0 : m0 + T(rest);
    if constexpr ((Zeros & kNoFirst) != 0) {
      s1 = u * mass;
      s2 = (Zeros & kNoSecond) != 0 ? u * s1 : hi + u * s1;
    } else {
      s1 = mid + u * mass;
      s2 = (Zeros & kNoSecond) != 0 ? u * (mid + s1) : hi + u * (mid + s1);
    }
  }
  lo = T(0.5) * (s2 - s1);
  hi = T(0.5) * (s2 + s1);
  mid = (Zeros & kNoZeroth) != 0 ? -s2 : m0 - s2;
}

}  // namespace cumulant_detail

/// See the top of this file. D3Q27 only: the Chimera transform and the cumulants need all 27
/// moments (lbm::validate refuses D3Q19).
struct Cumulant {
  static constexpr const char* name = "cumulant";

  template <Lattice L, class T>
  static SETTLE_LBM_INLINE void collide(T* g, const T* F, const RelaxationRates& r) {
    static_assert(L::Q == 27, "the cumulant operator needs D3Q27");
    T m[27];
    T drho, rho, inv_rho, u[3];
    forward_z_and_moments(g, F, m, drho, rho, inv_rho, u);
    forward_yx(m, u);
    relax_and_rebuild(m, F, r, drho, rho, inv_rho, u);
    backward(m, u, g);
  }

 private:
  /// The z pass, fused with the density and momentum (which the pass's line sums give).
  template <class T>
  static SETTLE_LBM_INLINE void forward_z_and_moments(const T* g, const T* F, T (&m)[27], T& drho, T& rho, T& inv_rho,
                                                      T (&u)[3]) {
    using namespace cumulant_detail;
    T sum[9], diff[9], m0[9];
#pragma GCC unroll 9
    for (int n = 0; n < 9; ++n) {
      const int a = n % 3, b = n / 3;
      const T lo = g[kDirection[at(a, b, 0)]], mid = g[kDirection[at(a, b, 1)]], hi = g[kDirection[at(a, b, 2)]];
      sum[n] = hi + lo;
      diff[n] = hi - lo;
      m0[n] = sum[n] + mid;
    }
    // Rows summed first: shorter dependency chains than one running sum.
    const T row0 = m0[0] + m0[1] + m0[2], row1 = m0[3] + m0[4] + m0[5], row2 = m0[6] + m0[7] + m0[8];
    drho = row0 + row1 + row2;
    const T jx = (m0[2] - m0[0]) + (m0[5] - m0[3]) + (m0[8] - m0[6]);
    const T jy = row2 - row0;
    const T jz = (diff[0] + diff[1] + diff[2]) + (diff[3] + diff[4] + diff[5]) + (diff[6] + diff[7] + diff[8]);
    rho = T(1.0) + drho;
    inv_rho = T(1.0) / rho;
    u[0] = (jx + T(0.5) * F[0]) * inv_rho;
    u[1] = (jy + T(0.5) * F[1]) * inv_rho;
    u[2] = (jz + T(0.5) * F[2]) * inv_rho;
#pragma GCC unroll 9
    for (int n = 0; n < 9; ++n) {
      const int a = n % 3, b = n / 3;
      const double rest = kWeight1d[a] * kWeight1d[b];
      const T mass = m0[n] + T(rest);
      const T first = diff[n] - u[2] * mass;
      m[at(a, b, 0)] = m0[n];
      m[at(a, b, 1)] = first;
      m[at(a, b, 2)] = sum[n] - u[2] * (diff[n] + first);
    }
  }

  /// The y and x passes of the forward transform.
  template <class T>
  static SETTLE_LBM_INLINE void forward_yx(T (&m)[27], const T (&u)[3]) {
    using namespace cumulant_detail;
#pragma GCC unroll 9
    for (int n = 0; n < 9; ++n) {
      const int a = n % 3, c = n / 3;
      forward_line(m[at(a, 0, c)], m[at(a, 1, c)], m[at(a, 2, c)], u[1], kWeight1d[a] * kRestMoment1d[c]);
    }
#pragma GCC unroll 9
    for (int n = 0; n < 9; ++n) {
      const int b = n % 3, c = n / 3;
      forward_line(m[at(0, b, c)], m[at(1, b, c)], m[at(2, b, c)], u[0], kRestMoment1d[b] * kRestMoment1d[c]);
    }
  }

  /// Relaxation of the second-order cumulants and the post-collision central moments of every
  /// order, written over m (x-exponent, y-exponent, z-exponent).
  template <class T>
  static SETTLE_LBM_INLINE void relax_and_rebuild(T (&m)[27], const T* F, const RelaxationRates& r, T drho, T rho,
                                                  T inv_rho, const T (&u)[3]) {
    using cumulant_detail::at;
    const T omega = T(r.omega_plus);
    constexpr double omega_bulk = 1.0;  // G15's omega_2: bulk viscosity cs^2 (1/omega_2 - 1/2) * 2/3 = 1/9
    const T k200 = m[at(2, 0, 0)], k020 = m[at(0, 2, 0)], k002 = m[at(0, 0, 2)];
    const T dxy = k200 - k020, dxz = k200 - k002, trace = k200 + k020 + k002;
    // rho times the velocity gradients (G15, Appendix H).
    const T rdxux = T(-0.5) * omega * (dxy + dxz) + T(0.5 * omega_bulk) * (drho - trace);
    const T rdyuy = rdxux + T(1.5) * omega * dxy;
    const T rdzuz = rdxux + T(1.5) * omega * dxz;
    const T ux2 = u[0] * u[0], uy2 = u[1] * u[1], uz2 = u[2] * u[2];
    const T defect_x = ux2 * rdxux, defect_y = uy2 * rdyuy, defect_z = uz2 * rdzuz;
    const T keep = T(1.0) - omega, correct = T(-3.0) * (T(1.0) - T(0.5) * omega);
    const T dxy_post = keep * dxy + correct * (defect_x - defect_y);
    const T dxz_post = keep * dxz + correct * (defect_x - defect_z);
    // The trace's departure from its equilibrium drho after relaxation with omega_2 = 1: the
    // (1 - omega_2) (T - drho) term is zero and omitted.
    const T trace_excess = T(-3.0 * (1.0 - 0.5 * omega_bulk)) * (defect_x + defect_y + defect_z);
    const T p = keep * m[at(1, 1, 0)], q = keep * m[at(1, 0, 1)], s = keep * m[at(0, 1, 1)];  // xy, xz, yz
    // Normalised deviations from rest, k_aa - 1/3 and k_ab, of the post-collision state.
    const T third = T(1.0 / 3.0);
    const T dev_a = third * (dxy_post + dxz_post + trace_excess);  // kappa_200 - rho/3
    const T dev_b = third * (trace_excess - T(2.0) * dxy_post + dxz_post);
    const T dev_c = third * (trace_excess + dxy_post - T(2.0) * dxz_post);
    const T da = dev_a * inv_rho, db = dev_b * inv_rho, dc = dev_c * inv_rho;
    const T P = p * inv_rho, Q = q * inv_rho, S = s * inv_rho;
    const T drho_3 = third * drho, drho_9 = T(1.0 / 9.0) * drho;
    const T xx = third + da, yy = third + db, zz = third + dc;  // k_xx, k_yy, k_zz
    // Orders 0-2: density, +F/2 (forcing), the relaxed second order (well-conditioned: kappa_aa - 1/3).
    m[at(0, 0, 0)] = drho;
    m[at(1, 0, 0)] = T(0.5) * F[0];
    m[at(0, 1, 0)] = T(0.5) * F[1];
    m[at(0, 0, 1)] = T(0.5) * F[2];
    m[at(2, 0, 0)] = drho_3 + dev_a;
    m[at(0, 2, 0)] = drho_3 + dev_b;
    m[at(0, 0, 2)] = drho_3 + dev_c;
    m[at(1, 1, 0)] = p;
    m[at(1, 0, 1)] = q;
    m[at(0, 1, 1)] = s;
    // Order 4: kappa_211 = rho (k_xx k_yz + 2 k_xy k_xz);
    // kappa_220 - 1/9 = drho/9 + rho ((da + db)/3 + da db) + 2 rho k_xy^2.
    m[at(2, 1, 1)] = xx * s + T(2.0) * p * Q;
    m[at(1, 2, 1)] = yy * q + T(2.0) * p * S;
    m[at(1, 1, 2)] = zz * p + T(2.0) * q * S;
    m[at(2, 2, 0)] = drho_9 + rho * (third * (da + db) + da * db) + T(2.0) * p * P;
    m[at(2, 0, 2)] = drho_9 + rho * (third * (da + dc) + da * dc) + T(2.0) * q * Q;
    m[at(0, 2, 2)] = drho_9 + rho * (third * (db + dc) + db * dc) + T(2.0) * s * S;
    // Order 6, less its rest value 1/27.
    const T dd = da * db + da * dc + db * dc;
    m[at(2, 2, 2)] = T(1.0 / 27.0) * drho + rho * (T(1.0 / 9.0) * (da + db + dc) + third * dd + da * db * dc) +
                     T(2.0) * (xx * s * S + yy * q * Q + zz * p * P) + T(8.0) * p * Q * S;
    // Orders 3 and 5 are zero: the backward x pass skips them (its kNoFirst / kNoZeroth lines).
  }

  /// Backward Chimera transform, x then y then z, into the populations.
  template <class T>
  static SETTLE_LBM_INLINE void backward(T (&m)[27], const T (&u)[3], T* g) {
    using namespace cumulant_detail;
    // x pass: each line (b, c) holds the moments (0, b, c), (1, b, c), (2, b, c); third- and
    // fifth-order entries are zero.
    const T ux = u[0];
    backward_line<kNone>(m[at(0, 0, 0)], m[at(1, 0, 0)], m[at(2, 0, 0)], ux, 1.0);
    backward_line<kNoSecond>(m[at(0, 1, 0)], m[at(1, 1, 0)], m[at(2, 1, 0)], ux, 0.0);
    backward_line<kNoFirst>(m[at(0, 2, 0)], m[at(1, 2, 0)], m[at(2, 2, 0)], ux, 1.0 / 3.0);
    backward_line<kNoSecond>(m[at(0, 0, 1)], m[at(1, 0, 1)], m[at(2, 0, 1)], ux, 0.0);
    backward_line<kNoFirst>(m[at(0, 1, 1)], m[at(1, 1, 1)], m[at(2, 1, 1)], ux, 0.0);
    backward_line<kNoZeroth | kNoSecond>(m[at(0, 2, 1)], m[at(1, 2, 1)], m[at(2, 2, 1)], ux, 0.0);
    backward_line<kNoFirst>(m[at(0, 0, 2)], m[at(1, 0, 2)], m[at(2, 0, 2)], ux, 1.0 / 3.0);
    backward_line<kNoZeroth | kNoSecond>(m[at(0, 1, 2)], m[at(1, 1, 2)], m[at(2, 1, 2)], ux, 0.0);
    backward_line<kNoFirst>(m[at(0, 2, 2)], m[at(1, 2, 2)], m[at(2, 2, 2)], ux, 1.0 / 9.0);
#pragma GCC unroll 9
    for (int n = 0; n < 9; ++n) {
      const int a = n % 3, c = n / 3;
      backward_line<kNone>(m[at(a, 0, c)], m[at(a, 1, c)], m[at(a, 2, c)], u[1], kWeight1d[a] * kRestMoment1d[c]);
    }
#pragma GCC unroll 9
    for (int n = 0; n < 9; ++n) {
      const int a = n % 3, b = n / 3;
      T lo = m[at(a, b, 0)], mid = m[at(a, b, 1)], hi = m[at(a, b, 2)];
      backward_line<kNone>(lo, mid, hi, u[2], kWeight1d[a] * kWeight1d[b]);
      g[kDirection[at(a, b, 0)]] = lo;
      g[kDirection[at(a, b, 1)]] = mid;
      g[kDirection[at(a, b, 2)]] = hi;
    }
  }
};

}  // namespace settle::lbm
