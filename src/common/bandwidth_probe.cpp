#include "common/bandwidth_probe.hpp"

#include <omp.h>

#include <algorithm>
#include <cstdlib>
#include <limits>
#include <memory>
#include <new>

namespace settle {
namespace {

struct FreeDeleter {
  void operator()(double* p) const { std::free(p); }
};

// Each thread updates the same contiguous block in every sweep (static schedule), so pages
// stay local to the thread that touched them first.
void sweep(double* x, std::ptrdiff_t n, double scale, double shift) {
#pragma omp parallel for schedule(static)
  for (std::ptrdiff_t i = 0; i < n; ++i) x[i] = scale * x[i] + shift;
}

}  // namespace

BandwidthProbeResult measure_inplace_bandwidth(std::size_t array_bytes, int repetitions) {
  const auto n = static_cast<std::ptrdiff_t>(array_bytes / sizeof(double));
  const std::size_t bytes = static_cast<std::size_t>(n) * sizeof(double);
  std::unique_ptr<double, FreeDeleter> storage(
      static_cast<double*>(std::aligned_alloc(4096, (bytes + 4095) / 4096 * 4096)));
  if (!storage) throw std::bad_alloc();
  double* x = storage.get();

#pragma omp parallel for schedule(static)
  for (std::ptrdiff_t i = 0; i < n; ++i) x[i] = 1.0;
  // Scale and shift keep the values bounded (fixed point at 1) so no denormals or overflow
  // slow a sweep down.
  const double scale = 0.5, shift = 0.5;
  sweep(x, n, scale, shift);

  double best_seconds = std::numeric_limits<double>::infinity();
  for (int r = 0; r < repetitions; ++r) {
    const double start = omp_get_wtime();
    sweep(x, n, scale, shift);
    best_seconds = std::min(best_seconds, omp_get_wtime() - start);
  }
  // Keep the compiler from discarding the sweeps: the result is observably used.
  volatile double sink = x[n / 2];
  (void)sink;

  BandwidthProbeResult result{};
  result.bandwidth_gbs = 2.0 * static_cast<double>(bytes) / best_seconds * 1e-9;
  result.array_bytes = static_cast<double>(bytes);
  result.repetitions = repetitions;
  result.threads = omp_get_max_threads();
  return result;
}

}  // namespace settle
