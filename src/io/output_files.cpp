#include "io/output_files.hpp"

#include <cmath>

#include <fmt/core.h>

#include "attitude/euler.hpp"
#include "common/atomic_file.hpp"
#include "common/error.hpp"

namespace settle::io {

const std::vector<TimeseriesColumn>& timeseries_column_table() {
  static const std::vector<TimeseriesColumn> table{
      {"t", "s", "", "simulated time"},
      {"x", "m", "inertial", "centre of mass, x"},
      {"y", "m", "inertial", "centre of mass, y"},
      {"z", "m", "inertial", "centre of mass, z"},
      {"ux", "m/s", "inertial", "velocity of the centre of mass, x"},
      {"uy", "m/s", "inertial", "velocity of the centre of mass, y"},
      {"uz", "m/s", "inertial", "velocity of the centre of mass, z"},
      {"wx", "rad/s", "inertial", "angular velocity, x"},
      {"wy", "rad/s", "inertial", "angular velocity, y"},
      {"wz", "rad/s", "inertial", "angular velocity, z"},
      {"wbx", "rad/s", "body", "angular velocity, body x"},
      {"wby", "rad/s", "body", "angular velocity, body y"},
      {"wbz", "rad/s", "body", "angular velocity, body z"},
      {"psi", "rad", "body to inertial", "set-1 Euler angle psi (z-y-x: C_b^n = Rz(psi) Ry(theta) Rx(gamma))"},
      {"theta", "rad", "body to inertial", "set-1 Euler angle theta"},
      {"gamma", "rad", "body to inertial", "set-1 Euler angle gamma"},
      {"psi_r", "rad", "body to inertial",
       "set-2 Euler angle psi_r (z-x-y: C_b^n = Rz(psi_r) Rx(gamma_r) Ry(theta_r))"},
      {"theta_r", "rad", "body to inertial", "set-2 Euler angle theta_r"},
      {"gamma_r", "rad", "body to inertial", "set-2 Euler angle gamma_r"},
      {"euler_set", "1", "", "the Euler set the dual-Euler solver advances (1 or 2)"},
      {"Fx", "N", "inertial", "hydrodynamic force, x, mean since the previous row"},
      {"Fy", "N", "inertial", "hydrodynamic force, y, mean since the previous row"},
      {"Fz", "N", "inertial", "hydrodynamic force, z, mean since the previous row"},
      {"Tx", "N m", "inertial", "hydrodynamic torque about the centre of mass, x, mean since the previous row"},
      {"Ty", "N m", "inertial", "hydrodynamic torque about the centre of mass, y, mean since the previous row"},
      {"Tz", "N m", "inertial", "hydrodynamic torque about the centre of mass, z, mean since the previous row"},
      {"Re", "1", "", "Reynolds number: relative flow speed x d_eq / nu"},
      {"slip_max", "m/s", "", "largest no-slip error at the surface markers after the forcing"},
      {"slip_rms", "m/s", "", "rms no-slip error at the surface markers after the forcing"},
      {"Fcx", "N", "inertial", "particle-wall contact force, x, mean since the previous row"},
      {"Fcy", "N", "inertial", "particle-wall contact force, y, mean since the previous row"},
      {"Fcz", "N", "inertial", "particle-wall contact force, z, mean since the previous row"},
      {"wall_gap", "m", "", "smallest body-wall gap of the last step; -1 without contact walls and at t = 0"},
      {"q_w", "1", "body to inertial", "unit quaternion of the attitude (q v_b q* = v_n), scalar part, >= 0"},
      {"q_x", "1", "body to inertial", "unit quaternion of the attitude, x"},
      {"q_y", "1", "body to inertial", "unit quaternion of the attitude, y"},
      {"q_z", "1", "body to inertial", "unit quaternion of the attitude, z"}};
  return table;
}

const std::vector<std::string>& timeseries_columns() {
  static const std::vector<std::string> names = [] {
    std::vector<std::string> result;
    for (const TimeseriesColumn& column : timeseries_column_table()) result.emplace_back(column.name);
    return result;
  }();
  return names;
}

namespace {

// A JSON string literal of `text` (the table's texts are plain ASCII; quotes and backslashes
// escaped all the same, so that an edit of the table cannot break the file).
std::string json_string(std::string_view text) {
  std::string quoted = "\"";
  for (const char c : text) {
    if (c == '"' || c == '\\') quoted += '\\';
    quoted += c;
  }
  return quoted + '"';
}

std::string header_line() {
  std::string header;
  for (const std::string& name : timeseries_columns()) header += (header.empty() ? "" : ",") + name;
  return header;
}

void write_sidecar(const std::filesystem::path& csv_path) {
  write_file_atomically(timeseries_sidecar_path(csv_path), timeseries_sidecar_json());
}

}  // namespace

std::string timeseries_sidecar_json() {
  std::string json = "{\n  \"file\": \"timeseries.csv\",\n  \"columns\": [\n";
  const auto& table = timeseries_column_table();
  for (std::size_t i = 0; i < table.size(); ++i) {
    const TimeseriesColumn& c = table[i];
    json +=
        fmt::format("    {{\"name\": {}, \"unit\": {}, \"frame\": {}, \"meaning\": {}}}{}\n", json_string(c.name),
                    json_string(c.unit), json_string(c.frame), json_string(c.meaning), i + 1 < table.size() ? "," : "");
  }
  return json + "  ]\n}\n";
}

std::filesystem::path timeseries_sidecar_path(const std::filesystem::path& csv_path) {
  return std::filesystem::path(csv_path).replace_extension(".json");
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
  std::ifstream existing(path);
  std::string header;
  std::getline(existing, header);
  if (header != header_line())
    throw InputError(
        fmt::format("{}: its columns are not those this settle writes (a run of another settle "
                    "version); cannot continue it: start it afresh",
                    path.string()));
  existing.close();
  std::filesystem::resize_file(path, keep_bytes, error);
  if (error)
    throw InputError(fmt::format("{}: cannot cut it to {} bytes: {}", path.string(), keep_bytes, error.message()));
  write_sidecar(path);
  return TimeseriesWriter(path, std::ios::out | std::ios::app);
}

TimeseriesWriter::TimeseriesWriter(const std::filesystem::path& path)
    : TimeseriesWriter(path, std::ios::out | std::ios::trunc) {
  out_ << header_line() << '\n';
  write_sidecar(path);
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
  row += fmt::format(",{:.17g}", std::isfinite(s.wall_gap_si) ? s.wall_gap_si : kNoWallGap);
  const Eigen::Quaterniond q = s.attitude.quaternion();
  row += fmt::format(",{:.17g},{:.17g},{:.17g},{:.17g}\n", q.w(), q.x(), q.y(), q.z());
  out_ << row;
  out_.flush();
  if (!out_) throw InputError(fmt::format("{}: write failed", path_.string()));
}

}  // namespace settle::io
