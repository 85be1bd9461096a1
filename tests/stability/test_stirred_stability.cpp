// Stirred mill at its hardest (issue 6, Done-when 5): 4000 rpm with eta = 1 Pa s and the seed's
// smallest lubrication gaps (inner cutoff 0.001 d), reduced size (the CI slice of
// stirred_mill_ls1_small.xml). Must run without NaN (the engine throws on a non-finite position)
// and without beads leaving the chamber (checked at every series row, 0.5 ms).
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>

#include "support/case_run.hpp"

namespace {

TEST(StirredStability, FourThousandRpmWithOnePascalSecond) {
  const auto r = millsim::testing::runCase("stirred_mill_ls1_small",
                                           {"stirrer.speeds_rpm=4000", "stirrer.ramp=0.002", "stirrer.hold=0.01",
                                            "lubrication.viscosity=1", "lubrication.inner=0.001"},
                                           "stirred_stability");
  ASSERT_EQ(r.summary["status"], "ok");
  const auto& speed = r.series.at("max_speed_m_s");
  ASSERT_FALSE(speed.empty());
  // Bounded speeds: a bead struck by the disk rim (38 mm at 4000 rpm: 15.9 m/s) leaves at most
  // (1 + e) = 1.5 times the rim speed faster than it came; 2x the tip speed leaves room for a
  // second hit, while a diverging step gives speeds orders of magnitude larger.
  const double tip = 0.038 * 4000 * 2 * 3.14159265358979323846 / 60;
  EXPECT_LT(*std::max_element(speed.begin(), speed.end()), 2 * tip);
  EXPECT_LT(std::abs(double(r.summary["stirred"]["energy"]["residual_relative"])), 0.02);
}

}  // namespace
