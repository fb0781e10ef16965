// The AA-pattern solver against a straightforward two-lattice reference written here from
// the textbook formulas: collide every cell, then push every post-collision population to
// its neighbour (periodic wrap, half-way bounce-back, specular reflection decided per link
// in the push direction, independently of the solver's pull-resolution lists). A random
// non-equilibrium field with random per-cell forces is advanced a few steps; after every
// step (so both AA parities) all populations of all cells must agree to round-off.
#include <gtest/gtest.h>

#include <array>
#include <cmath>
#include <random>
#include <vector>

#include "lbm/lattice.hpp"
#include "lbm/solver.hpp"

namespace {

using namespace settle::lbm;

/// The reference lattice, built by enumeration (not from the solver's tables).
struct RefLattice {
  std::vector<std::array<int, 3>> c;
  std::vector<double> w;
  std::vector<int> opp;
  std::vector<int> solver_index;  // index of the same velocity in the solver's ordering
};

RefLattice make_ref_lattice(LatticeKind kind) {
  RefLattice lat;
  for (int z = -1; z <= 1; ++z) {
    for (int y = -1; y <= 1; ++y) {
      for (int x = -1; x <= 1; ++x) {
        const int n = x * x + y * y + z * z;
        if (kind == LatticeKind::D3Q19 && n == 3) continue;
        lat.c.push_back({x, y, z});
        if (kind == LatticeKind::D3Q19) {
          lat.w.push_back(n == 0 ? 1.0 / 3.0 : n == 1 ? 1.0 / 18.0 : 1.0 / 36.0);
        } else {
          lat.w.push_back(n == 0 ? 8.0 / 27.0 : n == 1 ? 2.0 / 27.0 : n == 2 ? 1.0 / 54.0 : 1.0 / 216.0);
        }
      }
    }
  }
  const auto find = [&](int x, int y, int z) {
    for (std::size_t k = 0; k < lat.c.size(); ++k) {
      if (lat.c[k] == std::array<int, 3>{x, y, z}) return static_cast<int>(k);
    }
    return -1;
  };
  for (const auto& v : lat.c) {
    lat.opp.push_back(find(-v[0], -v[1], -v[2]));
    lat.solver_index.push_back(kind == LatticeKind::D3Q19 ? direction_index<D3Q19>(v[0], v[1], v[2])
                                                          : direction_index<D3Q27>(v[0], v[1], v[2]));
  }
  return lat;
}

/// Two-lattice reference solver with full (unshifted) populations.
class Reference {
 public:
  Reference(const SolverConfig& cfg, RefLattice lat)
      : cfg_(cfg), lat_(std::move(lat)), q_(static_cast<int>(lat_.c.size())),
        cells_(static_cast<std::size_t>(cfg.nx * cfg.ny * cfg.nz)),
        f_(cells_ * q_), post_(cells_ * q_), force_(cells_, Eigen::Vector3d::Zero()) {}

  std::size_t cell(int x, int y, int z) const {
    return static_cast<std::size_t>(x + cfg_.nx * (y + cfg_.ny * z));
  }
  double& f(std::size_t n, int k) { return f_[n * q_ + k]; }
  Eigen::Vector3d& force(std::size_t n) { return force_[n]; }

  void step() {
    for (std::size_t n = 0; n < cells_; ++n) collide(n);
    std::fill(f_.begin(), f_.end(), std::nan(""));
    for (int z = 0; z < cfg_.nz; ++z) {
      for (int y = 0; y < cfg_.ny; ++y) {
        for (int x = 0; x < cfg_.nx; ++x) {
          for (int k = 0; k < q_; ++k) push(x, y, z, k);
        }
      }
    }
  }

 private:
  void collide(std::size_t n) {
    const double* g = &f_[n * q_];
    double* out = &post_[n * q_];
    double rho = 0.0;
    Eigen::Vector3d mom = Eigen::Vector3d::Zero();
    for (int k = 0; k < q_; ++k) {
      rho += g[k];
      mom += g[k] * cvec(k);
    }
    const Eigen::Vector3d F = cfg_.body_force + force_[n];
    const Eigen::Vector3d u = (mom + 0.5 * F) / rho;
    std::vector<double> feq(q_), S(q_);
    for (int k = 0; k < q_; ++k) {
      const double cu = cvec(k).dot(u);
      feq[k] = lat_.w[k] * rho * (1.0 + 3.0 * cu + 4.5 * cu * cu - 1.5 * u.squaredNorm());
      S[k] = lat_.w[k] * (3.0 * (cvec(k) - u).dot(F) + 9.0 * cu * cvec(k).dot(F));
    }
    const double omega = 1.0 / cfg_.tau;
    if (cfg_.collision == CollisionKind::bgk) {
      for (int k = 0; k < q_; ++k) out[k] = g[k] - omega * (g[k] - feq[k]) + (1.0 - omega / 2) * S[k];
    } else if (cfg_.collision == CollisionKind::trt) {
      const double omega_minus = 1.0 / (cfg_.magic / (cfg_.tau - 0.5) + 0.5);
      for (int k = 0; k < q_; ++k) {
        const int o = lat_.opp[k];
        const double fp = 0.5 * (g[k] + g[o]), fm = 0.5 * (g[k] - g[o]);
        const double ep = 0.5 * (feq[k] + feq[o]), em = 0.5 * (feq[k] - feq[o]);
        const double sp = 0.5 * (S[k] + S[o]), sm = 0.5 * (S[k] - S[o]);
        out[k] = g[k] - omega * (fp - ep) - omega_minus * (fm - em) + (1.0 - omega / 2) * sp +
                 (1.0 - omega_minus / 2) * sm;
      }
    } else {
      regularized(g, out, rho, u, F, feq, S, omega);
    }
  }

  // Recursive regularisation in full tensor form (only compared on D3Q27, where every
  // third-order Hermite polynomial not carried by the lattice vanishes on it):
  //   f* = w [rho + rho c.u / cs^2 + H2 : A2 / (2 cs^4) + H3 : A3 / (6 cs^6)] + S / 2,
  //   A2 = rho u u + (1 - omega) dev(a2),  A3 = rho u u u + (1 - omega) a3(a2),
  //   a2 = sum H2 (f - feq) + (u F + F u) / 2,  a3_abc = u_a a2_bc + u_b a2_ac + u_c a2_ab.
  void regularized(const double* g, double* out, double rho, const Eigen::Vector3d& u,
                   const Eigen::Vector3d& F, const std::vector<double>& feq,
                   const std::vector<double>& S, double omega) const {
    const double cs2_ = 1.0 / 3.0;
    const Eigen::Matrix3d I = Eigen::Matrix3d::Identity();
    Eigen::Matrix3d a2 = 0.5 * (u * F.transpose() + F * u.transpose());
    for (int k = 0; k < q_; ++k) {
      a2 += (g[k] - feq[k]) * (cvec(k) * cvec(k).transpose() - cs2_ * I);
    }
    const Eigen::Matrix3d A2 = rho * u * u.transpose() + (1.0 - omega) * (a2 - a2.trace() / 3.0 * I);
    double A3[3][3][3];
    for (int a = 0; a < 3; ++a)
      for (int b = 0; b < 3; ++b)
        for (int c = 0; c < 3; ++c)
          A3[a][b][c] = rho * u[a] * u[b] * u[c] +
                        (1.0 - omega) * (u[a] * a2(b, c) + u[b] * a2(a, c) + u[c] * a2(a, b));
    for (int k = 0; k < q_; ++k) {
      const Eigen::Vector3d c = cvec(k);
      double h2 = 0.0, h3 = 0.0;
      for (int a = 0; a < 3; ++a) {
        for (int b = 0; b < 3; ++b) {
          h2 += (c[a] * c[b] - cs2_ * (a == b)) * A2(a, b);
          for (int d = 0; d < 3; ++d) {
            const double H3 = c[a] * c[b] * c[d] - cs2_ * (c[a] * (b == d) + c[b] * (a == d) + c[d] * (a == b));
            h3 += H3 * A3[a][b][d];
          }
        }
      }
      out[k] = lat_.w[k] * (rho + rho * c.dot(u) / cs2_ + h2 / (2 * cs2_ * cs2_) +
                            h3 / (6 * cs2_ * cs2_ * cs2_)) +
               0.5 * S[k];
    }
  }

  void push(int x, int y, int z, int k) {
    const std::array<int, 3> from{x, y, z};
    const std::array<int, 3> extent{cfg_.nx, cfg_.ny, cfg_.nz};
    std::array<int, 3> to{}, dir = lat_.c[k];
    bool bounce = false;
    for (int a = 0; a < 3; ++a) {
      to[a] = from[a] + dir[a];
      if ((to[a] < 0 || to[a] >= extent[a]) && cfg_.boundaries[a] == Boundary::no_slip) bounce = true;
    }
    int dest_dir = k;
    if (bounce) {
      to = from;
      dest_dir = lat_.opp[k];
    } else {
      for (int a = 0; a < 3; ++a) {
        if (to[a] >= 0 && to[a] < extent[a]) continue;
        if (cfg_.boundaries[a] == Boundary::periodic) {
          to[a] = (to[a] + extent[a]) % extent[a];
        } else {  // free slip: stays in its layer along a, normal component reversed
          to[a] = from[a];
          dir[a] = -dir[a];
        }
      }
      for (int j = 0; j < q_; ++j) {
        if (lat_.c[j] == dir) dest_dir = j;
      }
    }
    f(cell(to[0], to[1], to[2]), dest_dir) = post_[cell(x, y, z) * q_ + k];
  }

  Eigen::Vector3d cvec(int k) const { return {double(lat_.c[k][0]), double(lat_.c[k][1]), double(lat_.c[k][2])}; }

  SolverConfig cfg_;
  RefLattice lat_;
  int q_;
  std::size_t cells_;
  std::vector<double> f_, post_;
  std::vector<Eigen::Vector3d> force_;
};

/// Largest |f_solver - f_reference| over all populations of all cells.
double max_difference(const Solver& solver, Reference& ref, const RefLattice& lat) {
  const SolverConfig& cfg = solver.config();
  std::vector<double> f(static_cast<std::size_t>(solver.velocity_count()));
  double worst = 0.0;
  for (int z = 0; z < cfg.nz; ++z) {
    for (int y = 0; y < cfg.ny; ++y) {
      for (int x = 0; x < cfg.nx; ++x) {
        solver.cell_populations(x, y, z, f);
        for (std::size_t k = 0; k < lat.c.size(); ++k) {
          const double r = ref.f(ref.cell(x, y, z), static_cast<int>(k));
          const double d = std::abs(f[lat.solver_index[k]] - r);
          worst = std::isnan(d) ? INFINITY : std::max(worst, d);
        }
      }
    }
  }
  return worst;
}

/// Runs solver and reference side by side from the same random state; returns the largest
/// difference seen after any of `steps` steps.
double compare(const SolverConfig& cfg, int steps, unsigned seed) {
  const RefLattice lat = make_ref_lattice(cfg.lattice);
  auto solver = make_solver(cfg);
  Reference ref(cfg, lat);
  std::mt19937 rng(seed);
  std::uniform_real_distribution<double> unit(-1.0, 1.0);
  std::vector<double> f(static_cast<std::size_t>(solver->velocity_count()));
  for (int z = 0; z < cfg.nz; ++z) {
    for (int y = 0; y < cfg.ny; ++y) {
      for (int x = 0; x < cfg.nx; ++x) {
        const std::size_t n = ref.cell(x, y, z);
        const Eigen::Vector3d force(1e-3 * unit(rng), 1e-3 * unit(rng), 1e-3 * unit(rng));
        solver->set_force(x, y, z, force);
        ref.force(n) = force;
        for (std::size_t k = 0; k < lat.c.size(); ++k) {
          // Random non-equilibrium populations around the rest state (up to 20 %).
          const double value = lat.w[k] * (1.0 + 0.2 * unit(rng));
          ref.f(n, static_cast<int>(k)) = value;
          f[lat.solver_index[k]] = value;
        }
        solver->set_cell_populations(x, y, z, f);
      }
    }
  }
  double worst = max_difference(*solver, ref, lat);
  for (int s = 0; s < steps; ++s) {
    solver->step();
    ref.step();
    worst = std::max(worst, max_difference(*solver, ref, lat));
  }
  return worst;
}

SolverConfig small_box(LatticeKind lattice, CollisionKind collision, Boundary bx, Boundary by,
                       Boundary bz) {
  SolverConfig cfg;
  cfg.lattice = lattice;
  cfg.collision = collision;
  cfg.nx = 6;  // unequal extents catch swapped strides
  cfg.ny = 5;
  cfg.nz = 4;
  cfg.boundaries = {bx, by, bz};
  cfg.tau = 0.7;
  cfg.body_force = Eigen::Vector3d(2e-4, -1e-4, 3e-4);
  return cfg;
}

// Populations are O(0.3) and each step does a few dozen double operations per value; the
// solver stores f - w instead of f and groups terms differently, so the two agree to a few
// ulps of 0.3 per step. 1e-13 after 5 steps is ~100 ulps: any indexing or boundary error
// moves populations by O(1e-2).
constexpr double kRoundOff = 1e-13;
constexpr int kSteps = 5;  // covers both AA parities several times

TEST(LbmAaReference, PeriodicTrtD3Q19) {
  const auto cfg = small_box(LatticeKind::D3Q19, CollisionKind::trt, Boundary::periodic,
                             Boundary::periodic, Boundary::periodic);
  EXPECT_LT(compare(cfg, kSteps, 1), kRoundOff);
}

TEST(LbmAaReference, MixedTrtD3Q19PeriodicXFreeSlipYNoSlipZ) {
  const auto cfg = small_box(LatticeKind::D3Q19, CollisionKind::trt, Boundary::periodic,
                             Boundary::free_slip, Boundary::no_slip);
  EXPECT_LT(compare(cfg, kSteps, 2), kRoundOff);
}

TEST(LbmAaReference, MixedBgkD3Q19NoSlipXPeriodicYFreeSlipZ) {
  const auto cfg = small_box(LatticeKind::D3Q19, CollisionKind::bgk, Boundary::no_slip,
                             Boundary::periodic, Boundary::free_slip);
  EXPECT_LT(compare(cfg, kSteps, 3), kRoundOff);
}

TEST(LbmAaReference, AllFreeSlipTrtD3Q27) {
  const auto cfg = small_box(LatticeKind::D3Q27, CollisionKind::trt, Boundary::free_slip,
                             Boundary::free_slip, Boundary::free_slip);
  EXPECT_LT(compare(cfg, kSteps, 4), kRoundOff);
}

TEST(LbmAaReference, AllNoSlipBgkD3Q27) {
  const auto cfg = small_box(LatticeKind::D3Q27, CollisionKind::bgk, Boundary::no_slip,
                             Boundary::no_slip, Boundary::no_slip);
  EXPECT_LT(compare(cfg, kSteps, 5), kRoundOff);
}

TEST(LbmAaReference, MixedFreeSlipXNoSlipYPeriodicZTrtD3Q27) {
  const auto cfg = small_box(LatticeKind::D3Q27, CollisionKind::trt, Boundary::free_slip,
                             Boundary::no_slip, Boundary::periodic);
  EXPECT_LT(compare(cfg, kSteps, 6), kRoundOff);
}

TEST(LbmAaReference, RecursiveRegularizedD3Q27MatchesFullTensorForm) {
  auto cfg = small_box(LatticeKind::D3Q27, CollisionKind::recursive_regularized,
                       Boundary::periodic, Boundary::no_slip, Boundary::free_slip);
  cfg.tau = 0.52;
  EXPECT_LT(compare(cfg, kSteps, 7), kRoundOff);
}

TEST(LbmAaReference, SingleCellThickPeriodicAxis) {
  // A periodic axis one cell thick (quasi-2D runs) wraps every link onto the cell itself.
  auto cfg = small_box(LatticeKind::D3Q19, CollisionKind::trt, Boundary::no_slip,
                       Boundary::free_slip, Boundary::periodic);
  cfg.nz = 1;
  EXPECT_LT(compare(cfg, kSteps, 8), kRoundOff);
}

TEST(LbmAaReference, FloatStorageFollowsDoubleReference) {
  auto cfg = small_box(LatticeKind::D3Q19, CollisionKind::trt, Boundary::periodic,
                       Boundary::free_slip, Boundary::no_slip);
  cfg.precision = Precision::float32;
  // Float storage of f - w: |f - w| <= 0.2 w ~ 0.02, rounded to 2^-24 relative (1.2e-9)
  // each step, plus the per-cell forces stored in float (1e-3 * 6e-8). Five steps stay
  // well below 1e-8, while any indexing error is O(1e-2).
  EXPECT_LT(compare(cfg, kSteps, 9), 1e-8);
}

}  // namespace
