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

/// One column of timeseries.csv as its sidecar timeseries.json describes it: `unit` SI ("1" for a
/// pure number), `frame` "inertial", "body", "body to inertial" (an attitude) or "" (a scalar).
struct TimeseriesColumn {
  std::string_view name;
  std::string_view unit;
  std::string_view frame;
  std::string_view meaning;
};

/// The columns of timeseries.csv in their order: the one table from which the header line and
/// timeseries.json are written. The contract (t .. Re; docs/architecture.md, "Contracts"), then
/// extras (slip_max .. wall_gap, then the attitude quaternion q_w .. q_z). New columns are only
/// ever appended.
const std::vector<TimeseriesColumn>& timeseries_column_table();

/// The names of timeseries_column_table(), in order.
const std::vector<std::string>& timeseries_columns();

/// The text of timeseries.json: {"file": "timeseries.csv", "columns": [{"name", "unit", "frame",
/// "meaning"}, ...]} in the order of the CSV's columns.
std::string timeseries_sidecar_json();

/// Where the sidecar of `csv_path` goes: the same name with .json (timeseries.json).
std::filesystem::path timeseries_sidecar_path(const std::filesystem::path& csv_path);

/// How many of timeseries_columns() are the contract (t .. Re).
inline constexpr std::size_t kContractColumnCount = 27;

/// wall_gap of timeseries.csv when the run has no contact walls (a following window, periodic
/// axes, contact off, towed or fixed bodies) and at t = 0: the file holds finite numbers only.
inline constexpr double kNoWallGap = -1.0;

/// One row per sample, SI, full double precision; flushed after every row so that a running
/// case can be watched. Both constructors (re)write the sidecar timeseries.json beside the file.
class TimeseriesWriter {
 public:
  /// A new file holding the header line (an existing one is replaced).
  explicit TimeseriesWriter(const std::filesystem::path& path);
  /// Continues the file of a restarted run: cuts it to its first `keep_bytes` bytes (the length
  /// when the checkpoint was written; the rows after it are written again) and appends. Throws
  /// settle::InputError naming the file when it is missing or shorter than that, or when its
  /// header is not this build's (a run of a settle with other columns: its rows would not match).
  static TimeseriesWriter continue_at(const std::filesystem::path& path, std::uintmax_t keep_bytes);
  void write(const coupling::Sample& sample);

 private:
  TimeseriesWriter(const std::filesystem::path& path, std::ios::openmode mode);

  std::ofstream out_;
  std::filesystem::path path_;
};

}  // namespace settle::io
