// The progress line of long runs (sim::progressText): a run of hours must read as hours, not as
// hundreds of minutes, and a run that has not moved yet has no ETA. Its ETA (sim::ProgressPace)
// follows the current phase of a run, not the average since the start.
#include <gtest/gtest.h>

#include <cmath>
#include <string>

#include "sim/run_outputs.hpp"

namespace millsim {
namespace {

TEST(ProgressText, EtaInMinutesBelowAnHourAndHoursAbove) {
  EXPECT_EQ(sim::progressText(3.2, 12.0, 41200, 21 * 60 + 5), " t = 3.200 / 12.000 s   27%  41200 steps/s  ETA 21:05");
  // 2.5 h of the 500 mm wet mill: 9000 s.
  EXPECT_EQ(sim::progressText(2.5, 12.0, 85, 9000), " t = 2.500 / 12.000 s   21%  85 steps/s  ETA 2:30:00");
  EXPECT_EQ(sim::progressText(0.0, 12.0, 0, 0), " t = 0.000 / 12.000 s    0%  0 steps/s  ETA --");
}

// The wet mill's two phases, as the 2026-12-06 run logged them: 2 s of dry compaction in ~60 s of
// wall, then coupled rotation at ~800 wall s per simulated second (and ~35 steps per wall s),
// sampled every 60 s as in a log file. 10 minutes into the slow phase the ETA must be the slow
// phase's: (12 - t) x 800 s. The exact value of the exponential average after n samples of the
// new pace P after a first pace P0: P + (P0 - P) exp(-n 60 / tau), tau = 120 s, n = 10:
// within 0.7% of P. (The whole-run average, what the line printed before, gives 0.30 of it.)
TEST(ProgressPace, EtaFollowsThePhaseTheRunIsIn) {
  sim::ProgressPace pace;
  EXPECT_EQ(pace.etaSeconds(12), 0.0);  // not moved yet
  pace.sample(0, 0, 0);
  EXPECT_EQ(pace.etaSeconds(12), 0.0);
  pace.sample(60, 2.0, 70000);  // compaction: 30 wall s per simulated s
  EXPECT_NEAR(pace.etaSeconds(12), 10 * 30.0, 1e-9);
  double wall = 60, t = 2.0;
  long long steps = 70000;
  for (int n = 0; n < 10; ++n) {
    wall += 60, t += 60.0 / 800, steps += 60 * 35;
    pace.sample(wall, t, steps);
  }
  const double want = (12 - t) * 800;
  const double p = 800 + (30 - 800) * std::exp(-10 * 60.0 / 120);
  EXPECT_NEAR(pace.etaSeconds(12), (12 - t) * p, 1e-6 * want);
  EXPECT_NEAR(pace.etaSeconds(12) / want, 1.0, 0.007);
  EXPECT_NEAR(pace.stepsPerSecond(), 35.0, 0.007 * 35);  // averaged as wall time per step
  // No simulated time between two samples (a stall, a long output): no pace from it; the next
  // sample covers both intervals.
  pace.sample(wall + 30, t, steps);
  EXPECT_NEAR(pace.etaSeconds(12), (12 - t) * p, 1e-6 * want);
  pace.sample(wall + 60, t + 60.0 / 800, steps + 60 * 35);
  EXPECT_NEAR(pace.etaSeconds(12) / ((12 - t - 60.0 / 800) * 800), 1.0, 0.007);
}

}  // namespace
}  // namespace millsim
