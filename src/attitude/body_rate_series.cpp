#include "attitude/body_rate_series.hpp"

#include <algorithm>
#include <charconv>
#include <cmath>
#include <fstream>
#include <stdexcept>
#include <string_view>

#include <fmt/core.h>

#include "common/error.hpp"

namespace settle::attitude {
namespace {

std::string_view trim(std::string_view text) {
  const auto first = text.find_first_not_of(" \t\r");
  if (first == std::string_view::npos) return {};
  const auto last = text.find_last_not_of(" \t\r");
  return text.substr(first, last - first + 1);
}

std::vector<std::string_view> split_fields(std::string_view line) {
  std::vector<std::string_view> fields;
  std::size_t start = 0;
  while (true) {
    const auto comma = line.find(',', start);
    fields.push_back(trim(line.substr(start, comma - start)));
    if (comma == std::string_view::npos) break;
    start = comma + 1;
  }
  return fields;
}

/// The whole field as a finite double, or throws InputError.
double parse_number(std::string_view field, const std::string& where) {
  double value = 0.0;
  const auto* end = field.data() + field.size();
  const auto [ptr, error] = std::from_chars(field.data(), end, value);
  if (field.empty() || error != std::errc() || ptr != end || !std::isfinite(value)) {
    throw InputError(fmt::format("{}: '{}' is not a finite number", where, field));
  }
  return value;
}

void check_header(std::string_view line, const std::string& path) {
  const auto fields = split_fields(line);
  const bool matches =
      fields.size() == 4 && fields[0] == "t" && fields[1] == "wx" && fields[2] == "wy" && fields[3] == "wz";
  if (!matches) {
    throw InputError(fmt::format("{}: line 1: header must be t,wx,wy,wz, got '{}'", path, trim(line)));
  }
}

}  // namespace

BodyRateSeries::BodyRateSeries(std::vector<double> times_si, std::vector<Eigen::Vector3d> omega_b)
    : times_(std::move(times_si)), omega_b_(std::move(omega_b)) {
  if (times_.size() < 2 || times_.size() != omega_b_.size()) {
    throw std::invalid_argument("body-rate series needs at least two samples and one rate per time");
  }
  for (std::size_t i = 0; i < times_.size(); ++i) {
    if (!std::isfinite(times_[i]) || !omega_b_[i].allFinite()) {
      throw std::invalid_argument("body-rate series values must be finite");
    }
    if (i > 0 && !(times_[i] > times_[i - 1])) {
      throw std::invalid_argument("body-rate series times must increase strictly");
    }
  }
}

BodyRateSeries BodyRateSeries::read_csv(const std::string& path) {
  std::ifstream file(path);
  if (!file) throw InputError(fmt::format("cannot open '{}'", path));
  std::string line;
  if (!std::getline(file, line)) throw InputError(fmt::format("{}: file is empty", path));
  check_header(line, path);

  std::vector<double> times;
  std::vector<Eigen::Vector3d> rates;
  for (int line_number = 2; std::getline(file, line); ++line_number) {
    if (trim(line).empty()) continue;
    const std::string where = fmt::format("{}: line {}", path, line_number);
    const auto fields = split_fields(line);
    if (fields.size() != 4) {
      throw InputError(
          fmt::format("{}: expected 4 comma-separated numbers t,wx,wy,wz, got {} fields", where, fields.size()));
    }
    const double t = parse_number(fields[0], where);
    if (!times.empty() && !(t > times.back())) {
      throw InputError(fmt::format("{}: times must increase strictly, got {} after {}", where, t, times.back()));
    }
    times.push_back(t);
    rates.emplace_back(parse_number(fields[1], where), parse_number(fields[2], where), parse_number(fields[3], where));
  }
  if (file.bad()) throw InputError(fmt::format("cannot read '{}'", path));
  if (times.size() < 2) {
    throw InputError(fmt::format("{}: needs at least two samples, got {}", path, times.size()));
  }
  return {std::move(times), std::move(rates)};
}

Eigen::Vector3d BodyRateSeries::at(double t_si) const {
  if (!(t_si >= times_.front() && t_si <= times_.back())) {
    throw std::out_of_range(
        fmt::format("time {} outside the body-rate series [{}, {}]", t_si, times_.front(), times_.back()));
  }
  // First sample strictly after t, clamped so that t = end_time() uses the last interval.
  const auto after = std::upper_bound(times_.begin() + 1, times_.end() - 1, t_si);
  const auto i = static_cast<std::size_t>(after - times_.begin());
  const double fraction = (t_si - times_[i - 1]) / (times_[i] - times_[i - 1]);
  return (1.0 - fraction) * omega_b_[i - 1] + fraction * omega_b_[i];
}

}  // namespace settle::attitude
