#pragma once
// Memory-bandwidth probe for the fluid benchmark's roofline.
//
// The lattice Boltzmann kernel streams in place (AA pattern): every population is read and written
// back where it lives, so each byte of the lattice crosses the memory bus twice and no
// write-allocate traffic occurs. A STREAM triad (a = b + s c) would count 3 streams but move 4
// (the write-allocate read of a), and so misstates the bound. This probe does exactly what the
// kernel does to memory: x[i] = s * x[i] + t over an array far larger than the last-level cache,
// in parallel over the same OpenMP threads, first-touched by the thread that later updates it.
#include <cstddef>

namespace settle {

struct BandwidthProbeResult {
  double bandwidth_gbs;  ///< best of the repetitions, 1e9 bytes/s, counting read + write
  double array_bytes;    ///< size of the probed array
  int repetitions;
  int threads;
};

/// Runs the in-place read-modify-write probe over `array_bytes` bytes of doubles.
/// `repetitions` sweeps are timed individually and the best is reported (as STREAM does), after
/// one untimed sweep that faults the pages in.
BandwidthProbeResult measure_inplace_bandwidth(std::size_t array_bytes, int repetitions);

}  // namespace settle
