#pragma once
// The AA pattern's kernel (Bailey, Myre, Walsh, Lilja & Saar 2009, doi:10.1109/ICPP.2009.37): the
// collision of every interior cell of a block with its reads and writes in the one population
// array (lbm/aa_populations.hpp), templated over lattice, collision and storage type so that the
// hot loop sees compile-time constants. In short, with A[q][x] the stored value of direction q at
// padded cell x and g = f - w (collision.hpp):
//  - even step: g_i(x) = A[i][x]; collide; A[opp(i)][x] = g*_i(x). No neighbour access.
//  - odd step: g_i(x) = A[opp(i)][x - c_i]; collide; A[i][x + c_i] = g*_i(x).
// After an odd step A[i][x] = g_i(x) again (the natural layout). Boundaries are handled by the two
// copy lists of lbm/grid.hpp between steps, so the kernel has no branch. The relaxation rates are
// built here (AaKernel's constructor) and the collision is called in collide_row, nowhere else.
#include <omp.h>

#include <vector>

#include "lbm/aa_populations.hpp"
#include "lbm/collision.hpp"
#include "lbm/config.hpp"
#include "lbm/force_field.hpp"
#include "lbm/lattice.hpp"

namespace settle::lbm {

template <Lattice L, class Collision, class Real>
class AaKernel {
 public:
  static constexpr int Q = L::Q;
  /// Arithmetic type of the collision: float storage is computed in float. The stored
  /// values are f - w (collision.hpp), so float arithmetic keeps the same ~7 significant
  /// digits of the deviations that float storage keeps, at half the vector work (the float
  /// kernel is otherwise compute-bound on AVX-512; see docs/lbm.md).
  using Arith = Real;

  AaKernel(const SolverConfig& config, bool threaded)
      : body_force_{config.body_force.x(), config.body_force.y(), config.body_force.z()},
        rates_(config.collision == CollisionKind::trt ? trt_rates(config.tau, config.magic)
                                                      : RelaxationRates{1.0 / config.tau, 1.0 / config.tau}),
        threaded_(threaded) {
    // Read only by the Smagorinsky variants (the factory chooses Collision = Smagorinsky<...>).
    rates_.smagorinsky = smagorinsky_constants(config.tau, config.smagorinsky_constant, config.magic);
  }

  /// The hot loop: one AA step over all interior cells. Rows of x are contiguous in every
  /// population array (the odd step's neighbour offsets are constant along a row), so the
  /// x loop in collide_row is a vectorised loop of unit-stride loads and stores; the lattice
  /// constants fold at compile time. Vectorisation checked with -fopt-info-vec-optimized
  /// ("loop vectorized using 64 byte vectors" for every instantiation with SETTLE_NATIVE) and
  /// zmm instructions in the disassembly, see docs/lbm.md.
  template <bool Odd>
  void run(AaPopulations<L, Real>& f, const ForceField<Real>& force) const {
    const Sweep k = sweep(f, force);
    const int ny = k.ny, nz = f.layout().nz;
#pragma omp parallel for collapse(2) schedule(static) if (threaded_)
    for (int z = 0; z < nz; ++z) {
      for (int y = 0; y < ny; ++y) row<Odd>(k, y, z);
    }
  }

  /// The kernel on a list of rows (y + ny z): a block's face rows, then its interior rows, so that
  /// its messages travel while the interior is updated. Every cell reads and writes only its own
  /// slots in either parity, so the rows may run in any order with the same result.
  template <bool Odd>
  void run_rows(AaPopulations<L, Real>& f, const ForceField<Real>& force, const std::vector<int>& rows) const {
    const Sweep k = sweep(f, force);
    const int ny = k.ny, count = static_cast<int>(rows.size());
#pragma omp parallel for schedule(static) if (threaded_)
    for (int n = 0; n < count; ++n)
      row<Odd>(k, rows[static_cast<std::size_t>(n)] % ny, rows[static_cast<std::size_t>(n)] / ny);
  }

 private:
  /// What every row of one sweep shares: the population and force arrays, the lattice's
  /// offsets and the relaxation rates.
  struct Sweep {
    Real* base;
    const Real* force[3];
    std::ptrdiff_t offsets[Q];
    std::size_t stride;
    double body[3];
    RelaxationRates rates;
    const GridLayout* layout;
    int nx, ny;
  };

  Sweep sweep(AaPopulations<L, Real>& f, const ForceField<Real>& force) const {
    const GridLayout& layout = f.layout();
    Sweep k{f.data(),
            {force.component(0), force.component(1), force.component(2)},
            {},
            layout.pop_stride,
            {body_force_[0], body_force_[1], body_force_[2]},
            rates_,
            &layout,
            layout.nx,
            layout.ny};
    for (int i = 0; i < Q; ++i) k.offsets[i] = layout.offset(L::set.c[i]);
    return k;
  }

  template <bool Odd>
  static void row(const Sweep& k, int y, int z) {
    const std::size_t row = k.layout->index(0, y, z);
    Real* src[Q];
    Real* dst[Q];
    for (int i = 0; i < Q; ++i) {
      if constexpr (Odd) {
        src[i] = k.base + static_cast<std::size_t>(opposite(i)) * k.stride + row - k.offsets[i];
        dst[i] = k.base + static_cast<std::size_t>(i) * k.stride + row + k.offsets[i];
      } else {
        src[i] = k.base + static_cast<std::size_t>(i) * k.stride + row;
        dst[i] = k.base + static_cast<std::size_t>(opposite(i)) * k.stride + row;
      }
    }
    const std::size_t force_row =
        static_cast<std::size_t>(k.nx) *
        (static_cast<std::size_t>(y) + static_cast<std::size_t>(k.ny) * static_cast<std::size_t>(z));
    collide_row(src, dst, k.force[0] + force_row, k.force[1] + force_row, k.force[2] + force_row, k.nx, k.body,
                k.rates);
  }

  static void collide_row(Real* const (&src)[Q], Real* const (&dst)[Q], const Real* __restrict fx,
                          const Real* __restrict fy, const Real* __restrict fz, int n, const double (&body)[3],
                          const RelaxationRates& rates) {
    // Local copies of the row pointers: loop-invariant scalars the vectoriser can use as
    // bases of unit-stride accesses (through the reference it reloads them per element).
    Real* in[Q];
    Real* out[Q];
    for (int i = 0; i < Q; ++i) {
      in[i] = src[i];
      out[i] = dst[i];
    }
    // Lanes are independent: in either parity, the slots a cell reads are exactly the slots
    // it writes, and no two cells share a slot, so `ivdep` (no loop-carried dependence) is
    // true. (`omp simd` made GCC 12 keep the row pointers in memory and give up.)
    const Arith body_x = static_cast<Arith>(body[0]), body_y = static_cast<Arith>(body[1]),
                body_z = static_cast<Arith>(body[2]);
#if !defined(__clang__)  // clang's sanitizer build (-O1) does not vectorise
#pragma GCC ivdep
#endif
    for (int x = 0; x < n; ++x) {
      Arith g[Q];
#pragma GCC unroll 32
      for (int i = 0; i < Q; ++i) g[i] = static_cast<Arith>(in[i][x]);
      const Arith F[3] = {body_x + static_cast<Arith>(fx[x]), body_y + static_cast<Arith>(fy[x]),
                          body_z + static_cast<Arith>(fz[x])};
      Collision::template collide<L, Arith>(g, F, rates);
#pragma GCC unroll 32
      for (int i = 0; i < Q; ++i) out[i][x] = static_cast<Real>(g[i]);
    }
  }

  double body_force_[3];
  RelaxationRates rates_;
  bool threaded_;
};

}  // namespace settle::lbm
