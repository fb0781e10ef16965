#pragma once
// Small writers for the run directory: whole files written atomically (temporary file plus
// rename, so a reader never sees half a file), and the streaming timeseries.csv whose columns
// are the contract of DESIGN.md section 3.
#include <filesystem>
#include <fstream>
#include <string>
#include <string_view>
#include <vector>

#include "coupling/runner.hpp"

namespace settle::io {

/// Writes `text` to `path` through `path` + ".tmp" and a rename (atomic on POSIX file systems).
/// Throws settle::InputError naming the path when it cannot be written.
void write_file_atomically(const std::filesystem::path& path, std::string_view text);

/// The columns of timeseries.csv: the DESIGN.md contract (t .. Re), then extras (slip_max,
/// slip_rms: the largest and rms no-slip error at the markers after forcing, m/s).
const std::vector<std::string>& timeseries_columns();

/// One row per sample, SI, full double precision; flushed after every row so that a running
/// case can be watched.
class TimeseriesWriter {
 public:
  explicit TimeseriesWriter(const std::filesystem::path& path);
  void write(const coupling::Sample& sample);

 private:
  std::ofstream out_;
  std::filesystem::path path_;
};

}  // namespace settle::io
