// The progress line of long runs (sim::progressText): a run of hours must read as hours, not as
// hundreds of minutes, and a run that has not moved yet has no ETA.
#include <gtest/gtest.h>

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

}  // namespace
}  // namespace millsim
