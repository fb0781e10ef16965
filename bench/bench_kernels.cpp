// Micro-benchmarks of settle's kernels (Google Benchmark), for developers comparing changes.
// The user-facing fluid benchmark with the bandwidth roofline is `settle bench`.
#include <benchmark/benchmark.h>

#include <omp.h>
#include <sys/mman.h>

#include <algorithm>
#include <cmath>
#include <cstdlib>
#include <memory>
#include <numbers>

#include "attitude/integrators.hpp"
#include "body/ellipsoid.hpp"
#include "body/shape_factory.hpp"
#include "coupling/immersed_body.hpp"
#include "coupling/immersed_boundary_coupling.hpp"
#include "coupling/momentum_exchange.hpp"
#include "ibm/forcing.hpp"
#include "lbm/solver.hpp"

namespace {

using namespace settle;

// One fluid step of a periodic N^3 box, D3Q19 TRT with forcing, double or float storage.
void BM_LbmStep(benchmark::State& state) {
  lbm::SolverConfig config;
  config.nx = config.ny = config.nz = static_cast<int>(state.range(0));
  config.precision = state.range(1) ? lbm::Precision::float32 : lbm::Precision::float64;
  config.body_force = Eigen::Vector3d(1e-7, 0.0, 0.0);
  auto solver = lbm::make_solver(config);
  solver->initialise([](int, int, int) { return lbm::CellState{}; });
  solver->run(2);
  for (auto _ : state) solver->step();
  state.counters["MLUPS"] = benchmark::Counter(static_cast<double>(solver->cell_count()) * 1e-6,
                                               benchmark::Counter::kIsIterationInvariantRate);
}
BENCHMARK(BM_LbmStep)->ArgsProduct({{64, 128}, {0, 1}})->Unit(benchmark::kMillisecond);

// One dual-Euler RK4 step with interpolated body rates (the coupled solver's form).
void BM_DualEulerStep(benchmark::State& state) {
  attitude::Attitude a = attitude::Attitude::from_set1(0.3, 0.7, -0.2);
  const Eigen::Vector3d w0(0.1, 1.0, -0.3), w1(0.11, 0.99, -0.29);
  for (auto _ : state) {
    attitude::dual_euler_step(a, 1e-3, w0, w1);
    benchmark::DoNotOptimize(a);
  }
}
BENCHMARK(BM_DualEulerStep);

// Multi-direct forcing on a sphere of radius R cells (about 4 pi R^2 markers), 3 sweeps.
void BM_MultiDirectForcing(benchmark::State& state) {
  const double radius = static_cast<double>(state.range(0));
  const int box = static_cast<int>(2 * radius) + 8;
  const int n = static_cast<int>(std::round(4.0 * std::numbers::pi * radius * radius));
  ibm::Markers markers;
  const double golden = std::numbers::pi * (3.0 - std::sqrt(5.0));
  const Eigen::Vector3d centre = Eigen::Vector3d::Constant(box / 2.0);
  for (int l = 0; l < n; ++l) {
    const double z = 1.0 - (2.0 * l + 1.0) / n, r = std::sqrt(1.0 - z * z);
    markers.position.push_back(centre +
                               radius * Eigen::Vector3d(r * std::cos(golden * l), r * std::sin(golden * l), z));
    markers.target_velocity.push_back(Eigen::Vector3d::Zero());
    markers.volume.push_back(4.0 * std::numbers::pi * radius * radius / n);
  }
  for (auto _ : state) {
    ibm::LocalGrid grid({0, 0, 0}, {box, box, box});
    for (auto& u : grid.velocity[0]) u = 0.01;
    benchmark::DoNotOptimize(ibm::multi_direct_forcing(grid, markers, {ibm::DeltaKernel::Roma3, 3}));
  }
  state.counters["markers"] = n;
}
BENCHMARK(BM_MultiDirectForcing)->Arg(3)->Arg(8)->Arg(10)->Unit(benchmark::kMicrosecond);

// Volume fractions of the cells the default case's body overlaps (a prolate spheroid of aspect
// ratio 2 at 8 cells per equivalent diameter, tilted 0.5 rad, off the grid's symmetric positions):
// the immersed boundary's internal-momentum sum evaluates them once per step.
// range(0): 0 exact signed distances, 1 interpolated from the coupling's table.
void BM_SpheroidSolidCells(benchmark::State& state) {
  const double dx_si = 1.26e-3 / 8.0;
  const auto shared = std::make_shared<const body::Ellipsoid>(body::Ellipsoid::spheroid(1.0e-3, 2.0));
  const body::Ellipsoid& shape = *shared;
  const body::DistanceTable table(shared, 0.25 * dx_si, 2.5 * dx_si, 2.5 * dx_si);
  const Eigen::Vector3d centre(24.3, 23.8, 48.1);
  const Eigen::Matrix3d rotation = Eigen::AngleAxisd(0.5, Eigen::Vector3d::UnitY()).toRotationMatrix();
  const coupling::CellBox box =
      coupling::immersed_boundary_box(shape, dx_si, ibm::DeltaKernel::Roma3, centre, rotation);
  std::size_t cells = 0;
  for (auto _ : state) {
    const coupling::SolidCells solid = state.range(0) ? coupling::solid_cells(table, dx_si, box, centre, rotation)
                                                      : coupling::solid_cells(shape, dx_si, box, centre, rotation);
    cells = solid.cell.size();
    benchmark::DoNotOptimize(solid.alpha.data());
  }
  state.counters["cells"] = static_cast<double>(cells);
}
BENCHMARK(BM_SpheroidSolidCells)->Arg(0)->Arg(1)->Unit(benchmark::kMicrosecond);

// The momentum exchange's walls at one pose (the `markers` sub-step of `settle bench --case`):
// range(0) 0 the rounded cube (superellipsoid, exponents 0.4, 12 cells per d_eq), 1 the shipped
// grain (cases/grain.stl, 10 cells per d_eq), 2 a sphere of 10 cells; at a generic tilt and off the
// grid's symmetric positions, the pose advancing a little every iteration as in a run.
void BM_MomentumExchangeWalls(benchmark::State& state) {
  body::ShapeSpec spec;
  double cells_per_diameter = 10.0;
  if (state.range(0) == 0) {
    spec.shape = "superellipsoid", spec.semi_axes = {{0.5e-3, 0.5e-3, 0.5e-3}}, spec.exponents = {{0.4, 0.4}};
    cells_per_diameter = 12.0;
  } else if (state.range(0) == 1) {
    spec.shape = "mesh", spec.file = std::string(SETTLE_SOURCE_DIR) + "/cases/grain.stl", spec.scale = 5.0e-4;
  } else {
    spec.shape = "sphere", spec.diameter = 1.0e-3;
  }
  const std::shared_ptr<const body::Shape> shape = body::make_shape(spec);
  const double dx_si = shape->equivalent_diameter() / cells_per_diameter;
  const auto inside_table = coupling::inside_table_for(shape, dx_si);  // the coupling's, built once
  coupling::LatticePose pose;
  pose.velocity = Eigen::Vector3d(0.001, -0.002, -0.03);
  pose.angular_velocity_n = Eigen::Vector3d(1e-3, 2e-3, -1e-3);
  const auto velocities = lbm::velocity_set(lbm::LatticeKind::D3Q19);
  std::size_t links = 0;
  int step = 0;
  for (auto _ : state) {
    pose.centre = Eigen::Vector3d(40.3, 41.7, 60.2) + static_cast<double>(step % 64) * pose.velocity;
    pose.body_to_inertial =
        (Eigen::AngleAxisd(0.4 + 1e-3 * (step % 64), Eigen::Vector3d::UnitZ()) *
         Eigen::AngleAxisd(0.5, Eigen::Vector3d::UnitY()) * Eigen::AngleAxisd(0.6, Eigen::Vector3d::UnitX()))
            .toRotationMatrix();
    ++step;
    const coupling::CellBox box = coupling::momentum_exchange_box(*shape, dx_si, pose.centre, pose.body_to_inertial);
    const coupling::BodyWalls walls =
        coupling::body_walls(*shape, dx_si, box, pose, velocities, lbm::WallRule::bouzidi, inside_table.get());
    links = walls.obstacle.links.size();
    benchmark::DoNotOptimize(walls.crossing.data());
  }
  state.counters["links"] = static_cast<double>(links);
}
BENCHMARK(BM_MomentumExchangeWalls)->Arg(0)->Arg(1)->Arg(2)->Unit(benchmark::kMicrosecond)->UseRealTime();

// Density and velocity of every cell of a 13 x 13 x 16 box of a 48 x 48 x 96 float grid (the
// immersed boundary's gather of the default case's body), after an odd (range(0) = 0) or even (1)
// step count.
void BM_CellStatesOfBox(benchmark::State& state) {
  lbm::SolverConfig config;
  config.nx = config.ny = 48;
  config.nz = 96;
  config.precision = lbm::Precision::float32;
  auto solver = lbm::make_solver(config);
  solver->initialise([](int, int, int) { return lbm::CellState{}; });
  solver->run(state.range(0) ? 2 : 1);
  const coupling::CellBox box{{18, 18, 40}, {13, 13, 16}};
  const std::vector<std::array<int, 3>> cells = coupling::cells_of(box);
  std::vector<double> rho(cells.size());
  std::array<std::vector<double>, 3> u{rho, rho, rho};
  for (auto _ : state) {
    if (state.range(1)) {
      solver->box_states(box.origin, box.extent, rho.data(), {u[0].data(), u[1].data(), u[2].data()});
    } else {
      for (std::size_t n = 0; n < cells.size(); ++n) {
        const lbm::CellState c = solver->cell_state(cells[n][0], cells[n][1], cells[n][2]);
        rho[n] = c.density;
        for (int a = 0; a < 3; ++a) u[static_cast<std::size_t>(a)][n] = c.velocity[a];
      }
    }
    benchmark::DoNotOptimize(rho.data());
  }
  state.counters["cells"] = static_cast<double>(cells.size());
}
// range(1): 0 cell_state cell by cell, 1 box_states (rows)
BENCHMARK(BM_CellStatesOfBox)->ArgsProduct({{0, 1}, {0, 1}})->Unit(benchmark::kMicrosecond);

// In-place read-modify-write of Q arrays of 256-element rows, the memory traffic of one AA step
// without the collision (docs/lbm.md, "Experiments of 2026-11-24"): range(0) arrays over 1 GiB in
// all, staggered in their 4 KiB offsets as the fluid grid's are; range(1) = 1 visits the arrays in
// one loop over the row, as the fluid kernel does; 0 sweeps one array's row segment after the
// other. Both threads of the machine, as `settle bench`.
void update_row(double* __restrict a, std::size_t n) {
#pragma omp simd
  for (std::size_t x = 0; x < n; ++x) a[x] = 0.5 * a[x] + 0.5;
}

void BM_InplaceStreams(benchmark::State& state) {
  const auto arrays = static_cast<std::size_t>(state.range(0));
  const bool interleaved = state.range(1) != 0;
  constexpr std::size_t kRow = 256, kHuge = std::size_t{2} << 20, kTotal = std::size_t{1} << 27;
  const std::size_t rows = kTotal / arrays / kRow;
  const std::size_t stride = (rows * kRow + 511) / 512 * 512 + 4096 / arrays / 64 * 64 / sizeof(double);
  const std::size_t bytes = (stride * arrays * sizeof(double) + kHuge - 1) / kHuge * kHuge;
  std::unique_ptr<double, decltype(&std::free)> storage(static_cast<double*>(std::aligned_alloc(kHuge, bytes)),
                                                        &std::free);
  double* const base = storage.get();
  ::madvise(base, bytes, MADV_HUGEPAGE);
#pragma omp parallel for schedule(static)
  for (std::size_t r = 0; r < rows; ++r) {  // first touch by the thread that updates the row
    for (std::size_t q = 0; q < arrays; ++q) std::fill_n(base + q * stride + r * kRow, kRow, 1.0);
  }
  for (auto _ : state) {
#pragma omp parallel for schedule(static)
    for (std::size_t r = 0; r < rows; ++r) {
      double* p[64];
      for (std::size_t q = 0; q < arrays; ++q) p[q] = base + q * stride + r * kRow;
      if (!interleaved) {
        for (std::size_t q = 0; q < arrays; ++q) update_row(p[q], kRow);
        continue;
      }
#pragma GCC ivdep
      for (std::size_t x = 0; x < kRow; ++x) {
        for (std::size_t q = 0; q < arrays; ++q) p[q][x] = 0.5 * p[q][x] + 0.5;
      }
    }
    benchmark::ClobberMemory();
  }
  state.counters["bytes_per_s"] =
      benchmark::Counter(2.0 * static_cast<double>(rows * kRow * arrays * sizeof(double)),
                         benchmark::Counter::kIsIterationInvariantRate, benchmark::Counter::kIs1000);
}
BENCHMARK(BM_InplaceStreams)
    ->ArgsProduct({{1, 4, 10, 11, 19, 22}, {0, 1}})
    ->Unit(benchmark::kMillisecond)
    ->UseRealTime();

// The memory side of a candidate layout for the AA kernel (docs/lbm.md): AoSoA, each row
// of x stored as blocks of 8 cells x 19 populations (1216 bytes, whole cache lines), rows after
// one another. Each block's 19 population vectors are read and written back in place, either
// all in the cell's own row (the even AA step: one sequential stream per thread) or, for the odd
// step, in the row of the D3Q19 neighbour (y + c_y, z + c_z): 9 rows touched per row. No
// arithmetic beyond x = 0.5 x + 0.5, so this bounds what the layout could give the kernel;
// compare with BM_InplaceStreams (19 separate arrays) in the same run. Arguments: 0 even, 1 odd;
// then 0 for blocks of all 19 populations, 1 for each row split into 9 segments by (c_y, c_z), a
// segment holding blocks of 8 cells x its 1 or 3 populations, so that the odd step touches one
// contiguous segment per neighbour row instead of 3 lines in every 19.
void BM_AosoaStreams(benchmark::State& state) {
  const bool odd = state.range(0) != 0;
  const bool grouped = state.range(1) != 0;
  constexpr int kQ = 19, kLanes = 8, kNx = 256;
  constexpr std::size_t kHuge = std::size_t{2} << 20, kTotal = std::size_t{1} << 27;  // doubles, 1 GiB
  constexpr std::size_t kRow = std::size_t{kNx} * kQ;                                 // doubles per row
  constexpr int kNy = 64;
  const int nz = static_cast<int>(kTotal / kRow / kNy);
  const std::size_t bytes = (kRow * kNy * nz * sizeof(double) + kHuge - 1) / kHuge * kHuge;
  std::unique_ptr<double, decltype(&std::free)> storage(static_cast<double*>(std::aligned_alloc(kHuge, bytes)),
                                                        &std::free);
  double* const base = storage.get();
  ::madvise(base, bytes, MADV_HUGEPAGE);
  constexpr int cy[kQ] = {0, 1, -1, 0, 0, 0, 0, 1, -1, 1, -1, 0, 0, 0, 0, 1, -1, 1, -1};
  constexpr int cz[kQ] = {0, 0, 0, 1, -1, 0, 0, 0, 0, 0, 0, 1, -1, 1, -1, 1, 1, -1, -1};
  // Population q's vector of block b sits at first[q] + b * stride[q] doubles in its row: plain
  // blocks of 19, or by segment (the populations sharing (c_y, c_z), laid out in the order of
  // their first member, each segment holding blocks of its own width).
  std::size_t first[kQ], stride[kQ];
  std::size_t next_segment = 0;
  for (int q = 0; q < kQ; ++q) {
    if (!grouped) {
      first[q] = static_cast<std::size_t>(q) * kLanes;
      stride[q] = std::size_t{kQ} * kLanes;
      continue;
    }
    int leader = -1, width = 0, rank = 0;
    for (int k = 0; k < kQ; ++k) {
      if (cy[k] != cy[q] || cz[k] != cz[q]) continue;
      if (leader < 0) leader = k;
      if (k < q) ++rank;
      ++width;
    }
    stride[q] = static_cast<std::size_t>(width) * kLanes;
    // The leader (rank 0) opens the segment; the others sit after it at their rank.
    if (leader == q) {
      first[q] = next_segment;
      next_segment += stride[q] * (kNx / kLanes);
    } else {
      first[q] = first[leader] + static_cast<std::size_t>(rank) * kLanes;
    }
  }
  const auto row_of = [&](int y, int z) {  // periodic wrap: the kernel's halo plays that part
    return base + ((static_cast<std::size_t>((z + nz) % nz) * kNy + static_cast<std::size_t>((y + kNy) % kNy)) * kRow);
  };
#pragma omp parallel for collapse(2) schedule(static)
  for (int z = 0; z < nz; ++z)
    for (int y = 0; y < kNy; ++y) std::fill_n(row_of(y, z), kRow, 1.0);
  for (auto _ : state) {
#pragma omp parallel for collapse(2) schedule(static)
    for (int z = 0; z < nz; ++z) {
      for (int y = 0; y < kNy; ++y) {
        double* rows[kQ];
        for (int q = 0; q < kQ; ++q) rows[q] = odd ? row_of(y + cy[q], z + cz[q]) : row_of(y, z);
        for (int b = 0; b < kNx / kLanes; ++b) {
          for (int q = 0; q < kQ; ++q) {
            double* __restrict v = rows[q] + first[q] + static_cast<std::size_t>(b) * stride[q];
#pragma GCC unroll 8
            for (int l = 0; l < kLanes; ++l) v[l] = 0.5 * v[l] + 0.5;
          }
        }
      }
    }
    benchmark::ClobberMemory();
  }
  state.counters["bytes_per_s"] =
      benchmark::Counter(2.0 * static_cast<double>(kRow * kNy * nz * sizeof(double)),
                         benchmark::Counter::kIsIterationInvariantRate, benchmark::Counter::kIs1000);
}
BENCHMARK(BM_AosoaStreams)->ArgsProduct({{0, 1}, {0, 1}})->Unit(benchmark::kMillisecond)->UseRealTime();

}  // namespace
