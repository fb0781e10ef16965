#include "analysis/timeseries.hpp"

#include <algorithm>
#include <charconv>
#include <cmath>
#include <fstream>
#include <sstream>
#include <stdexcept>

#include <fmt/core.h>

#include "attitude/attitude.hpp"
#include "common/error.hpp"
#include "coupling/runner.hpp"

namespace settle::analysis {
namespace {

std::string_view trim(std::string_view text) {
  const auto blank = [](char c) { return c == ' ' || c == '\t' || c == '\r'; };
  while (!text.empty() && blank(text.front())) text.remove_prefix(1);
  while (!text.empty() && blank(text.back())) text.remove_suffix(1);
  return text;
}

std::vector<std::string_view> split_fields(std::string_view line) {
  std::vector<std::string_view> fields;
  std::size_t begin = 0;
  while (true) {
    const std::size_t comma = line.find(',', begin);
    const std::size_t length = comma == std::string_view::npos ? std::string_view::npos : comma - begin;
    fields.push_back(trim(line.substr(begin, length)));
    if (comma == std::string_view::npos) return fields;
    begin = comma + 1;
  }
}

// The lines of the text with their 1-based line numbers, blank lines dropped.
std::vector<std::pair<std::size_t, std::string_view>> non_blank_lines(std::string_view text) {
  std::vector<std::pair<std::size_t, std::string_view>> lines;
  std::size_t number = 0, begin = 0;
  while (begin < text.size()) {
    const std::size_t end = std::min(text.find('\n', begin), text.size());
    ++number;
    const std::string_view line = text.substr(begin, end - begin);
    if (!trim(line).empty()) lines.emplace_back(number, line);
    begin = end + 1;
  }
  return lines;
}

double parse_value(std::string_view field, const std::string& where) {
  double value = 0.0;
  const char* first = field.data();
  const char* last = field.data() + field.size();
  if (!field.empty() && *first == '+') ++first;  // from_chars refuses a leading '+'
  const auto [stop, ec] = std::from_chars(first, last, value);
  if (field.empty() || ec != std::errc() || stop != last)
    throw InputError(fmt::format("{}: not a number: '{}'", where, field));
  return value;
}

Eigen::Vector3d vector_at(const Timeseries& table, const char* x, const char* y, const char* z, std::size_t row) {
  return {table.column(x)[row], table.column(y)[row], table.column(z)[row]};
}

}  // namespace

void Timeseries::add_column(const std::string& name, std::vector<double> values) {
  if (has(name)) throw std::invalid_argument("Timeseries::add_column: repeated column " + name);
  if (!columns_.empty() && values.size() != rows())
    throw std::invalid_argument("Timeseries::add_column: column " + name + " has a different length");
  names_.push_back(name);
  columns_.push_back(std::move(values));
}

bool Timeseries::has(std::string_view name) const {
  return std::find(names_.begin(), names_.end(), name) != names_.end();
}

const std::vector<double>& Timeseries::column(std::string_view name) const {
  const auto it = std::find(names_.begin(), names_.end(), name);
  if (it == names_.end()) throw InputError(fmt::format("{}: missing column '{}'", source_, name));
  return columns_[static_cast<std::size_t>(it - names_.begin())];
}

Timeseries parse_timeseries_csv(std::string_view text, const std::string& source) {
  const auto lines = non_blank_lines(text);
  if (lines.empty()) throw InputError(fmt::format("{}: empty file (expected a header line of column names)", source));
  const auto [header_line, header] = lines.front();
  const std::vector<std::string_view> names = split_fields(header);
  for (std::size_t c = 0; c < names.size(); ++c) {
    if (names[c].empty())
      throw InputError(fmt::format("{}:{}: header column {} has no name", source, header_line, c + 1));
    if (std::find(names.begin(), names.begin() + static_cast<std::ptrdiff_t>(c), names[c]) !=
        names.begin() + static_cast<std::ptrdiff_t>(c))
      throw InputError(fmt::format("{}:{}: column '{}' appears twice in the header", source, header_line, names[c]));
  }

  std::vector<std::vector<double>> columns(names.size());
  for (std::size_t i = 1; i < lines.size(); ++i) {
    const auto [number, line] = lines[i];
    const std::vector<std::string_view> fields = split_fields(line);
    if (fields.size() != names.size())
      throw InputError(fmt::format("{}:{}: expected {} values (one per header column), got {}", source, number,
                                   names.size(), fields.size()));
    for (std::size_t c = 0; c < fields.size(); ++c)
      columns[c].push_back(parse_value(fields[c], fmt::format("{}:{}: column '{}'", source, number, names[c])));
  }

  Timeseries table(source);
  for (std::size_t c = 0; c < names.size(); ++c) table.add_column(std::string(names[c]), std::move(columns[c]));
  return table;
}

Timeseries read_timeseries_csv(const std::filesystem::path& path) {
  std::ifstream in(path, std::ios::binary);
  if (!in) throw InputError(fmt::format("{}: cannot open the file", path.string()));
  std::stringstream text;
  text << in.rdbuf();
  if (in.bad()) throw InputError(fmt::format("{}: read failed", path.string()));
  return parse_timeseries_csv(text.str(), path.string());
}

void SettlingSeries::add(double t, const Eigen::Vector3d& position, const Eigen::Vector3d& velocity,
                         const Eigen::Vector3d& angular_velocity_n, const Eigen::Vector3d& angular_velocity_b,
                         const Eigen::Matrix3d& body_to_inertial_matrix, const Eigen::Vector3d& force,
                         const Eigen::Vector3d& torque) {
  t_si.push_back(t);
  position_si.push_back(position);
  velocity_si.push_back(velocity);
  angular_velocity_n_si.push_back(angular_velocity_n);
  angular_velocity_b_si.push_back(angular_velocity_b);
  body_to_inertial.push_back(body_to_inertial_matrix);
  force_si.push_back(force);
  torque_si.push_back(torque);
}

SettlingSeries SettlingSeries::since(double t0_si) const {
  SettlingSeries out;
  for (std::size_t k = 0; k < size(); ++k)
    if (t_si[k] >= released_from(t0_si)) {
      out.add(t_si[k], position_si[k], velocity_si[k], angular_velocity_n_si[k], angular_velocity_b_si[k],
              body_to_inertial[k], force_si[k], torque_si[k]);
      if (!contact_force_si.empty()) out.contact_force_si.push_back(contact_force_si[k]);
    }
  return out;
}

const std::vector<std::string>& settling_series_columns() {
  static const std::vector<std::string> columns{"t",  "x",  "y",   "z",   "ux",  "uy",  "uz",    "wx",
                                                "wy", "wz", "wbx", "wby", "wbz", "psi", "theta", "gamma",
                                                "Fx", "Fy", "Fz",  "Tx",  "Ty",  "Tz"};
  return columns;
}

SettlingSeries settling_series(const Timeseries& table) {
  // Every column is looked up first, so that a missing one is reported before any value.
  for (const std::string& name : settling_series_columns()) (void)table.column(name);
  const std::size_t rows = table.rows();
  if (rows < 2) throw InputError(fmt::format("{}: {} data rows; the analysis needs at least 2", table.source(), rows));
  // Line numbers in messages count the header as line 1 (blank lines aside).
  for (const std::string& name : settling_series_columns()) {
    const std::vector<double>& values = table.column(name);
    for (std::size_t r = 0; r < rows; ++r)
      if (!std::isfinite(values[r]))
        throw InputError(
            fmt::format("{}: row {}: column '{}' is not finite ({})", table.source(), r + 1, name, values[r]));
  }
  const std::vector<double>& t = table.column("t");
  for (std::size_t r = 1; r < rows; ++r)
    if (!(t[r] > t[r - 1]))
      throw InputError(
          fmt::format("{}: row {}: column 't' must increase, got {} after {}", table.source(), r + 1, t[r], t[r - 1]));

  SettlingSeries series;
  for (std::size_t r = 0; r < rows; ++r) {
    const Eigen::Vector3d angles = vector_at(table, "psi", "theta", "gamma", r);
    series.add(t[r], vector_at(table, "x", "y", "z", r), vector_at(table, "ux", "uy", "uz", r),
               vector_at(table, "wx", "wy", "wz", r), vector_at(table, "wbx", "wby", "wbz", r),
               attitude::Attitude::from_set1(angles[0], angles[1], angles[2]).body_to_inertial(),
               vector_at(table, "Fx", "Fy", "Fz", r), vector_at(table, "Tx", "Ty", "Tz", r));
  }
  if (table.has("Fcx") && table.has("Fcy") && table.has("Fcz"))
    for (std::size_t r = 0; r < rows; ++r) series.contact_force_si.push_back(vector_at(table, "Fcx", "Fcy", "Fcz", r));
  return series;
}

SettlingSeries settling_series(const std::vector<coupling::Sample>& samples) {
  SettlingSeries series;
  for (const coupling::Sample& s : samples) {
    if (!series.t_si.empty() && !(s.t_si > series.t_si.back()))
      throw std::invalid_argument("settling_series: sample times must increase");
    series.add(s.t_si, s.position_si, s.velocity_si, s.angular_velocity_n_si, s.angular_velocity_b_si,
               s.attitude.body_to_inertial(), s.hydrodynamic.force_si, s.hydrodynamic.torque_si);
    series.contact_force_si.push_back(s.contact.force_si);
  }
  return series;
}

}  // namespace settle::analysis
