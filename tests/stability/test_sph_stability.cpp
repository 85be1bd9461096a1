// Issue 4, Done-when 6: a still tank stays still for 10 s of simulated time, and a violently
// sloshing tank (cases/sloshing_tank_2d.xml at 30 rpm: the water is lifted by the walls and
// thrown across, speeds reach 2.4x the wall speed) finishes without NaN and with fewer than
// 0.1% of its particles excluded, its mass conserved.
#include <gtest/gtest.h>

#include <cmath>

#include "support/case_run.hpp"

namespace millsim {
namespace {

TEST(SphStability, StillTankStaysStillForTenSeconds) {
  // The hydrostatic column at dp = H/20 (so 10 s fit in CI: 44k steps).
  const auto r = testing::runCase("hydrostatic_2d", {"sph.dp=0.05", "time.end=10", "output.fields_every=0",
                                                     "output.series_every=0.05", "probes.points=bottom:0.5,0.025"},
                                  "still_tank");
  ASSERT_EQ(r.summary["status"], "ok");
  const double g = 9.81, H = 1.0;
  double vmax = 0;
  for (double v : r.series.at("max_speed_m_s")) vmax = std::max(vmax, v);
  EXPECT_LT(vmax, 0.01 * std::sqrt(g * H)) << "largest fluid speed over the 10 s";
  EXPECT_EQ(r.summary["excluded"]["total"], 0);
  EXPECT_EQ(r.summary["fluid_mass_kg"]["active"].get<double>(), r.summary["fluid_mass_kg"]["initial"].get<double>());
  // The pressure does not drift: bottom row at rho0 g (H - dp/2) within 2% at the end.
  const double p_end = r.series.at("p_bottom_Pa").back();
  EXPECT_NEAR(p_end, 1000 * g * (H - 0.025), 0.02 * 1000 * g * H);
}

TEST(SphStability, ViolentSloshingFinishesWithoutLosses) {
  const auto r = testing::runCase("sloshing_tank_2d", {"tank.rotation_rpm=30", "output.fields_every=0"}, "sloshing");
  ASSERT_EQ(r.summary["status"], "ok");
  const long long fluid = r.summary["particles"]["sph_fluid"];
  EXPECT_LE(r.summary["excluded"]["total"].get<double>(), 0.001 * double(fluid));
  EXPECT_DOUBLE_EQ(r.summary["fluid_mass_kg"]["including_excluded"].get<double>(),
                   r.summary["fluid_mass_kg"]["initial"].get<double>());
  // Violent indeed: the water moves faster than the walls (omega R_corner = 1.1 m/s).
  double vmax = 0;
  for (double v : r.series.at("max_speed_m_s")) {
    ASSERT_TRUE(std::isfinite(v));
    vmax = std::max(vmax, v);
  }
  EXPECT_GT(vmax, 1.5);
  EXPECT_LT(vmax, 10.0);  // bounded: c0 = 31 m/s
  for (double rho : r.series.at("rho_max")) EXPECT_LT(rho, 1050.0);  // weakly compressible: < 5%
}

}  // namespace
}  // namespace millsim
