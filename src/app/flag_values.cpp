#include "app/flag_values.hpp"

#include <algorithm>
#include <charconv>
#include <cmath>
#include <thread>

#include <fmt/core.h>

#include "common/error.hpp"

namespace settle::app {

int max_thread_count() {
  constexpr int kThreadsPerCore = 4, kAtLeast = 256;
  const auto cores = static_cast<int>(std::max(1u, std::thread::hardware_concurrency()));
  return std::max(kAtLeast, kThreadsPerCore * cores);
}

void check_thread_count(int threads, const std::string& flag) {
  if (threads < 0) throw InputError(fmt::format("{}: must be >= 1 (or 0 for OpenMP's default), got {}", flag, threads));
  if (threads > max_thread_count())
    throw InputError(
        fmt::format("{}: {} threads are more than the {} settle starts on this machine of {} cores (4 "
                    "per core, at least 256); OpenMP cannot create that many",
                    flag, threads, max_thread_count(), std::max(1u, std::thread::hardware_concurrency())));
}

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
