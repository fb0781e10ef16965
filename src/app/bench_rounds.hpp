#pragma once
// What the two benchmarks of `settle bench` share: timed rounds of work, each bracketed by two
// probes of this machine's memory bandwidth, and the fraction of it that the work reached.
#include <functional>
#include <string>
#include <vector>

#include <nlohmann/json.hpp>

namespace settle::app {

/// What one round reports: the bytes per second that the measured kernel moved, and a line for
/// the progress output.
struct RoundResult {
  double achieved_gbs = 0.0;
  std::string description;
};

/// The probes around the rounds and each round's fraction of them.
struct BracketedRounds {
  std::vector<double> bandwidth_gbs;    ///< rounds + 1 probes: one before the first round, one after each
  std::vector<double> fraction;         ///< each round's achieved GB/s over the mean of its two probes
  std::vector<double> steady_fraction;  ///< the fractions of the rounds whose two probes agree within 10%
};

double median(std::vector<double> values);

/// Runs `rounds` rounds (run_round receives the round's index) between bandwidth probes of
/// `probe_gib` GiB, printing one line per round to stderr when `speak` (under mpirun, rank 0).
BracketedRounds run_bracketed_rounds(int rounds, double probe_gib, const std::function<RoundResult(int)>& run_round,
                                     bool speak = true);

/// Adds the probes, the per-round fractions, their median (`roofline_fraction`) and the build to
/// a benchmark's JSON.
void add_roofline(nlohmann::json& j, const BracketedRounds& b, double probe_gib);

}  // namespace settle::app
