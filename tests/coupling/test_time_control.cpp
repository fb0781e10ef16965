// The output schedule (coupling/time_control.hpp) as a run and its continuation see it: a run
// stopped after any step and continued from the schedule's next_index() (what a checkpoint stores)
// must produce exactly the outputs of the uninterrupted run, none repeated and none skipped.
#include <cstdint>
#include <vector>

#include <gtest/gtest.h>

#include "coupling/time_control.hpp"

namespace {

using settle::coupling::OutputSchedule;

constexpr double kDt = 1.2468e-4;  // an awkward step, as a real case's (not a power of two)
constexpr int kSteps = 60;

/// The steps at which `schedule` is due from `first` to kSteps, as the run loop asks it: once
/// at the start step and after every step.
std::vector<int> due_steps(OutputSchedule& schedule, int first) {
  std::vector<int> steps;
  for (int n = first; n <= kSteps; ++n)
    if (schedule.due(n * kDt, kDt)) steps.push_back(n);
  return steps;
}

/// Stopped after each step in turn and continued: the two parts together are the whole run.
void expect_continuation_is_seamless(double interval_si) {
  OutputSchedule whole(interval_si);
  const std::vector<int> straight = due_steps(whole, 0);
  for (int stop = 0; stop < kSteps; ++stop) {
    OutputSchedule first(interval_si);
    std::vector<int> joined;
    for (int n = 0; n <= stop; ++n)
      if (first.due(n * kDt, kDt)) joined.push_back(n);
    OutputSchedule continued(interval_si);
    continued.set_next_index(first.next_index());
    const std::vector<int> rest = due_steps(continued, stop);
    joined.insert(joined.end(), rest.begin(), rest.end());
    EXPECT_EQ(joined, straight) << "stopped after step " << stop;
  }
}

TEST(OutputSchedule, EveryStepIsDueOnceAcrossARestart) {
  OutputSchedule every(0.0);
  EXPECT_EQ(due_steps(every, 0).size(), static_cast<std::size_t>(kSteps + 1));
  expect_continuation_is_seamless(0.0);
}

TEST(OutputSchedule, AnIntervalIsDueOnceAcrossARestart) {
  OutputSchedule interval(7.4 * kDt);
  // Outputs at the first step within half a step of each multiple of 7.4 dt (every multiple is at
  // least 0.1 dt from that threshold, so round-off cannot move one).
  EXPECT_EQ(due_steps(interval, 0), (std::vector<int>{0, 7, 15, 22, 30, 37, 44, 52, 59}));
  expect_continuation_is_seamless(7.4 * kDt);
}

TEST(OutputSchedule, ANegativeIntervalIsNeverDue) {
  OutputSchedule never(-1.0);
  EXPECT_TRUE(due_steps(never, 0).empty());
}

}  // namespace
