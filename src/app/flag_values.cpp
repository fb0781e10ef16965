#include "app/flag_values.hpp"

#include <charconv>
#include <cmath>

#include <fmt/core.h>

#include "common/error.hpp"

namespace settle::app {

double parse_number(const std::string& text, const std::string& flag) {
  double value = 0.0;
  const char* end = text.data() + text.size();
  const auto [stop, ec] = std::from_chars(text.data(), end, value);
  if (ec != std::errc() || stop != end || !std::isfinite(value))
    throw InputError(fmt::format("{}: expected a finite number, got '{}'", flag, text));
  return value;
}

double positive_number(const std::string& text, const std::string& flag) {
  const double value = parse_number(text, flag);
  if (!(value > 0.0)) throw InputError(fmt::format("{}: must be > 0, got {}", flag, text));
  return value;
}

std::vector<double> parse_numbers(const std::string& text, const std::string& flag, std::size_t count) {
  std::vector<std::string> parts(1);
  for (const char c : text) {
    if (c == ',')
      parts.emplace_back();
    else
      parts.back() += c;
  }
  if (parts.size() != count)
    throw InputError(fmt::format("{}: expected {} comma-separated numbers, got '{}'", flag, count, text));
  std::vector<double> values;
  for (const std::string& part : parts) values.push_back(parse_number(part, flag));
  return values;
}

}  // namespace settle::app
