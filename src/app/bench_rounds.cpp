#include "app/bench_rounds.hpp"

#include <algorithm>
#include <cmath>
#include <cstdio>

#include <fmt/core.h>

#include "common/bandwidth_probe.hpp"
#include "common/build_info.hpp"

namespace settle::app {

double median(std::vector<double> values) {
  std::sort(values.begin(), values.end());
  const std::size_t n = values.size();
  return n % 2 ? values[n / 2] : 0.5 * (values[n / 2 - 1] + values[n / 2]);
}

// The memory bandwidth of a virtual machine drifts with its neighbours' load (on the development
// machine single probe sweeps ranged from 41 to 131 GB/s within minutes, and the host switched
// between its fast and slow modes inside one run), so every round is bracketed by a probe before
// and after it and its fraction is taken against the mean of the two. The reported fraction is
// the median over the rounds whose two probes agree within 10% (the bandwidth held still; over all
// rounds if none did): separate medians of throughput and bandwidth would mix rounds from
// different modes. The probe keeps the best of 3 sweeps, which favours the probe, not the kernel.
BracketedRounds run_bracketed_rounds(int rounds, double probe_gib, const std::function<RoundResult(int)>& run_round,
                                     bool speak) {
  const auto probe = [probe_gib] {
    return measure_inplace_bandwidth(static_cast<std::size_t>(probe_gib * 1073741824.0), 3).bandwidth_gbs;
  };
  BracketedRounds b;
  b.bandwidth_gbs.push_back(probe());
  for (int round = 0; round < rounds; ++round) {
    const RoundResult r = run_round(round);
    b.bandwidth_gbs.push_back(probe());
    const double before = b.bandwidth_gbs[round], after = b.bandwidth_gbs[round + 1];
    const double bracket_gbs = 0.5 * (before + after);
    b.fraction.push_back(r.achieved_gbs / bracket_gbs);
    if (std::abs(after - before) <= 0.1 * bracket_gbs) b.steady_fraction.push_back(b.fraction.back());
    if (speak)
      fmt::print(stderr, "  round {}: {}, probes {:.1f} / {:.1f} GB/s, fraction {:.3f}\n", round + 1, r.description,
                 before, after, b.fraction.back());
  }
  return b;
}

void add_roofline(nlohmann::json& j, const BracketedRounds& b, double probe_gib) {
  j["bandwidth_gbs"] = median(b.bandwidth_gbs);
  j["bandwidth_probe"] = {{"kind", "in-place read-modify-write x = a x + b, best of 3 sweeps per probe"},
                          {"array_bytes", probe_gib * 1073741824.0},
                          {"bandwidth_gbs_before_and_after_rounds", b.bandwidth_gbs}};
  j["roofline_fraction_per_round"] = b.fraction;
  j["steady_rounds"] = b.steady_fraction.size();
  j["roofline_fraction"] = median(b.steady_fraction.empty() ? b.fraction : b.steady_fraction);
  if (b.steady_fraction.empty())
    j["warning_bandwidth"] = "the bandwidth changed by more than 10% across every round: the fraction is uncertain";
  const BuildInfo build = build_info();
  j["build"] = {{"version", build.version},
                {"compiler", build.compiler},
                {"build_type", build.build_type},
                {"native_cpu", build.native_cpu},
                {"sanitizers", build.sanitizers}};
  if (!build.native_cpu) j["warning"] = "built without -march=native (use the `native` preset for benchmark figures)";
}

}  // namespace settle::app
