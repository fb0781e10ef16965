#include "io/output_files.hpp"

#include <cmath>

#include <fmt/core.h>

#include "attitude/euler.hpp"
#include "common/error.hpp"

namespace settle::io {

const std::vector<std::string>& timeseries_columns() {
  static const std::vector<std::string> columns{
      "t",   "x",   "y",   "z",     "ux",    "uy",       "uz",       "wx",      "wy",        "wz",  "wbx",
      "wby", "wbz", "psi", "theta", "gamma", "psi_r",    "theta_r",  "gamma_r", "euler_set", "Fx",  "Fy",
      "Fz",  "Tx",  "Ty",  "Tz",    "Re",    "slip_max", "slip_rms", "Fcx",     "Fcy",       "Fcz", "wall_gap"};
  return columns;
}

TimeseriesWriter::TimeseriesWriter(const std::filesystem::path& path, std::ios::openmode mode)
    : out_(path, mode), path_(path) {
  if (!out_) throw InputError(fmt::format("{}: cannot write", path.string()));
}

TimeseriesWriter TimeseriesWriter::continue_at(const std::filesystem::path& path, std::uintmax_t keep_bytes) {
  std::error_code error;
  const std::uintmax_t size = std::filesystem::file_size(path, error);
  if (error) throw InputError(fmt::format("{}: cannot continue it: {}", path.string(), error.message()));
  if (size < keep_bytes)
    throw InputError(
        fmt::format("{}: holds {} bytes, fewer than the {} it held at the checkpoint: the rows before the "
                    "checkpoint are missing; cannot continue this run",
                    path.string(), size, keep_bytes));
  std::filesystem::resize_file(path, keep_bytes, error);
  if (error)
    throw InputError(fmt::format("{}: cannot cut it to {} bytes: {}", path.string(), keep_bytes, error.message()));
  return TimeseriesWriter(path, std::ios::out | std::ios::app);
}

TimeseriesWriter::TimeseriesWriter(const std::filesystem::path& path)
    : TimeseriesWriter(path, std::ios::out | std::ios::trunc) {
  const auto& columns = timeseries_columns();
  for (std::size_t i = 0; i < columns.size(); ++i) out_ << (i ? "," : "") << columns[i];
  out_ << '\n';
}

void TimeseriesWriter::write(const coupling::Sample& s) {
  const Eigen::Vector3d set1 = s.attitude.set1_angles();
  const Eigen::Vector3d set2 = s.attitude.set2_angles();
  const int euler_set = s.attitude.set() == attitude::EulerSet::set1 ? 1 : 2;
  std::string row = fmt::format("{:.17g}", s.t_si);
  const auto add = [&](const Eigen::Vector3d& v) {
    for (int a = 0; a < 3; ++a) row += fmt::format(",{:.17g}", v[a]);
  };
  add(s.position_si);
  add(s.velocity_si);
  add(s.angular_velocity_n_si);
  add(s.angular_velocity_b_si);
  add(set1);
  // set2_angles() returns (psi_r, theta_r, gamma_r), the column order
  add(set2);
  row += fmt::format(",{}", euler_set);
  add(s.hydrodynamic.force_si);
  add(s.hydrodynamic.torque_si);
  row += fmt::format(",{:.17g},{:.17g},{:.17g}", s.reynolds, s.slip_max_si, s.slip_rms_si);
  add(s.contact.force_si);
  // Every value of the file is finite (readers and tests rely on it): without contact walls the
  // gap is infinite, written as the sentinel -1 (a real gap is never below minus a cell or so).
  row += fmt::format(",{:.17g}\n", std::isfinite(s.wall_gap_si) ? s.wall_gap_si : kNoWallGap);
  out_ << row;
  out_.flush();
  if (!out_) throw InputError(fmt::format("{}: write failed", path_.string()));
}

}  // namespace settle::io
