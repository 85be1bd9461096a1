// Issue 5, Done-when 4 (reduced size): the small wet drum (cases/wet_drum_small.xml) at 100% of
// the critical speed, slurry poured into the settled charge and the balls thrown through it,
// and balls dropped from the top of the drum into the slurry pool. Both must finish with no
// NaN, no ball leaving the drum (the run loop stops with exit 3 otherwise), fewer than 0.5% of
// the slurry excluded, and a measured slurry curve.
#include <gtest/gtest.h>

#include <cmath>

#include "support/case_run.hpp"

namespace millsim {
namespace {

void expectBounded(const testing::CaseOutput& r) {
  ASSERT_EQ(r.summary["status"], "ok");
  const auto& wet = r.summary["wet_mill"];
  const double sph = r.summary["particles"]["sph"].get<double>();
  EXPECT_GT(wet["sph_steps"].get<double>(), 100);
  EXPECT_LT(wet["sph_excluded"].get<double>(), 0.005 * sph);
  EXPECT_FALSE(wet["slurry_curve_mm"].is_null());
  for (double v : r.series.at("max_speed_m_s")) {
    ASSERT_TRUE(std::isfinite(v));
    EXPECT_LT(v, 10.0);  // a ball in a 0.2 m drum at 100% critical moves at ~1 m/s
  }
}

TEST(WetMillStability, CriticalSpeedWithSlurry) {
  expectBounded(testing::runCase("wet_drum_small",
                                 {"drum.critical_fraction=1.0", "time.end=0.75", "angle_of_repose.start_time=0.6",
                                  "angle_of_repose.frames=5", "output.fields_every=0"},
                                 "wet_critical"));
}

TEST(WetMillStability, BallsDroppedIntoSlurry) {
  // The slurry is poured while the balls are still falling from the loose placement (before
  // the piston has packed them): at 0.05 s they drop through the pool.
  expectBounded(testing::runCase("wet_drum_small",
                                 {"drum.start_time=0.05", "time.end=0.2", "angle_of_repose.start_time=0.1",
                                  "angle_of_repose.frames=5", "output.fields_every=0"},
                                 "wet_drop"));
}

}  // namespace
}  // namespace millsim
