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

/// The most OpenMP threads a --threads flag may ask for: 4 per core of this machine
/// (std::thread::hardware_concurrency), and never fewer than 256, so that a restart can use the
/// thread count of a larger machine's run (bit-for-bit continuation needs the same count).
/// Beyond some tens of thousands libgomp cannot create them: 50 000 aborted, 100 000 crashed with
/// SIGSEGV after the output directory was prepared.
int max_thread_count();

/// A --threads value: 0 (OpenMP's default) or 1 .. max_thread_count(). settle::InputError naming
/// `flag` otherwise.
void check_thread_count(int threads, const std::string& flag);

template <std::size_t N>
std::array<double, N> parse_list(const std::string& text, const std::string& flag) {
  const std::vector<double> values = parse_numbers(text, flag, N);
  std::array<double, N> list{};
  for (std::size_t i = 0; i < N; ++i) list[i] = values[i];
  return list;
}

}  // namespace settle::app
