#include "lbm/refined_lattice.hpp"

#include <stdexcept>

#include "lbm/collision.hpp"
#include "lbm/lattice.hpp"

namespace settle::lbm::refinement {

namespace {

using Lat = D3Q19;
constexpr int Q = RefinedLattice::Q;

/// One level's collision parameters: relaxation time, force density per lattice unit of the level,
/// and its time step in coarse time steps (1 or 1/2).
struct LevelParameters {
  double tau = 1.0;
  std::array<double, 3> force{};
  double dt = 1.0;
};

/// Guo's source term S_i for velocity u and force F (collision.hpp's header gives the formula).
double guo_source(int i, const std::array<double, 3>& u, const std::array<double, 3>& F) {
  const auto& c = Lat::set.c[i];
  const double cu = c[0] * u[0] + c[1] * u[1] + c[2] * u[2];
  const double cF = c[0] * F[0] + c[1] * F[1] + c[2] * F[2];
  const double uF = u[0] * F[0] + u[1] * F[1] + u[2] * F[2];
  return Lat::set.w[i] * (3.0 * (cF - uF) + 9.0 * cu * cF);
}

/// BGK with Guo forcing on one cell of shifted populations g (collision.hpp, "Storage"), written
/// here in the split form the rescaling needs: with the Guo-corrected non-equilibrium part
/// n_i = g_i - geq_i + S_i / 2 (zero mass and momentum), the post-collision state is
///   g*_i = geq_i + S_i / 2 + (1 - 1/tau) n_i,
/// which equals g - (g - geq)/tau + (1 - 1/(2 tau)) S (Guo, Zheng and Shi 2002,
/// doi:10.1103/PhysRevE.65.046308). This is the existing `Bgk` operator's arithmetic (same
/// equilibrium, same source), not its pair-wise code; the local form is used because the interface
/// needs geq, S and n separately.
///
/// `as_other` receives the same cell's post-collision state as the other level would hold it, the
/// Chapman-Enskog rescaling of Dupuis and Chopard (2003, doi:10.1103/PhysRevE.67.066707): the
/// non-equilibrium part is proportional to tau times the velocity gradient in lattice units (that
/// is, times dt), so n_other = (tau_other / tau) (dt_other / dt) n; the equilibrium is the same (the
/// lattice velocity is the same on both levels), the source uses the other level's force, and the
/// other level's relaxation is applied. Mass and momentum are those of `post` (n has none, sum S = 0,
/// and both states carry rho u + F_level / 2). Without rescaling, as_other = post.
void collide_cell(const double* g, const LevelParameters& self, const LevelParameters& other, bool rescale,
                  double* post, double* as_other) {
  const double zero_force[3] = {0.0, 0.0, 0.0};
  const auto m = macroscopic<Lat, double>(g, zero_force);
  const double drho = m.drho, rho = m.rho;
  const std::array<double, 3> u = {(m.ux * rho + 0.5 * self.force[0]) / rho, (m.uy * rho + 0.5 * self.force[1]) / rho,
                                   (m.uz * rho + 0.5 * self.force[2]) / rho};
  const double keep = 1.0 - 1.0 / self.tau;
  const double ratio = (other.tau / self.tau) * (other.dt / self.dt);
  const double keep_other = (1.0 - 1.0 / other.tau) * ratio;
  for (int i = 0; i < Q; ++i) {
    const double geq = shifted_equilibrium<Lat>(i, drho, rho, u[0], u[1], u[2]);
    const double source = guo_source(i, u, self.force);
    const double n = g[i] - geq + 0.5 * source;
    post[i] = geq + 0.5 * source + keep * n;
    if (as_other == nullptr) continue;
    as_other[i] = rescale ? geq + 0.5 * guo_source(i, u, other.force) + keep_other * n : post[i];
  }
}

CellMoments moments_of(const double* g, const std::array<double, 3>& force) {
  const auto m = macroscopic<Lat, double>(g, force.data());
  return {m.rho, {m.ux, m.uy, m.uz}};
}

int floor_half(int a) { return a >= 0 ? a / 2 : -((1 - a) / 2); }

}  // namespace

RefinedLattice::RefinedLattice(const RefinedLatticeConfig& config) : config_(config) {
  const auto& box = config_.fine_box;
  for (int d = 0; d < 3; ++d) {
    // One coarse cell between the box and every face: the interface layer is made of coarse fluid
    // cells and needs no periodic wrap or wall of its own.
    if (box.lo[d] < 1 || box.hi[d] > config_.coarse_cells[d] - 1 || box.hi[d] <= box.lo[d])
      throw std::invalid_argument("refined lattice: the fine box must keep one coarse cell from every face");
    fine_cells_[d] = 2 * (box.hi[d] - box.lo[d]);
  }
  // Same physical viscosity: cs^2 (tau_f - 1/2) dx_f^2 / dt_f = cs^2 (tau_c - 1/2) dx_c^2 / dt_c.
  tau_fine_ = 2.0 * (config_.tau_coarse - 0.5) + 0.5;
  const std::size_t coarse_size =
      static_cast<std::size_t>(config_.coarse_cells[0]) * config_.coarse_cells[1] * config_.coarse_cells[2] * Q;
  const std::size_t fine_size = static_cast<std::size_t>(fine_cells_[0]) * fine_cells_[1] * fine_cells_[2] * Q;
  for (auto* v : {&coarse_, &coarse_post_, &coarse_exploded_, &coarse_fine_share_, &coarse_coalesced_})
    v->assign(coarse_size, 0.0);
  for (auto* v : {&fine_, &fine_post_, &fine_post_as_coarse_}) v->assign(fine_size, 0.0);
  for (auto* v : {&coarse_post_slope_, &coarse_exploded_slope_, &coarse_entering_offset_})
    v->assign(3 * coarse_size, 0.0);
  for (int z = box.lo[2] - 1; z <= box.hi[2]; ++z)
    for (int y = box.lo[1] - 1; y <= box.hi[1]; ++y)
      for (int x = box.lo[0] - 1; x <= box.hi[0]; ++x) {
        if (covered(x, y, z)) continue;
        for (int i = 0; i < Q; ++i) {
          const std::size_t at = static_cast<std::size_t>(coarse_index(x, y, z)) * Q + i;
          int count = 0;
          std::array<double, 3> offsets{};
          children_entering(x, y, z, i, count, offsets);
          coarse_fine_share_[at] = count / 8.0;
          for (int d = 0; d < 3; ++d) coarse_entering_offset_[3 * at + d] = offsets[d];
        }
      }
}

int RefinedLattice::coarse_index(int x, int y, int z) const {
  const auto& n = config_.coarse_cells;
  return (z * n[1] + y) * n[0] + x;
}

int RefinedLattice::fine_index(int a, int b, int c) const { return (c * fine_cells_[1] + b) * fine_cells_[0] + a; }

bool RefinedLattice::in_fine_box(int a, int b, int c) const {
  return a >= 0 && a < fine_cells_[0] && b >= 0 && b < fine_cells_[1] && c >= 0 && c < fine_cells_[2];
}

int RefinedLattice::parent_of_fine(int a, int b, int c) const {
  const auto& lo = config_.fine_box.lo;
  return coarse_index(lo[0] + floor_half(a), lo[1] + floor_half(b), lo[2] + floor_half(c));
}

/// Offset of fine cell a's centre from its parent's centre, in coarse cells: -1/4 or +1/4.
double child_offset(int a) { return a - 2 * floor_half(a) == 1 ? 0.25 : -0.25; }

// The children of coarse cell X whose population i the fine level takes during the coarse step: the
// explosion gives X's value to its 8 children, the fine level streams them twice (the ghost children
// are not collided), and a child's value enters the box at the first fine step (y + c inside) or at
// the second (y + 2c inside; a box being convex, y + c is then in the ghost layer). The coarse
// streaming passes on the rest, so that a uniform state stays uniform and mass is exact
// (docs/lbm.md, "Grid refinement").
void RefinedLattice::children_entering(int x, int y, int z, int i, int& count,
                                       std::array<double, 3>& offset_sum) const {
  const auto& lo = config_.fine_box.lo;
  const auto& c = Lat::set.c[i];
  count = 0;
  offset_sum = {0.0, 0.0, 0.0};
  for (int k = 0; k < 8; ++k) {
    const int a = 2 * (x - lo[0]) + (k & 1), b = 2 * (y - lo[1]) + ((k >> 1) & 1), cz = 2 * (z - lo[2]) + (k >> 2);
    if (!in_fine_box(a + c[0], b + c[1], cz + c[2]) && !in_fine_box(a + 2 * c[0], b + 2 * c[1], cz + 2 * c[2]))
      continue;
    ++count;
    offset_sum[0] += child_offset(a);
    offset_sum[1] += child_offset(b);
    offset_sum[2] += child_offset(cz);
  }
}

int RefinedLattice::uncovered_neighbour(int x, int y, int z) const {
  const auto& n = config_.coarse_cells;
  if (config_.walls_y && (y < 0 || y >= n[1])) return -1;
  const auto wrap = [](int v, int size) { return ((v % size) + size) % size; };
  x = wrap(x, n[0]);
  y = wrap(y, n[1]);
  z = wrap(z, n[2]);
  return covered(x, y, z) ? -1 : coarse_index(x, y, z);
}

// Slopes per coarse cell of each population: central differences, one-sided where a neighbour is
// covered by the box or past a wall (second order in the cell, first order there).
void RefinedLattice::compute_slopes(const std::vector<double>& values, std::vector<double>& slopes, int x, int y,
                                    int z) const {
  const int cell = coarse_index(x, y, z);
  for (int d = 0; d < 3; ++d) {
    const int e[3] = {d == 0, d == 1, d == 2};
    const int up = uncovered_neighbour(x + e[0], y + e[1], z + e[2]);
    const int down = uncovered_neighbour(x - e[0], y - e[1], z - e[2]);
    for (int i = 0; i < Q; ++i) {
      const double here = values[static_cast<std::size_t>(cell) * Q + i];
      const double above = up >= 0 ? values[static_cast<std::size_t>(up) * Q + i] : here;
      const double below = down >= 0 ? values[static_cast<std::size_t>(down) * Q + i] : here;
      const double span = (up >= 0 ? 1.0 : 0.0) + (down >= 0 ? 1.0 : 0.0);
      slopes[3 * (static_cast<std::size_t>(cell) * Q + i) + d] = span > 0.0 ? (above - below) / span : 0.0;
    }
  }
}

void RefinedLattice::initialise(const InitialState& state) {
  const auto& n = config_.coarse_cells;
  const auto fill = [](double* g, const CellMoments& s) {
    for (int i = 0; i < Q; ++i) g[i] = shifted_equilibrium<Lat>(i, s.rho - 1.0, s.rho, s.u[0], s.u[1], s.u[2]);
  };
  for (int z = 0; z < n[2]; ++z)
    for (int y = 0; y < n[1]; ++y)
      for (int x = 0; x < n[0]; ++x)
        if (!covered(x, y, z)) fill(&coarse_[coarse_index(x, y, z) * Q], state(x + 0.5, y + 0.5, z + 0.5));
  const auto& lo = config_.fine_box.lo;
  for (int c = 0; c < fine_cells_[2]; ++c)
    for (int b = 0; b < fine_cells_[1]; ++b)
      for (int a = 0; a < fine_cells_[0]; ++a)
        fill(&fine_[fine_index(a, b, c) * Q],
             state(lo[0] + 0.5 * (a + 0.5), lo[1] + 0.5 * (b + 0.5), lo[2] + 0.5 * (c + 0.5)));
}

// The order of Rohde et al. (2006): the coarse level collides, its interface cells explode into the
// fine ghost layer, the fine level makes its two steps against that ghost layer, and the coarse level
// streams, taking in what the fine level sent out (coalescence).
void RefinedLattice::step() {
  collide_coarse();
  explode();
  fine_substep(1);
  fine_substep(2);
  stream_coarse();
}

namespace {
LevelParameters coarse_parameters(const RefinedLatticeConfig& cfg) { return {cfg.tau_coarse, cfg.force_coarse, 1.0}; }
// Acoustic scaling: a force density (an acceleration times a density) per lattice unit scales as
// dt^2 / dx, so the fine level's is half the coarse level's.
LevelParameters fine_parameters(const RefinedLatticeConfig& cfg, double tau_fine) {
  return {tau_fine, {0.5 * cfg.force_coarse[0], 0.5 * cfg.force_coarse[1], 0.5 * cfg.force_coarse[2]}, 0.5};
}
}  // namespace

void RefinedLattice::collide_coarse() {
  const auto self = coarse_parameters(config_);
  const auto& n = config_.coarse_cells;
  for (int z = 0; z < n[2]; ++z)
    for (int y = 0; y < n[1]; ++y)
      for (int x = 0; x < n[0]; ++x) {
        if (covered(x, y, z)) continue;
        const int cell = coarse_index(x, y, z) * Q;
        collide_cell(&coarse_[cell], self, self, false, &coarse_post_[cell], nullptr);
      }
}

// Explosion: the post-collision state of the cells around the box as the fine level holds it
// (rescaled or copied, collide_cell), and, for the linear explosion, the slopes of it and of the
// coarse post-collision state in the interface cells. A child's value is the parent's plus its
// offset (+-1/4 per axis) times the slope; the 8 children average to the parent's value (Rohde et
// al. 2006's homogeneous distribution is the case of zero slopes).
void RefinedLattice::explode() {
  const auto coarse = coarse_parameters(config_);
  const auto fine = fine_parameters(config_, tau_fine_);
  const auto& box = config_.fine_box;
  double scratch[Q];
  // The interface layer and its neighbours, whose values the slopes read.
  for (int z = box.lo[2] - 2; z <= box.hi[2] + 1; ++z)
    for (int y = box.lo[1] - 2; y <= box.hi[1] + 1; ++y)
      for (int x = box.lo[0] - 2; x <= box.hi[0] + 1; ++x) {
        const int cell = uncovered_neighbour(x, y, z);
        if (cell < 0) continue;
        collide_cell(&coarse_[cell * Q], coarse, fine, config_.rescale_non_equilibrium, scratch,
                     &coarse_exploded_[cell * Q]);
      }
  if (!config_.linear_explosion) return;
  for (int z = box.lo[2] - 1; z <= box.hi[2]; ++z)
    for (int y = box.lo[1] - 1; y <= box.hi[1]; ++y)
      for (int x = box.lo[0] - 1; x <= box.hi[0]; ++x) {
        if (covered(x, y, z)) continue;
        compute_slopes(coarse_exploded_, coarse_exploded_slope_, x, y, z);
        compute_slopes(coarse_post_, coarse_post_slope_, x, y, z);
      }
}

void RefinedLattice::fine_substep(int substep) {
  collide_fine();
  accumulate_coalescence(substep);
  stream_fine(substep);
}

void RefinedLattice::collide_fine() {
  const auto fine = fine_parameters(config_, tau_fine_);
  const auto coarse = coarse_parameters(config_);
  for (int c = 0; c < fine_cells_[2]; ++c)
    for (int b = 0; b < fine_cells_[1]; ++b)
      for (int a = 0; a < fine_cells_[0]; ++a) {
        const int cell = fine_index(a, b, c) * Q;
        // Only the outer fine layer sends populations out of the box.
        const bool outer =
            a == 0 || b == 0 || c == 0 || a == fine_cells_[0] - 1 || b == fine_cells_[1] - 1 || c == fine_cells_[2] - 1;
        collide_cell(&fine_[cell], fine, coarse, config_.rescale_non_equilibrium, &fine_post_[cell],
                     outer ? &fine_post_as_coarse_[cell] : nullptr);
      }
}

// Pull streaming on the fine level. A population coming from outside the box is the explosion value
// of the ghost child it started from: at the first fine step the child x - c; at the second, the
// child x - 2c, whose value streamed into x - c at the first (the ghost layer streams but does not
// collide). A child's value is its parent's plus its offset times the parent's slope (explode). With
// the rescaling, the value differs from the coarse population it stands for (the same profile of
// the coarse post-collision state); the difference goes to the rest population so that the cell
// receives exactly the mass the coarse level gave.
void RefinedLattice::stream_fine(int substep) {
  const int reach = substep == 1 ? 1 : 2;
  for (int c = 0; c < fine_cells_[2]; ++c)
    for (int b = 0; b < fine_cells_[1]; ++b)
      for (int a = 0; a < fine_cells_[0]; ++a) {
        double* g = &fine_[fine_index(a, b, c) * Q];
        for (int i = 0; i < Q; ++i) {
          const auto& v = Lat::set.c[i];
          if (in_fine_box(a - v[0], b - v[1], c - v[2])) {
            g[i] = fine_post_[fine_index(a - v[0], b - v[1], c - v[2]) * Q + i];
            continue;
          }
          const int ga = a - reach * v[0], gb = b - reach * v[1], gc = c - reach * v[2];
          const std::size_t at = static_cast<std::size_t>(parent_of_fine(ga, gb, gc)) * Q + i;
          const double offset[3] = {child_offset(ga), child_offset(gb), child_offset(gc)};
          double value = coarse_exploded_[at], mass = coarse_post_[at];
          for (int d = 0; d < 3; ++d) {
            value += offset[d] * coarse_exploded_slope_[3 * at + d];
            mass += offset[d] * coarse_post_slope_[3 * at + d];
          }
          g[i] = value;
          g[0] += mass - value;
        }
      }
}

// Coalescence: a population leaving the box is carried by the ghost layer to where it is at the end
// of the coarse step (x + 2c if it left at the first fine step, x + c at the second; a box being
// convex, neither is back inside) and added, with the volume weight 1/8, to that coarse cell's
// population. With the rescaling, the value is the fine cell's state as the coarse level holds it
// and the difference of mass goes to the coarse cell's rest population.
void RefinedLattice::accumulate_coalescence(int substep) {
  const int reach = substep == 1 ? 2 : 1;
  for (int c = 0; c < fine_cells_[2]; ++c)
    for (int b = 0; b < fine_cells_[1]; ++b)
      for (int a = 0; a < fine_cells_[0]; ++a) {
        const int cell = fine_index(a, b, c) * Q;
        for (int i = 1; i < Q; ++i) {
          const auto& v = Lat::set.c[i];
          if (in_fine_box(a + v[0], b + v[1], c + v[2])) continue;
          const int target = parent_of_fine(a + reach * v[0], b + reach * v[1], c + reach * v[2]) * Q;
          coarse_coalesced_[target + i] += 0.125 * fine_post_as_coarse_[cell + i];
          coarse_coalesced_[target] += 0.125 * (fine_post_[cell + i] - fine_post_as_coarse_[cell + i]);
        }
      }
}

// Pull streaming on the coarse level: from an uncovered neighbour what the fine level did not take,
// from a covered one nothing, from a wall (half-way bounce-back) the cell's own opposite population;
// then the coalescence gathered over the two fine steps.
void RefinedLattice::stream_coarse() {
  const auto& n = config_.coarse_cells;
  const auto wrap = [](int v, int size) { return (v + size) % size; };
  for (int z = 0; z < n[2]; ++z)
    for (int y = 0; y < n[1]; ++y)
      for (int x = 0; x < n[0]; ++x) {
        if (covered(x, y, z)) continue;
        const int cell = coarse_index(x, y, z) * Q;
        for (int i = 0; i < Q; ++i) {
          const auto& v = Lat::set.c[i];
          const int sy = y - v[1];
          int source = 0, j = i;
          if (config_.walls_y && (sy < 0 || sy >= n[1])) {
            source = cell;
            j = opposite(i);
          } else {
            const int sx = wrap(x - v[0], n[0]), sz = wrap(z - v[2], n[2]), syw = wrap(sy, n[1]);
            if (covered(sx, syw, sz)) {
              coarse_[cell + i] = 0.0;
              continue;
            }
            source = coarse_index(sx, syw, sz) * Q;
          }
          // What the fine level took: its share of the children, each the linear profile's value.
          const std::size_t at = static_cast<std::size_t>(source) + j;
          double taken = coarse_fine_share_[at] * coarse_post_[at];
          for (int d = 0; d < 3; ++d)
            taken += 0.125 * coarse_entering_offset_[3 * at + d] * coarse_post_slope_[3 * at + d];
          coarse_[cell + i] = coarse_post_[at] - taken;
        }
        for (int i = 0; i < Q; ++i) {
          coarse_[cell + i] += coarse_coalesced_[cell + i];
          coarse_coalesced_[cell + i] = 0.0;
        }
      }
}

CellMoments RefinedLattice::coarse_moments(int x, int y, int z) const {
  return moments_of(&coarse_[coarse_index(x, y, z) * Q], config_.force_coarse);
}

CellMoments RefinedLattice::fine_moments(int a, int b, int c) const {
  return moments_of(&fine_[fine_index(a, b, c) * Q], fine_parameters(config_, tau_fine_).force);
}

double RefinedLattice::mass_deviation() const {
  const auto& n = config_.coarse_cells;
  double coarse = 0.0, fine = 0.0;
  for (int z = 0; z < n[2]; ++z)
    for (int y = 0; y < n[1]; ++y)
      for (int x = 0; x < n[0]; ++x) {
        if (covered(x, y, z)) continue;
        for (int i = 0; i < Q; ++i) coarse += coarse_[coarse_index(x, y, z) * Q + i];
      }
  for (const double g : fine_) fine += g;
  return coarse + 0.125 * fine;
}

}  // namespace settle::lbm::refinement
