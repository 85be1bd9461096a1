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

// No ball can move faster than the drum can make it (the minimal drum's bound in
// test_drum_stability.cpp): the wall speed omega R plus a free fall across the diameter,
// sqrt(2 g D); the slurry only takes energy from the balls. omega = f sqrt(g / (R - r)) with the
// largest balls' r (10 mm: the highest critical speed the case could define).
void expectBounded(const testing::CaseOutput& r, double critical_fraction) {
  ASSERT_EQ(r.summary["status"], "ok");
  const auto& wet = r.summary["wet_mill"];
  const double sph = r.summary["particles"]["sph"].get<double>();
  EXPECT_GT(wet["sph_steps"].get<double>(), 100);
  EXPECT_LT(wet["sph_excluded"].get<double>(), 0.005 * sph);
  EXPECT_FALSE(wet["slurry_curve_mm"].is_null());
  const double R = 0.1, g = 9.81, omega = critical_fraction * std::sqrt(g / (R - 0.01));
  const double bound = omega * R + std::sqrt(2 * g * 2 * R);
  for (double v : r.series.at("max_speed_m_s")) {
    ASSERT_TRUE(std::isfinite(v));
    EXPECT_LT(v, bound);
  }
}

TEST(WetMillStability, CriticalSpeedWithSlurry) {
  expectBounded(testing::runCase("wet_drum_small",
                                 {"drum.critical_fraction=1.0", "time.end=0.75", "angle_of_repose.start_time=0.6",
                                  "angle_of_repose.frames=5", "output.fields_every=0"},
                                 "wet_critical"),
                1.0);
}

TEST(WetMillStability, BallsDroppedIntoSlurry) {
  // The slurry is poured while the balls are still falling from the loose placement (before
  // the piston has packed them): at 0.05 s they drop through the pool.
  expectBounded(testing::runCase("wet_drum_small",
                                 {"drum.start_time=0.05", "time.end=0.2", "angle_of_repose.start_time=0.1",
                                  "angle_of_repose.frames=5", "output.fields_every=0"},
                                 "wet_drop"),
                0.3);
}

}  // namespace
}  // namespace millsim
