#pragma once
// The streaming timeseries.csv of the run directory, whose columns are a contract
// (docs/architecture.md, "Contracts"). Whole files (summary.json, case.resolved.toml) are written
// with common/atomic_file.hpp.
#include <cstdint>
#include <filesystem>
#include <fstream>
#include <string>
#include <string_view>
#include <vector>

#include "coupling/runner.hpp"

namespace settle::io {

/// The columns of timeseries.csv: the contract (t .. Re; docs/architecture.md, "Contracts"), then extras (slip_max,
/// slip_rms: the largest and rms no-slip error at the markers after forcing, m/s; Fcx, Fcy, Fcz:
/// the particle-wall contact force of the last step, N; wall_gap: the smallest body-wall gap of
/// the last step, m, kNoWallGap without contact walls). New columns are only ever appended.
const std::vector<std::string>& timeseries_columns();

/// How many of timeseries_columns() are the contract (t .. Re).
inline constexpr std::size_t kContractColumnCount = 27;

/// wall_gap of timeseries.csv when the run has no contact walls (a following window, periodic
/// axes, contact off, towed or fixed bodies) and at t = 0: the file holds finite numbers only.
inline constexpr double kNoWallGap = -1.0;

/// One row per sample, SI, full double precision; flushed after every row so that a running
/// case can be watched.
class TimeseriesWriter {
 public:
  /// A new file holding the header line (an existing one is replaced).
  explicit TimeseriesWriter(const std::filesystem::path& path);
  /// Continues the file of a restarted run: cuts it to its first `keep_bytes` bytes (the length
  /// when the checkpoint was written; the rows after it are written again) and appends. Throws
  /// settle::InputError naming the file when it is missing or shorter than that.
  static TimeseriesWriter continue_at(const std::filesystem::path& path, std::uintmax_t keep_bytes);
  void write(const coupling::Sample& sample);

 private:
  TimeseriesWriter(const std::filesystem::path& path, std::ios::openmode mode);

  std::ofstream out_;
  std::filesystem::path path_;
};

}  // namespace settle::io
