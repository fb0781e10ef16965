#pragma once
// Numbers given on the command line. Each flag's value arrives as text, so that every message
// names the flag: "--diameter: expected a finite number, got 'x'" (settle::InputError).
#include <array>
#include <cstddef>
#include <string>
#include <vector>

namespace settle::app {

/// The text as a finite number.
double parse_number(const std::string& text, const std::string& flag);
/// The text as a finite number > 0.
double positive_number(const std::string& text, const std::string& flag);
/// Exactly `count` comma-separated finite numbers.
std::vector<double> parse_numbers(const std::string& text, const std::string& flag, std::size_t count);

template <std::size_t N>
std::array<double, N> parse_list(const std::string& text, const std::string& flag) {
  const std::vector<double> values = parse_numbers(text, flag, N);
  std::array<double, N> list{};
  for (std::size_t i = 0; i < N; ++i) list[i] = values[i];
  return list;
}

}  // namespace settle::app
