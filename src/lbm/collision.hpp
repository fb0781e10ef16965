#pragma once
// Collision operators with second-order Guo forcing, on one cell, in arithmetic type T:
// double for double storage, float for float storage (see AaSolver: with the shifted
// populations below float arithmetic loses nothing that float storage keeps, and halves the
// work per vector).
//
// Representation: the kernels store and pass the shifted populations g_i = f_i - w_i (the
// deviation from the rest equilibrium at density 1). The density is rho = 1 + sum g_i and
// the momentum sum f_i c_i = sum g_i c_i. Subtracting the O(1) part keeps ~3 more
// significant digits in float storage (the same idea as FluidX3D's DDF shifting; Lehmann
// 2022) and makes the entering rest fluid of the moving window exactly zero. Differences
// f - f_eq, and hence all collision formulas, are unchanged by the shift.
//
// Forcing: Guo, Zheng & Shi 2002, doi:10.1103/PhysRevE.65.046308. Velocity
// u = (sum f c + F/2) / rho, source
//   S_i = w_i [ (c_i - u).F / cs^2 + (c_i.u)(c_i.F) / cs^4 ],
// added as (1 - omega/2) S_i for BGK, split into symmetric/antisymmetric parts with the
// matching rates for TRT, and as S_i/2 after the regularised relaxation (see RR below).
//
// Every function is force-inlined and loops over the compile-time velocity set with full
// unrolling, so that inside the kernel's vectorised loop (`GCC ivdep`, lbm/aa_kernel.hpp) each
// lattice constant folds away.
#include <array>
#include <cmath>

#include "lbm/lattice.hpp"

#define SETTLE_LBM_INLINE inline __attribute__((always_inline))

namespace settle::lbm {

/// What the operators' Smagorinsky variants (`Smagorinsky<Operator>`) read besides the rates, the
/// same for every cell; the plain operators ignore it.
struct SmagorinskyConstants {
  double tau0 = 1.0;       ///< relaxation time of the molecular viscosity, nu0 = cs^2 (tau0 - 1/2)
  double factor = 0.0;     ///< 18 sqrt(2) C_S^2 (smagorinsky_tau)
  double trt_magic = 0.0;  ///< TRT: Lambda, held per cell while omega_plus follows tau_eff
};

/// Relaxation rates. omega_plus = 1/tau relaxes the symmetric (even) moments and sets the
/// shear viscosity nu = cs^2 (1/omega_plus - 1/2); omega_minus relaxes the antisymmetric
/// (odd) moments (TRT only).
struct RelaxationRates {
  double omega_plus = 1.0;
  double omega_minus = 1.0;
  SmagorinskyConstants smagorinsky{};
};

/// TRT rates of relaxation time tau and magic parameter Lambda = (tau+ - 1/2)(tau- - 1/2)
/// (Ginzburg, Verhaeghe & d'Humieres 2008, doi:10.4208/cicp.2008.v3.p427).
inline RelaxationRates trt_rates(double tau, double magic) {
  const double tau_minus = magic / (tau - 0.5) + 0.5;
  return {1.0 / tau, 1.0 / tau_minus};
}

/// The constants of the Smagorinsky model for molecular relaxation time tau0, constant C_S (filter
/// width Delta = dx) and, for TRT, magic parameter Lambda.
inline SmagorinskyConstants smagorinsky_constants(double tau0, double constant, double magic) {
  return {tau0, 18.0 * std::sqrt(2.0) * constant * constant, magic};
}

/// Smagorinsky subgrid model in the lattice Boltzmann form of Hou, Sterling, Chen and Doolen
/// (1996, "A lattice Boltzmann subgrid model for high Reynolds number flows", Fields Inst.
/// Commun. 6, 151-166): the relaxation time of the shear moments, per cell, that adds the eddy
/// viscosity nu_t = (C_S Delta)^2 |S|, |S| = sqrt(2 S:S) (Smagorinsky 1963, Mon. Weather Rev. 91,
/// 99-164), Delta = dx = 1.
///
/// Derivation. The Chapman-Enskog expansion gives the non-equilibrium momentum flux (with
/// Guo's correction, RecursiveRegularized's a2) as Pi_neq = -2 rho cs^2 tau S at the relaxation
/// time tau the cell actually uses, so |S| = |Pi_neq| / (sqrt(2) rho cs^2 tau), |Pi_neq| =
/// sqrt(Pi_ab Pi_ab). With cs^2 (tau - tau0) = nu_t = C_S^2 |S| at tau = tau_eff:
///   tau_eff^2 - tau0 tau_eff - C_S^2 |Pi_neq| / (sqrt(2) rho cs^4) = 0,
///   tau_eff = (tau0 + sqrt(tau0^2 + 18 sqrt(2) C_S^2 |Pi_neq| / rho)) / 2
/// (the positive root; 4 / (sqrt(2) cs^4) = 18 sqrt(2)). Explicit: no iteration, no neighbour.
/// Approximations: S is the whole strain rate, its trace div(u) included (O(Ma^2) here), as in
/// Hou et al. (under RecursiveRegularized, whose trace relaxes at rate 1, that part of a2 is
/// -2 rho cs^2 div(u) instead); the eddy viscosity acts everywhere, next to walls too (no van
/// Driest damping); Delta is the lattice spacing whatever the flow's scales.
template <class T>
SETTLE_LBM_INLINE T smagorinsky_tau(const SmagorinskyConstants& k, T pi_neq_squared, T rho) {
  const T tau0 = T(k.tau0);
  return T(0.5) * (tau0 + std::sqrt(tau0 * tau0 + T(k.factor) * std::sqrt(pi_neq_squared) / rho));
}

/// Pi_ab Pi_ab of a symmetric tensor given by its six components.
template <class T>
SETTLE_LBM_INLINE T symmetric_squared_norm(T xx, T yy, T zz, T xy, T xz, T yz) {
  return xx * xx + yy * yy + zz * zz + T(2.0) * (xy * xy + xz * xz + yz * yz);
}

/// Pi_neq:Pi_neq of the Guo-corrected non-equilibrium momentum flux a2 = Pi - Pi_eq + (u F + F u)/2
/// (RecursiveRegularized's a2), from the second moments pi = {xx, yy, zz, xy, xz, yz} of the shifted
/// populations, for which Pi_eq = cs^2 drho I + rho u u.
template <class T>
SETTLE_LBM_INLINE T guo_non_equilibrium_flux_squared(const T (&pi)[6], T drho, T rho, T ux, T uy, T uz, const T* F) {
  const T iso = T(cs2) * drho;
  return symmetric_squared_norm(pi[0] - iso - rho * ux * ux + ux * F[0], pi[1] - iso - rho * uy * uy + uy * F[1],
                                pi[2] - iso - rho * uz * uz + uz * F[2],
                                pi[3] - rho * ux * uy + T(0.5) * (ux * F[1] + uy * F[0]),
                                pi[4] - rho * ux * uz + T(0.5) * (ux * F[2] + uz * F[0]),
                                pi[5] - rho * uy * uz + T(0.5) * (uy * F[2] + uz * F[1]));
}

/// TRT's odd rate for a shear rate 1/tau at fixed Lambda: 1 / (Lambda / (tau - 1/2) + 1/2), with one
/// division.
template <class T>
SETTLE_LBM_INLINE T trt_omega_minus(T tau, T magic) {
  const T excess = tau - T(0.5);
  return excess / (magic + T(0.5) * excess);
}

/// Density deviation, velocity (Guo's half-force correction included) of one cell.
template <Lattice L, class T = double>
struct Macroscopic {
  T drho, rho, ux, uy, uz;
};

template <Lattice L, class T = double>
SETTLE_LBM_INLINE Macroscopic<L, T> macroscopic(const T* g, const T* F) {
  T drho = T(0.0), jx = T(0.0), jy = T(0.0), jz = T(0.0);
#pragma GCC unroll 32
  for (int i = 0; i < L::Q; ++i) {
    drho += g[i];
    jx += T(L::set.c[i][0]) * g[i];
    jy += T(L::set.c[i][1]) * g[i];
    jz += T(L::set.c[i][2]) * g[i];
  }
  const T rho = T(1.0) + drho;
  const T inv_rho = T(1.0) / rho;
  return {drho, rho, (jx + T(0.5) * F[0]) * inv_rho, (jy + T(0.5) * F[1]) * inv_rho, (jz + T(0.5) * F[2]) * inv_rho};
}

/// Shifted second-order equilibrium g_eq_i = f_eq_i - w_i.
template <Lattice L>
SETTLE_LBM_INLINE double shifted_equilibrium(int i, double drho, double rho, double ux, double uy, double uz) {
  const auto& c = L::set.c[i];
  const double cu = c[0] * ux + c[1] * uy + c[2] * uz;
  const double usq = ux * ux + uy * uy + uz * uz;
  return L::set.w[i] * (drho + rho * (3.0 * cu + 4.5 * cu * cu - 1.5 * usq));
}

/// c.v for a lattice velocity c with components in {-1, 0, 1}, written so that after
/// unrolling no multiply by 0 or add of 0.0 is emitted (IEEE rules forbid the compiler from
/// dropping `0.0 + x` itself, because of signed zeros).
template <class T>
SETTLE_LBM_INLINE T lattice_dot(const std::array<int, 3>& c, T x, T y, T z) {
  T v = T(0.0);
  bool started = false;
  const T comp[3] = {x, y, z};
  for (int a = 0; a < 3; ++a) {
    if (c[a] == 0) continue;
    const T term = c[a] > 0 ? comp[a] : -comp[a];
    v = started ? v + term : term;
    started = true;
  }
  return v;
}

/// acc += c * value for c in {-1, 0, 1}, with the first non-zero term assigned, not added.
template <class T>
SETTLE_LBM_INLINE void accumulate(T& acc, bool& started, int c, T value) {
  if (c == 0) return;
  const T term = c > 0 ? value : -value;
  acc = started ? acc + term : term;
  started = true;
}

/// Two relaxation times (Ginzburg 2005, doi:10.1016/j.advwatres.2005.03.004; Ginzburg,
/// Verhaeghe & d'Humieres 2008). For each opposite pair (i, o): symmetric parts
/// g+ = (g_i + g_o)/2 relax with omega+, antisymmetric g- = (g_i - g_o)/2 with omega-:
///   g*_i = g_i + omega+ (geq+ - g+) + omega- (geq- - g-) + (1 - omega+/2) S+ + (1 - omega-/2) S-
/// with geq+ = w [drho + rho (9/2 (c.u)^2 - 3/2 u.u)], geq- = 3 w rho c.u. Guo's source
/// splits likewise, S+ = w [-u.F/cs^2 + (c.u)(c.F)/cs^4], S- = w (c.F)/cs^2, each with the
/// factor of its own rate, which keeps the forcing second order for any omega- (the
/// symmetric/antisymmetric split of Guo's term, e.g. Seta 2013, doi:10.1103/PhysRevE.87.063304).
///
/// Cost: the code works on pair sums s = g_i + g_o and differences d = g_i - g_o (which also
/// give the moments cheaply) and groups the per-cell factors so that terms sharing a weight
/// are computed once (the compiler merges the identical w * factor products):
///   g*_i + g*_o = 2 [w A + c.u (w B c.u + 9 w (1 - omega+/2) c.F) + (1 - omega+)/2 s],
///   g*_i - g*_o = 2 [w D c.u + 3 w (1 - omega-/2) c.F + (1 - omega-)/2 d],
///   A = omega+ (drho - 3/2 rho u.u) - 3 (1 - omega+/2) u.F,  B = 9/2 omega+ rho,  D = 3 omega- rho.
///
/// With kSmagorinsky the rates are set per cell: omega+ = 1 / tau_eff (smagorinsky_tau) from the
/// second moments of the pair sums, and omega- from tau_eff at the fixed magic parameter Lambda
/// (r.smagorinsky.trt_magic), so that Lambda, and with it the place of half-way bounce-back walls
/// (Ginzburg et al. 2008), stays what the case chose while the viscosity varies.
struct Trt {
  static constexpr const char* name = "trt";
  template <Lattice L, class T, bool kSmagorinsky = false>
  static SETTLE_LBM_INLINE void collide(T* g, const T* F, const RelaxationRates& r) {
    relax<L, T, kSmagorinsky, false>(g, F, r);
  }

  /// The relaxation; kEqualRates: omega- = omega+ (BGK).
  template <Lattice L, class T, bool kSmagorinsky, bool kEqualRates>
  static SETTLE_LBM_INLINE void relax(T* g, const T* F, const RelaxationRates& r) {
    constexpr int P = (L::Q - 1) / 2;
    T s[P], d[P];
    T jx = T(0.0), jy = T(0.0), jz = T(0.0);
    bool started[3] = {false, false, false};
    // Three partial sums for the density: shorter dependency chains (the compiler may not
    // reassociate floating-point sums itself), which lets more cells overlap in flight.
    T partial[3] = {g[0], T(0.0), T(0.0)};
    bool partial_started[3] = {true, false, false};
    // Second moments sum c_a c_b g (Smagorinsky only): the pair sums carry them, c_a c_b being even.
    T pi[6] = {T(0.0), T(0.0), T(0.0), T(0.0), T(0.0), T(0.0)};
    bool pi_started[6] = {false, false, false, false, false, false};
#pragma GCC unroll 16
    for (int p = 0; p < P; ++p) {
      const int i = 2 * p + 1, o = 2 * p + 2;
      const auto& c = L::set.c[i];
      s[p] = g[i] + g[o];
      d[p] = g[i] - g[o];
      accumulate(partial[p % 3], partial_started[p % 3], 1, s[p]);
      accumulate(jx, started[0], c[0], d[p]);
      accumulate(jy, started[1], c[1], d[p]);
      accumulate(jz, started[2], c[2], d[p]);
      if constexpr (kSmagorinsky) {
        accumulate(pi[0], pi_started[0], c[0] * c[0], s[p]);
        accumulate(pi[1], pi_started[1], c[1] * c[1], s[p]);
        accumulate(pi[2], pi_started[2], c[2] * c[2], s[p]);
        accumulate(pi[3], pi_started[3], c[0] * c[1], s[p]);
        accumulate(pi[4], pi_started[4], c[0] * c[2], s[p]);
        accumulate(pi[5], pi_started[5], c[1] * c[2], s[p]);
      }
    }
    const T drho = partial[0] + (partial[1] + partial[2]);
    const T rho = T(1.0) + drho;
    const T inv_rho = T(1.0) / rho;
    const T ux = (jx + T(0.5) * F[0]) * inv_rho;
    const T uy = (jy + T(0.5) * F[1]) * inv_rho;
    const T uz = (jz + T(0.5) * F[2]) * inv_rho;
    T wp = T(r.omega_plus), wm = kEqualRates ? T(r.omega_plus) : T(r.omega_minus);
    if constexpr (kSmagorinsky) {
      const T tau = smagorinsky_tau(r.smagorinsky, guo_non_equilibrium_flux_squared(pi, drho, rho, ux, uy, uz, F), rho);
      wp = T(1.0) / tau;
      wm = kEqualRates ? wp : trt_omega_minus(tau, T(r.smagorinsky.trt_magic));
    }
    const T sp = T(1.0) - T(0.5) * wp, sm = T(1.0) - T(0.5) * wm;
    const T usq = ux * ux + uy * uy + uz * uz;
    const T uF = ux * F[0] + uy * F[1] + uz * F[2];
    const T A = wp * (drho - T(1.5) * rho * usq) - T(3.0) * sp * uF;
    const T B = T(4.5) * wp * rho;
    const T D = T(3.0) * wm * rho;
    // The new pair is built from s and d alone (g_i = (s + d)/2, g_o = (s - d)/2), so the 18
    // incoming populations are dead once s and d exist: that halves the live vector registers
    // and removes most of the kernel's spills (docs/lbm.md, Speed).
    const T keep_sym = T(0.5) * (T(1.0) - wp), keep_anti = T(0.5) * (T(1.0) - wm);
    g[0] = (T(1.0) - wp) * g[0] + T(L::set.w[0]) * A;
#pragma GCC unroll 16
    for (int p = 0; p < P; ++p) {
      const int i = 2 * p + 1, o = 2 * p + 2;
      const auto& c = L::set.c[i];
      const T w = T(L::set.w[i]);
      const T cu = lattice_dot(c, ux, uy, uz);
      const T cF = lattice_dot(c, F[0], F[1], F[2]);
      const T sym = w * A + cu * ((w * B) * cu + (T(9.0) * w * sp) * cF) + keep_sym * s[p];
      const T anti = (w * D) * cu + (T(3.0) * w * sm) * cF + keep_anti * d[p];
      g[i] = sym + anti;
      g[o] = sym - anti;
    }
  }
};

/// Single relaxation time (Bhatnagar, Gross & Krook 1954; Qian, d'Humieres & Lallemand 1992)
/// with Guo forcing: g*_i = g_i + omega (geq_i - g_i) + (1 - omega/2) S_i. This is exactly TRT
/// with omega- = omega+, so it shares TRT's pair-wise code (with kSmagorinsky both rates follow
/// tau_eff).
struct Bgk {
  static constexpr const char* name = "bgk";
  template <Lattice L, class T, bool kSmagorinsky = false>
  static SETTLE_LBM_INLINE void collide(T* g, const T* F, const RelaxationRates& r) {
    Trt::relax<L, T, kSmagorinsky, true>(g, F, r);
  }
};

/// Recursive regularised BGK (Malaspinas 2015, arXiv:1505.06900; Coreixas, Wissocq, Puigt,
/// Boussuge & Sagaut 2017, doi:10.1103/PhysRevE.96.033306), with Guo forcing.
///
/// The non-equilibrium part f - f_eq + S/2 (the Guo-shifted non-equilibrium, whose zeroth
/// and first moments vanish) is replaced by its Hermite projection
///   f_neq_i = w_i [ H2_i : a2 / (2 cs^4) + third order ],
///   a2 = sum c c (f - f_eq) + (u F + F u)/2,
/// with the third-order coefficients built recursively from a2 (the Chapman-Enskog relation
/// a3_abg = u_a a2_bg + u_b a2_ag + u_g a2_ab, Malaspinas 2015). Post-collision:
///   f*_i = f_eq_i + (1 - omega) f_neq_i + S_i / 2,
/// which is Guo's BGK step with f - f_eq + S/2 replaced by its projection.
/// Third order: D3Q19 carries only the combinations H_xxy +- H_yzz (and the two cyclic
/// permutations); on that lattice they are orthogonal but their norms differ from the
/// continuous ones, so each is weighted by 1 / sum_i w_i H_i^2 (this gives Coreixas et
/// al.'s 1/(2 cs^6) and 1/(6 cs^6)). D3Q27 also carries H_xyz. Approximation: the
/// equilibrium stays second order (the usual polynomial one), and fourth- and higher-order
/// non-equilibrium moments that D3Q27 could carry are dropped.
struct RecursiveRegularized {
  static constexpr const char* name = "rr";

  template <Lattice L>
  static constexpr double inverse_norm(int which) {
    double sum = 0.0;
    for (int i = 0; i < L::Q; ++i) {
      const auto& c = L::set.c[i];
      const double cx2 = c[0] * c[0], cz2 = c[2] * c[2];
      double h = 0.0;
      if (which == 0) h = c[1] * (cx2 + cz2 - 2.0 * cs2);  // H_xxy + H_yzz
      if (which == 1) h = c[1] * (cx2 - cz2);              // H_xxy - H_yzz
      if (which == 2) h = c[0] * c[1] * c[2];              // H_xyz
      sum += L::set.w[i] * h * h;
    }
    return sum > 0.0 ? 1.0 / sum : 0.0;
  }

  template <Lattice L, class T, bool kSmagorinsky = false>
  static SETTLE_LBM_INLINE void collide(T* g, const T* F, const RelaxationRates& r) {
    constexpr T k_plus = T(inverse_norm<L>(0));
    constexpr T k_minus = T(inverse_norm<L>(1));
    constexpr T k_xyz = T(inverse_norm<L>(2));
    const auto m = macroscopic<L, T>(g, F);
    const T ux = m.ux, uy = m.uy, uz = m.uz;
    T pxx = T(0.0), pyy = T(0.0), pzz = T(0.0), pxy = T(0.0), pxz = T(0.0), pyz = T(0.0);
#pragma GCC unroll 32
    for (int i = 0; i < L::Q; ++i) {
      const auto& c = L::set.c[i];
      // Products with zero velocity components are skipped at compile time.
      if (c[0] != 0) pxx += g[i];
      if (c[1] != 0) pyy += g[i];
      if (c[2] != 0) pzz += g[i];
      if (c[0] * c[1] != 0) pxy += T(c[0] * c[1]) * g[i];
      if (c[0] * c[2] != 0) pxz += T(c[0] * c[2]) * g[i];
      if (c[1] * c[2] != 0) pyz += T(c[1] * c[2]) * g[i];
    }
    // a2 = Pi - Pi_eq + (uF + Fu)/2; for shifted populations Pi_eq = cs^2 drho I + rho u u.
    const T iso = T(cs2) * m.drho;
    const T axx = pxx - iso - m.rho * ux * ux + ux * F[0];
    const T ayy = pyy - iso - m.rho * uy * uy + uy * F[1];
    const T azz = pzz - iso - m.rho * uz * uz + uz * F[2];
    const T axy = pxy - m.rho * ux * uy + T(0.5) * (ux * F[1] + uy * F[0]);
    const T axz = pxz - m.rho * ux * uz + T(0.5) * (ux * F[2] + uz * F[0]);
    const T ayz = pyz - m.rho * uy * uz + T(0.5) * (uy * F[2] + uz * F[1]);
    // Post-collision Hermite coefficients: equilibrium plus (1 - omega) times the
    // non-equilibrium, at second order (A) and third order (B, recursive non-equilibrium
    // plus the equilibrium's rho u u u, both projected on what the lattice carries).
    // With kSmagorinsky the shear part and the recursive third order relax at 1 / tau_eff of this
    // cell (smagorinsky_tau, from the full a2); the bulk part keeps its rate 1.
    T omega = T(r.omega_plus);
    if constexpr (kSmagorinsky)
      omega = T(1.0) / smagorinsky_tau(r.smagorinsky, symmetric_squared_norm(axx, ayy, azz, axy, axz, ayz), m.rho);
    const T keep = T(1.0) - omega;
    // The trace (bulk) part of a2 is not kept: its relaxation rate is 1 instead of omega
    // (bulk viscosity cs^2/3 = 1/9 instead of 2 nu / 3; Dellar 2001, "Bulk and shear viscosities
    // in lattice Boltzmann equations", Phys. Rev. E 64, 031203, doi:10.1103/PhysRevE.64.031203).
    // Near tau = 1/2 this damps the under-resolved acoustic modes that destabilise BGK; the shear (deviatoric) part keeps omega, so the shear
    // viscosity is unchanged.
    const T bulk = (axx + ayy + azz) / T(3.0);
    const T Axx = m.rho * ux * ux + keep * (axx - bulk);
    const T Ayy = m.rho * uy * uy + keep * (ayy - bulk);
    const T Azz = m.rho * uz * uz + keep * (azz - bulk);
    const T Axy = m.rho * ux * uy + keep * axy;
    const T Axz = m.rho * ux * uz + keep * axz, Ayz = m.rho * uy * uz + keep * ayz;
    const T cs2_trace = (Axx + Ayy + Azz) * T(cs2);
    const T ru = m.rho * ux, rv = m.rho * uy, rw = m.rho * uz;
    const T Bxxy = ru * ux * uy + keep * (T(2.0) * ux * axy + uy * axx);
    const T Byzz = rv * uz * uz + keep * (uy * azz + T(2.0) * uz * ayz);
    const T Bxzz = ru * uz * uz + keep * (ux * azz + T(2.0) * uz * axz);
    const T Bxyy = ru * uy * uy + keep * (ux * ayy + T(2.0) * uy * axy);
    const T Byyz = rw * uy * uy + keep * (uz * ayy + T(2.0) * uy * ayz);
    const T Bxxz = rw * ux * ux + keep * (uz * axx + T(2.0) * ux * axz);
    const T Bxyz = ru * uy * uz + keep * (ux * ayz + uy * axz + uz * axy);
    const T uF = ux * F[0] + uy * F[1] + uz * F[2];
#pragma GCC unroll 32
    for (int i = 0; i < L::Q; ++i) {
      const auto& c = L::set.c[i];
      const T w = T(L::set.w[i]);
      const T cx = T(c[0]), cy = T(c[1]), cz = T(c[2]);
      const T cx2 = cx * cx, cy2 = cy * cy, cz2 = cz * cz;
      const T second = T(4.5) * (cx2 * Axx + cy2 * Ayy + cz2 * Azz - cs2_trace +
                                 T(2.0) * (cx * cy * Axy + cx * cz * Axz + cy * cz * Ayz));
      const T third = k_plus * (cy * (cx2 + cz2 - T(2.0) * T(cs2)) * (Bxxy + Byzz) +
                                cx * (cz2 + cy2 - T(2.0) * T(cs2)) * (Bxzz + Bxyy) +
                                cz * (cy2 + cx2 - T(2.0) * T(cs2)) * (Byyz + Bxxz)) +
                      k_minus * (cy * (cx2 - cz2) * (Bxxy - Byzz) + cx * (cz2 - cy2) * (Bxzz - Bxyy) +
                                 cz * (cy2 - cx2) * (Byyz - Bxxz)) +
                      k_xyz * cx * cy * cz * Bxyz;
      const T cu = cx * ux + cy * uy + cz * uz;
      const T cF = cx * F[0] + cy * F[1] + cz * F[2];
      const T source = w * (T(3.0) * (cF - uF) + T(9.0) * cu * cF);
      g[i] = w * (m.drho + T(3.0) * m.rho * cu + second + third) + T(0.5) * source;
    }
  }
};

/// An operator with the Smagorinsky subgrid model (smagorinsky_tau): its shear relaxation time is
/// set per cell from the cell's own non-equilibrium momentum flux. A distinct type, so that the
/// plain operator's kernel is compiled without any of it (the choice is made once, in the
/// solver's factory).
template <class Operator>
struct Smagorinsky {
  static constexpr const char* name = Operator::name;
  template <Lattice L, class T>
  static SETTLE_LBM_INLINE void collide(T* g, const T* F, const RelaxationRates& r) {
    Operator::template collide<L, T, true>(g, F, r);
  }
};

}  // namespace settle::lbm
