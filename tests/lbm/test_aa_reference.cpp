// The AA-pattern solver against a straightforward two-lattice reference written here from
// the textbook formulas: collide every cell, then push every post-collision population to
// its neighbour (periodic wrap, half-way bounce-back, specular reflection decided per link
// in the push direction, independently of the solver's pull-resolution lists). A random
// non-equilibrium field with random per-cell forces is advanced a few steps; after every
// step (so both AA parities) all populations of all cells must agree to round-off.
// Inlets, outlets and obstacles are checked against a pull form of the same reference: each
// cell gathers f_i(x) from x - c_i, from the face's rule when x - c_i is outside, and from the
// wall's interpolation when it is solid.
#include <gtest/gtest.h>

#include <Eigen/LU>
#include <algorithm>
#include <array>
#include <cmath>
#include <cstdio>
#include <random>
#include <vector>

#include "lbm/lattice.hpp"
#include "lbm/solver.hpp"

namespace test_aa_reference {

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
      : cfg_(cfg),
        lat_(std::move(lat)),
        q_(static_cast<int>(lat_.c.size())),
        cells_(static_cast<std::size_t>(cfg.nx * cfg.ny * cfg.nz)),
        f_(cells_ * q_),
        post_(cells_ * q_),
        force_(cells_, Eigen::Vector3d::Zero()) {}

  std::size_t cell(int x, int y, int z) const { return static_cast<std::size_t>(x + cfg_.nx * (y + cfg_.ny * z)); }
  double& f(std::size_t n, int k) { return f_[n * q_ + k]; }
  Eigen::Vector3d& force(std::size_t n) { return force_[n]; }

  /// Solid cells and links (directions in the reference's ordering) of an obstacle.
  void set_obstacle(std::vector<std::array<int, 3>> solid, std::vector<WallLink> links, WallRule rule) {
    solid_ = std::move(solid);
    links_ = std::move(links);
    rule_ = rule;
  }
  const std::vector<Eigen::Vector3d>& wall_momentum() const { return momentum_; }
  bool is_solid(const std::array<int, 3>& x) const {
    return std::find(solid_.begin(), solid_.end(), x) != solid_.end();
  }

  void step() {
    for (std::size_t n = 0; n < cells_; ++n) collide(n);
    std::fill(f_.begin(), f_.end(), std::nan(""));
    const bool pull_form = !cfg_.open_faces.empty() || !solid_.empty();
    for (int z = 0; z < cfg_.nz; ++z) {
      for (int y = 0; y < cfg_.ny; ++y) {
        for (int x = 0; x < cfg_.nx; ++x) {
          for (int k = 0; k < q_; ++k) pull_form ? pull(x, y, z, k) : push(x, y, z, k);
        }
      }
    }
    if (pull_form) finish_walls();
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
    const double tau = relaxation_time(g, feq, rho, u, F);
    const double omega = 1.0 / tau;
    if (cfg_.collision == CollisionKind::bgk) {
      for (int k = 0; k < q_; ++k) out[k] = g[k] - omega * (g[k] - feq[k]) + (1.0 - omega / 2) * S[k];
    } else if (cfg_.collision == CollisionKind::trt) {
      const double omega_minus = 1.0 / (cfg_.magic / (tau - 0.5) + 0.5);
      for (int k = 0; k < q_; ++k) {
        const int o = lat_.opp[k];
        const double fp = 0.5 * (g[k] + g[o]), fm = 0.5 * (g[k] - g[o]);
        const double ep = 0.5 * (feq[k] + feq[o]), em = 0.5 * (feq[k] - feq[o]);
        const double sp = 0.5 * (S[k] + S[o]), sm = 0.5 * (S[k] - S[o]);
        out[k] =
            g[k] - omega * (fp - ep) - omega_minus * (fm - em) + (1.0 - omega / 2) * sp + (1.0 - omega_minus / 2) * sm;
      }
    } else if (cfg_.collision == CollisionKind::cumulant) {
      cumulant(g, out, rho, u, F, omega);
    } else {
      regularized(g, out, rho, u, F, feq, S, omega);
    }
  }

  // The cumulant operator of Geier et al. 2015 (D3Q27) from its definitions, none of the
  // solver's shortcuts: central moments by direct sums over full populations; the second-order
  // cumulants relaxed (shear omega, trace 1, with the cubic-defect correction); every cumulant of
  // order 3-6 relaxed with rate 1 to zero; post-collision central moments from the cumulants by
  // the general zero-mean relations (orders 4-6); first-order central moments +F/2; populations
  // by solving the 27 x 27 linear system of central moments.
  void cumulant(const double* f, double* out, double rho, const Eigen::Vector3d& u, const Eigen::Vector3d& F,
                double omega) const {
    using Moments = std::array<std::array<std::array<double, 3>, 3>, 3>;
    Eigen::Matrix<double, 27, 27> A;  // A(moment, direction) = prod (c - u)^exponent
    const auto row = [](int a, int b, int c) { return a + 3 * b + 9 * c; };
    Moments k{};
    for (int a = 0; a < 3; ++a)
      for (int b = 0; b < 3; ++b)
        for (int c = 0; c < 3; ++c)
          for (int i = 0; i < q_; ++i) {
            const Eigen::Vector3d d = cvec(i) - u;
            A(row(a, b, c), i) = std::pow(d.x(), a) * std::pow(d.y(), b) * std::pow(d.z(), c);
            k[a][b][c] += A(row(a, b, c), i) * f[i];
          }
    const double dxy = k[2][0][0] - k[0][2][0], dxz = k[2][0][0] - k[0][0][2];
    const double trace = k[2][0][0] + k[0][2][0] + k[0][0][2];
    const double rdxux = -0.5 * omega * (dxy + dxz) + 0.5 * (rho - trace);
    const double rdyuy = rdxux + 1.5 * omega * dxy, rdzuz = rdxux + 1.5 * omega * dxz;
    const double ex = u.x() * u.x() * rdxux, ey = u.y() * u.y() * rdyuy, ez = u.z() * u.z() * rdzuz;
    const double dxy_post = (1.0 - omega) * dxy - 3.0 * (1.0 - 0.5 * omega) * (ex - ey);
    const double dxz_post = (1.0 - omega) * dxz - 3.0 * (1.0 - 0.5 * omega) * (ex - ez);
    const double trace_post = rho - 1.5 * (ex + ey + ez);
    Moments p{};  // post-collision central moments; orders 3 and 5 stay zero below
    p[0][0][0] = rho;
    p[1][0][0] = 0.5 * F.x(), p[0][1][0] = 0.5 * F.y(), p[0][0][1] = 0.5 * F.z();
    p[2][0][0] = (dxy_post + dxz_post + trace_post) / 3.0;
    p[0][2][0] = (trace_post - 2.0 * dxy_post + dxz_post) / 3.0;
    p[0][0][2] = (trace_post + dxy_post - 2.0 * dxz_post) / 3.0;
    p[1][1][0] = (1.0 - omega) * k[1][1][0];
    p[1][0][1] = (1.0 - omega) * k[1][0][1];
    p[0][1][1] = (1.0 - omega) * k[0][1][1];
    // Zero-mean cumulant relations (Geier et al. 2015) with the cumulants set to zero,
    // written for the exponents (a, b, c) of one axis order and applied to the three orders.
    const auto second = [&](int x, int y) {  // p of the second moment along axes x, y
      std::array<int, 3> e{};
      e[x] += 1, e[y] += 1;
      return p[e[0]][e[1]][e[2]];
    };
    for (int x = 0; x < 3; ++x) {
      const int y = (x + 1) % 3, z = (x + 2) % 3;
      std::array<int, 3> e{};
      e[x] = 2, e[y] = 1, e[z] = 1;  // kappa_211 and permutations
      p[e[0]][e[1]][e[2]] = (second(x, x) * second(y, z) + 2.0 * second(x, y) * second(x, z)) / rho;
      e = {};
      e[x] = 2, e[y] = 2;  // kappa_220 and permutations
      p[e[0]][e[1]][e[2]] = (second(x, x) * second(y, y) + 2.0 * second(x, y) * second(x, y)) / rho;
    }
    // Order 5: every product holds a third-order moment, zero here; kappa_122 = C_122 + (...) / rho.
    for (int x = 0; x < 3; ++x) {
      const int y = (x + 1) % 3, z = (x + 2) % 3;
      const auto m = [&](int ax, int ay, int az) {
        std::array<int, 3> e{};
        e[x] = ax, e[y] = ay, e[z] = az;
        return p[e[0]][e[1]][e[2]];
      };
      std::array<int, 3> e{};
      e[x] = 1, e[y] = 2, e[z] = 2;
      p[e[0]][e[1]][e[2]] = (m(0, 0, 2) * m(1, 2, 0) + m(0, 2, 0) * m(1, 0, 2) + 4.0 * m(0, 1, 1) * m(1, 1, 1) +
                             2.0 * (m(1, 0, 1) * m(0, 2, 1) + m(1, 1, 0) * m(0, 1, 2))) /
                            rho;
    }
    const auto& q = p;
    p[2][2][2] =
        (4.0 * q[1][1][1] * q[1][1][1] + q[2][0][0] * q[0][2][2] + q[0][2][0] * q[2][0][2] + q[0][0][2] * q[2][2][0] +
         4.0 * (q[0][1][1] * q[2][1][1] + q[1][0][1] * q[1][2][1] + q[1][1][0] * q[1][1][2]) +
         2.0 * (q[1][2][0] * q[1][0][2] + q[2][1][0] * q[0][1][2] + q[2][0][1] * q[0][2][1])) /
            rho -
        (16.0 * q[1][1][0] * q[1][0][1] * q[0][1][1] +
         4.0 * (q[1][0][1] * q[1][0][1] * q[0][2][0] + q[0][1][1] * q[0][1][1] * q[2][0][0] +
                q[1][1][0] * q[1][1][0] * q[0][0][2]) +
         2.0 * q[2][0][0] * q[0][2][0] * q[0][0][2]) /
            (rho * rho);
    Eigen::Matrix<double, 27, 1> target;
    for (int a = 0; a < 3; ++a)
      for (int b = 0; b < 3; ++b)
        for (int c = 0; c < 3; ++c) target(row(a, b, c)) = p[a][b][c];
    const Eigen::Matrix<double, 27, 1> post = A.fullPivLu().solve(target);
    for (int i = 0; i < q_; ++i) out[i] = post(i);
  }

  // The shear relaxation time: tau, or with the Smagorinsky model (Hou et al. 1996)
  //   tau_eff = (tau + sqrt(tau^2 + 18 sqrt(2) C_S^2 |a2| / rho)) / 2,  |a2| = sqrt(a2 : a2),
  //   a2 = sum (c c - cs^2 I)(f - feq) + (u F + F u) / 2.
  double relaxation_time(const double* g, const std::vector<double>& feq, double rho, const Eigen::Vector3d& u,
                         const Eigen::Vector3d& F) const {
    if (cfg_.subgrid == SubgridModel::none) return cfg_.tau;
    Eigen::Matrix3d a2 = 0.5 * (u * F.transpose() + F * u.transpose());
    for (int k = 0; k < q_; ++k)
      a2 += (g[k] - feq[k]) * (cvec(k) * cvec(k).transpose() - Eigen::Matrix3d::Identity() / 3.0);
    const double c = cfg_.smagorinsky_constant;
    return 0.5 * (cfg_.tau + std::sqrt(cfg_.tau * cfg_.tau + 18.0 * std::sqrt(2.0) * c * c * a2.norm() / rho));
  }

  // Recursive regularisation in full tensor form (only compared on D3Q27, where every
  // third-order Hermite polynomial not carried by the lattice vanishes on it):
  //   f* = w [rho + rho c.u / cs^2 + H2 : A2 / (2 cs^4) + H3 : A3 / (6 cs^6)] + S / 2,
  //   A2 = rho u u + (1 - omega) dev(a2),  A3 = rho u u u + (1 - omega) a3(a2),
  //   a2 = sum H2 (f - feq) + (u F + F u) / 2,  a3_abc = u_a a2_bc + u_b a2_ac + u_c a2_ab.
  void regularized(const double* g, double* out, double rho, const Eigen::Vector3d& u, const Eigen::Vector3d& F,
                   const std::vector<double>& feq, const std::vector<double>& S, double omega) const {
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
          A3[a][b][c] =
              rho * u[a] * u[b] * u[c] + (1.0 - omega) * (u[a] * a2(b, c) + u[b] * a2(a, c) + u[c] * a2(a, b));
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
      out[k] = lat_.w[k] * (rho + rho * c.dot(u) / cs2_ + h2 / (2 * cs2_ * cs2_) + h3 / (6 * cs2_ * cs2_ * cs2_)) +
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

  // Pull form: f_k(x) = f*_k(x - c_k) where x - c_k is fluid (periodic axes wrapped); links from
  // solid cells are left for finish_walls.
  void pull(int x, int y, int z, int k) {
    const std::array<int, 3> to{x, y, z};
    const std::array<int, 3> extent{cfg_.nx, cfg_.ny, cfg_.nz};
    const FaceKinds kinds = face_kinds(cfg_);
    std::array<int, 3> from{}, dir = lat_.c[k];
    std::array<Boundary, 3> crossed{};
    bool outside = false, bounce = false, moving = false;
    for (int a = 0; a < 3; ++a) {
      from[a] = to[a] - dir[a];
      crossed[a] = Boundary::periodic;
      if (from[a] >= 0 && from[a] < extent[a]) continue;
      crossed[a] = kinds[a][from[a] < 0 ? 0 : 1];
      if (crossed[a] == Boundary::periodic) {
        from[a] = (from[a] + extent[a]) % extent[a];
        continue;
      }
      outside = true;
      bounce |= crossed[a] == Boundary::no_slip;
      moving |= crossed[a] == Boundary::velocity;
    }
    double& target = f(cell(x, y, z), k);
    if (!outside) {
      if (!is_solid(from)) target = post_[cell(from[0], from[1], from[2]) * q_ + k];
      return;  // from a solid cell: a wall link, closed later
    }
    if (bounce || moving) {
      target = post_[cell(x, y, z) * q_ + lat_.opp[k]];
      if (!bounce) target += 2.0 * lat_.w[k] * density(x, y, z) * cvec(k).dot(cfg_.inflow_velocity) / (1.0 / 3.0);
      return;
    }
    bool outflow = false;
    for (int a = 0; a < 3; ++a) {
      if (crossed[a] == Boundary::free_slip) {
        from[a] = to[a];
        dir[a] = -dir[a];
      }
      if (crossed[a] == Boundary::outflow) {
        from[a] = to[a];
        outflow = true;
      }
    }
    if (outflow) {
      // Equilibrium pressure outlet: f_eq_k(1, u) with u the post-collision velocity of x - c_k
      // brought back onto the layers of the open or mirrored faces it crossed.
      target = equilibrium(k, 1.0, velocity(from[0], from[1], from[2]));
      return;
    }
    target = post_[cell(from[0], from[1], from[2]) * q_ + index_of(dir)];
  }

  // Second pass: links from a solid cell take the wall's interpolation.
  void finish_walls() {
    momentum_.assign(links_.size(), Eigen::Vector3d::Zero());
    for (std::size_t m = 0; m < links_.size(); ++m) close_link(m);
  }

  // Bouzidi, Firdaouss and Lallemand 2001 with Ladd's moving-wall term, written for the incoming
  // population f_opp(i)(x) of a link along c_i; the momentum exchange of Wen et al. 2014.
  void close_link(std::size_t m) {
    const WallLink& link = links_[m];
    const std::array<int, 3>& x = link.cell;
    const int i = link.dir, o = lat_.opp[i];
    const double q = link.q;
    const auto post = [&](const std::array<int, 3>& c, int k) { return post_[cell(c[0], c[1], c[2]) * q_ + k]; };
    const double wall = -2.0 * lat_.w[i] * cvec(i).dot(link.wall_velocity) / (1.0 / 3.0);
    std::array<int, 3> second{};
    bool has_second = true;
    const std::array<int, 3> extent{cfg_.nx, cfg_.ny, cfg_.nz};
    for (int a = 0; a < 3; ++a) {
      second[a] = x[a] - lat_.c[i][a];
      if (second[a] >= 0 && second[a] < extent[a]) continue;
      if (cfg_.boundaries[a] == Boundary::periodic)
        second[a] = (second[a] + extent[a]) % extent[a];
      else
        has_second = false;
    }
    has_second = has_second && !is_solid(second);
    // The quadratic rule's third point x - 2c_i; both points inside the box without a wrap.
    std::array<int, 3> third{};
    bool quadratic = rule_ == WallRule::quadratic;
    for (int a = 0; a < 3; ++a) {
      third[a] = x[a] - 2 * lat_.c[i][a];
      const int s = x[a] - lat_.c[i][a];
      quadratic = quadratic && s >= 0 && s < extent[a] && third[a] >= 0 && third[a] < extent[a];
    }
    quadratic = quadratic && has_second && !is_solid(third);
    double back = 0.0;
    const bool central = rule_ == WallRule::central_linear;
    if (rule_ == WallRule::halfway || (!has_second && (q < 0.5 || central))) {
      back = post(x, i) + wall;
    } else if (central) {
      // Ginzburg, Verhaeghe and d'Humieres 2008, Eq. (4.1), Tables 3 and 4.
      const double k = (1.0 - 2.0 * q) / (1.0 + 2.0 * q);
      back = post(x, i) + k * (post(second, i) - post(x, o)) + 2.0 * wall / (1.0 + 2.0 * q);
    } else if (quadratic && q < 0.5) {
      back = q * (1.0 + 2.0 * q) * post(x, i) + (1.0 - 4.0 * q * q) * post(second, i) -
             q * (1.0 - 2.0 * q) * post(third, i) + wall;
    } else if (quadratic) {
      back = (post(x, i) + wall) / (q * (2.0 * q + 1.0)) + (2.0 * q - 1.0) / q * post(x, o) -
             (2.0 * q - 1.0) / (2.0 * q + 1.0) * post(second, o);
    } else if (q < 0.5) {
      back = 2.0 * q * post(x, i) + (1.0 - 2.0 * q) * post(second, i) + wall;
    } else {
      back = (post(x, i) + (2.0 * q - 1.0) * post(x, o) + wall) / (2.0 * q);
    }
    f(cell(x[0], x[1], x[2]), o) = back;
    momentum_[m] = cvec(i) * (post(x, i) + back) - link.wall_velocity * (post(x, i) - back);
  }

  double density(int x, int y, int z) const {
    double rho = 0.0;
    for (int k = 0; k < q_; ++k) rho += post_[cell(x, y, z) * q_ + k];
    return rho;
  }

  Eigen::Vector3d velocity(int x, int y, int z) const {
    Eigen::Vector3d momentum = Eigen::Vector3d::Zero();
    for (int k = 0; k < q_; ++k) momentum += post_[cell(x, y, z) * q_ + k] * cvec(k);
    return momentum / density(x, y, z);
  }

  double equilibrium(int k, double rho, const Eigen::Vector3d& u) const {
    const double cu = cvec(k).dot(u);
    return lat_.w[k] * rho * (1.0 + 3.0 * cu + 4.5 * cu * cu - 1.5 * u.squaredNorm());
  }

  int index_of(const std::array<int, 3>& dir) const {
    for (int j = 0; j < q_; ++j) {
      if (lat_.c[j] == dir) return j;
    }
    return -1;
  }

  Eigen::Vector3d cvec(int k) const { return {double(lat_.c[k][0]), double(lat_.c[k][1]), double(lat_.c[k][2])}; }

  SolverConfig cfg_;
  RefLattice lat_;
  int q_;
  std::size_t cells_;
  std::vector<double> f_, post_;
  std::vector<Eigen::Vector3d> force_;
  std::vector<std::array<int, 3>> solid_;
  std::vector<WallLink> links_;
  WallRule rule_ = WallRule::bouzidi;
  std::vector<Eigen::Vector3d> momentum_;
};

/// Largest |f_solver - f_reference| over all populations of all fluid cells.
double max_difference(const Solver& solver, Reference& ref, const RefLattice& lat) {
  const SolverConfig& cfg = solver.config();
  std::vector<double> f(static_cast<std::size_t>(solver.velocity_count()));
  double worst = 0.0;
  for (int z = 0; z < cfg.nz; ++z) {
    for (int y = 0; y < cfg.ny; ++y) {
      for (int x = 0; x < cfg.nx; ++x) {
        if (ref.is_solid({x, y, z})) continue;
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

/// An obstacle for the comparison: solid cells, and every link into them from a fluid cell with
/// a random wall fraction and wall velocity (directions in the reference's ordering).
struct RefObstacle {
  std::vector<std::array<int, 3>> solid;
  std::vector<WallLink> links;
  WallRule rule = WallRule::bouzidi;
};

RefObstacle obstacle_around(const SolverConfig& cfg, const RefLattice& lat, std::vector<std::array<int, 3>> solid,
                            WallRule rule, unsigned seed) {
  RefObstacle o{std::move(solid), {}, rule};
  std::mt19937 rng(seed);
  std::uniform_real_distribution<double> unit(0.0, 1.0);
  const std::array<int, 3> extent{cfg.nx, cfg.ny, cfg.nz};
  const auto solid_at = [&](const std::array<int, 3>& c) {
    return std::find(o.solid.begin(), o.solid.end(), c) != o.solid.end();
  };
  for (int z = 0; z < cfg.nz; ++z)
    for (int y = 0; y < cfg.ny; ++y)
      for (int x = 0; x < cfg.nx; ++x) {
        if (solid_at({x, y, z})) continue;
        for (int k = 0; k < static_cast<int>(lat.c.size()); ++k) {
          if (lat.c[k] == std::array<int, 3>{0, 0, 0}) continue;
          std::array<int, 3> n{};
          bool inside = true;
          for (int a = 0; a < 3; ++a) {
            n[a] = std::array<int, 3>{x, y, z}[a] + lat.c[k][a];
            if (n[a] >= 0 && n[a] < extent[a]) continue;
            if (cfg.boundaries[a] == Boundary::periodic)
              n[a] = (n[a] + extent[a]) % extent[a];
            else
              inside = false;
          }
          if (!inside || !solid_at(n)) continue;
          // Fractions over (0, 1], both branches of the interpolation; wall speeds up to 0.05.
          const double q = 1.0 - unit(rng);
          const Eigen::Vector3d u_w = 0.05 * Eigen::Vector3d(unit(rng) - 0.5, unit(rng) - 0.5, unit(rng) - 0.5);
          o.links.push_back({{x, y, z}, k, q, u_w});
        }
      }
  return o;
}

struct Agreement {
  double populations = 0.0;  ///< largest difference of a fluid cell's population
  double momentum = 0.0;     ///< largest difference of a link's momentum exchange
};

/// Runs solver and reference side by side from the same random state; returns the largest
/// differences seen after any of `steps` steps.
Agreement compare_with(const SolverConfig& cfg, int steps, unsigned seed, const RefObstacle* obstacle) {
  const RefLattice lat = make_ref_lattice(cfg.lattice);
  auto solver = make_solver(cfg);
  Reference ref(cfg, lat);
  if (obstacle) {
    Obstacle o{.solid_cells = obstacle->solid, .links = obstacle->links, .rule = obstacle->rule, .far_solid_cells = {}};
    for (WallLink& link : o.links) link.dir = lat.solver_index[static_cast<std::size_t>(link.dir)];
    solver->set_obstacle(o);
    ref.set_obstacle(obstacle->solid, obstacle->links, obstacle->rule);
  }
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
  Agreement worst{max_difference(*solver, ref, lat), 0.0};
  for (int s = 0; s < steps; ++s) {
    solver->step();
    ref.step();
    worst.populations = std::max(worst.populations, max_difference(*solver, ref, lat));
    const auto& got = solver->wall_momentum();
    const auto& want = ref.wall_momentum();
    if (got.size() != want.size()) return {INFINITY, INFINITY};
    for (std::size_t m = 0; m < got.size(); ++m)
      worst.momentum = std::max(worst.momentum, (got[m] - want[m]).cwiseAbs().maxCoeff());
  }
  return worst;
}

double compare(const SolverConfig& cfg, int steps, unsigned seed) {
  return compare_with(cfg, steps, seed, nullptr).populations;
}

SolverConfig small_box(LatticeKind lattice, CollisionKind collision, Boundary bx, Boundary by, Boundary bz) {
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
  const auto cfg =
      small_box(LatticeKind::D3Q19, CollisionKind::trt, Boundary::periodic, Boundary::periodic, Boundary::periodic);
  EXPECT_LT(compare(cfg, kSteps, 1), kRoundOff);
}

TEST(LbmAaReference, MixedTrtD3Q19PeriodicXFreeSlipYNoSlipZ) {
  const auto cfg =
      small_box(LatticeKind::D3Q19, CollisionKind::trt, Boundary::periodic, Boundary::free_slip, Boundary::no_slip);
  EXPECT_LT(compare(cfg, kSteps, 2), kRoundOff);
}

TEST(LbmAaReference, MixedBgkD3Q19NoSlipXPeriodicYFreeSlipZ) {
  const auto cfg =
      small_box(LatticeKind::D3Q19, CollisionKind::bgk, Boundary::no_slip, Boundary::periodic, Boundary::free_slip);
  EXPECT_LT(compare(cfg, kSteps, 3), kRoundOff);
}

TEST(LbmAaReference, AllFreeSlipTrtD3Q27) {
  const auto cfg =
      small_box(LatticeKind::D3Q27, CollisionKind::trt, Boundary::free_slip, Boundary::free_slip, Boundary::free_slip);
  EXPECT_LT(compare(cfg, kSteps, 4), kRoundOff);
}

TEST(LbmAaReference, AllNoSlipBgkD3Q27) {
  const auto cfg =
      small_box(LatticeKind::D3Q27, CollisionKind::bgk, Boundary::no_slip, Boundary::no_slip, Boundary::no_slip);
  EXPECT_LT(compare(cfg, kSteps, 5), kRoundOff);
}

TEST(LbmAaReference, MixedFreeSlipXNoSlipYPeriodicZTrtD3Q27) {
  const auto cfg =
      small_box(LatticeKind::D3Q27, CollisionKind::trt, Boundary::free_slip, Boundary::no_slip, Boundary::periodic);
  EXPECT_LT(compare(cfg, kSteps, 6), kRoundOff);
}

TEST(LbmAaReference, RecursiveRegularizedD3Q27MatchesFullTensorForm) {
  auto cfg = small_box(LatticeKind::D3Q27, CollisionKind::recursive_regularized, Boundary::periodic, Boundary::no_slip,
                       Boundary::free_slip);
  cfg.tau = 0.52;
  EXPECT_LT(compare(cfg, kSteps, 7), kRoundOff);
}

TEST(LbmAaReference, CumulantD3Q27MatchesMomentSpaceReference) {
  // Low tau (omega_1 near 2) and the box's body force and random per-cell forces: the correction
  // terms, the forcing and the Chimera transforms all take part.
  auto cfg = small_box(LatticeKind::D3Q27, CollisionKind::cumulant, Boundary::no_slip, Boundary::periodic,
                       Boundary::free_slip);
  cfg.tau = 0.52;
  const double in_double = compare(cfg, kSteps, 14);
  cfg.precision = Precision::float32;
  const double in_float = compare(cfg, kSteps, 14);
  std::printf("cumulant vs moment-space reference, 5 steps: max |diff| %.1e (double), %.1e (float)\n", in_double,
              in_float);
  EXPECT_LT(in_double, kRoundOff);
  // As FloatStorageFollowsDoubleReference below: float rounding of f - w (<= 0.2 w) per step.
  EXPECT_LT(in_float, 1e-8);
}

TEST(LbmAaReference, SmagorinskyWithEveryOperator) {
  // The eddy viscosity set per cell from the cell's own stress, under each operator (the
  // recursive regularised one on D3Q27, where the reference's full tensor form holds). At tau =
  // 0.52 and C_S = 0.1 the random field's stress (|a2| ~ 0.05) moves tau by ~0.01, which moves
  // populations by ~1e-3: far above the round-off bound.
  for (const auto collision : {CollisionKind::bgk, CollisionKind::trt, CollisionKind::recursive_regularized}) {
    const LatticeKind lattice =
        collision == CollisionKind::recursive_regularized ? LatticeKind::D3Q27 : LatticeKind::D3Q19;
    auto cfg = small_box(lattice, collision, Boundary::periodic, Boundary::no_slip, Boundary::free_slip);
    cfg.tau = 0.52;
    cfg.subgrid = SubgridModel::smagorinsky;
    cfg.smagorinsky_constant = 0.1;
    const double difference = compare(cfg, kSteps, 14);
    EXPECT_LT(difference, kRoundOff) << to_string(collision);
    std::printf("AA vs reference, %s + Smagorinsky: max |diff| %.2e\n", to_string(collision).c_str(), difference);
  }
}

TEST(LbmAaReference, SingleCellThickPeriodicAxis) {
  // A periodic axis one cell thick (quasi-2D runs) wraps every link onto the cell itself.
  auto cfg =
      small_box(LatticeKind::D3Q19, CollisionKind::trt, Boundary::no_slip, Boundary::free_slip, Boundary::periodic);
  cfg.nz = 1;
  EXPECT_LT(compare(cfg, kSteps, 8), kRoundOff);
}

TEST(LbmAaReference, InletAndOutletOnZWithFreeSlipXPeriodicY) {
  for (const auto lattice : {LatticeKind::D3Q19, LatticeKind::D3Q27}) {
    auto cfg = small_box(lattice, CollisionKind::trt, Boundary::free_slip, Boundary::periodic, Boundary::no_slip);
    cfg.open_faces = {{{2, 0}, Boundary::velocity}, {{2, 1}, Boundary::outflow}};
    cfg.inflow_velocity = Eigen::Vector3d(0.01, -0.02, 0.05);
    EXPECT_LT(compare(cfg, kSteps, 10), kRoundOff) << to_string(lattice);
  }
}

TEST(LbmAaReference, OutletsMeetingAtAnEdgeAndNoSlipWalls) {
  // Outflow on x+ and y-, a velocity inlet on x-, no-slip on the rest: every edge kind meets.
  auto cfg = small_box(LatticeKind::D3Q27, CollisionKind::bgk, Boundary::no_slip, Boundary::no_slip, Boundary::no_slip);
  cfg.open_faces = {{{0, 1}, Boundary::outflow}, {{1, 0}, Boundary::outflow}, {{0, 0}, Boundary::velocity}};
  cfg.inflow_velocity = Eigen::Vector3d(0.04, 0.0, -0.01);
  EXPECT_LT(compare(cfg, kSteps, 11), kRoundOff);
}

TEST(LbmAaReference, ObstacleWithInterpolatedMovingWalls) {
  // A solid block, one of its cells across the periodic x faces, in a box with walls and an
  // inlet: every link takes a random q and wall velocity. Populations and the momentum exchange
  // of every link agree with the pull-form reference at both parities.
  for (const auto rule : {WallRule::bouzidi, WallRule::quadratic, WallRule::central_linear, WallRule::halfway}) {
    for (const auto lattice : {LatticeKind::D3Q19, LatticeKind::D3Q27}) {
      auto cfg = small_box(lattice, CollisionKind::trt, Boundary::periodic, Boundary::free_slip, Boundary::no_slip);
      cfg.nx = 8, cfg.ny = 7, cfg.nz = 6;
      cfg.open_faces = {{{2, 0}, Boundary::velocity}, {{2, 1}, Boundary::outflow}};
      cfg.inflow_velocity = Eigen::Vector3d(0.0, 0.0, 0.03);
      const RefLattice lat = make_ref_lattice(lattice);
      const RefObstacle obstacle =
          obstacle_around(cfg, lat, {{3, 3, 2}, {4, 3, 2}, {3, 4, 2}, {3, 3, 3}, {0, 1, 3}, {7, 1, 3}}, rule, 12);
      const Agreement a = compare_with(cfg, kSteps, 13, &obstacle);
      EXPECT_LT(a.populations, kRoundOff) << to_string(lattice);
      // Momenta are sums of two O(0.1) populations: the same round-off.
      EXPECT_LT(a.momentum, kRoundOff) << to_string(lattice);
    }
  }
}

TEST(LbmAaReference, FloatStorageFollowsDoubleReference) {
  auto cfg =
      small_box(LatticeKind::D3Q19, CollisionKind::trt, Boundary::periodic, Boundary::free_slip, Boundary::no_slip);
  cfg.precision = Precision::float32;
  // Float storage of f - w: |f - w| <= 0.2 w ~ 0.02, rounded to 2^-24 relative (1.2e-9)
  // each step, plus the per-cell forces stored in float (1e-3 * 6e-8). Five steps stay
  // well below 1e-8, while any indexing error is O(1e-2).
  EXPECT_LT(compare(cfg, kSteps, 9), 1e-8);
  // The Smagorinsky kernel in float arithmetic (its two square roots included), at the same tau: the
  // same bound (measured 7.5e-9). The model moves tau by ~0.005 here, populations by ~1e-4.
  // (Closer to tau = 1/2 the bound itself no longer holds: |1 - omega| -> 1 keeps each step's
  // rounding; plain TRT measured 1.4e-8 at tau = 0.52.)
  cfg.subgrid = SubgridModel::smagorinsky;
  EXPECT_LT(compare(cfg, kSteps, 15), 1e-8);
}

}  // namespace test_aa_reference
