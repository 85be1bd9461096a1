// Stirred mill at its hardest (issue 6, Done-when 5): 4000 rpm with eta = 1 Pa s and the seed's
// smallest lubrication gaps (inner cutoff 0.001 d), reduced size (the CI slice of
// stirred_mill_ls1_small.xml). Must run without NaN (the engine throws on a non-finite position)
// and without beads leaving the chamber (checked at every series row, 0.5 ms).
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>

#include "millsim/core/error.hpp"
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

namespace {

// The guard, not the physics: the same case with the seed's film at 1e-5 d and a fixed step
// that ignores the film's time-step limit (1.76e-6 s instead of ~2e-8 s) diverges within ~20
// steps. The run must stop with the cause (the particle, the step, the likely cause), keep the
// last good state (its fields frames), and record the failure in summary.json; before the cell index was
// clamped in floating point, a position past 2^31 cells crashed the neighbour build instead.
TEST(StirredStability, DivergingStepStopsWithTheParticleAndTheCause) {
  const std::string out = (std::filesystem::temp_directory_path() / "millsim_test_stirred_diverge").string();
  std::filesystem::remove_all(out);
  const auto scene = millsim::io::loadCaseFile(
      std::string(MILLSIM_SOURCE_DIR) + "/cases/stirred_mill_ls1_small.xml",
      {"stirrer.speeds_rpm=4000", "stirrer.ramp=0.002", "stirrer.hold=0.01", "lubrication.viscosity=1",
       "lubrication.inner=0.00001", "time.dt=fixed", "time.dt_fixed=1.76e-6"});
  millsim::sim::RunOptions opt;
  opt.out_dir = out;
  opt.threads = 1;
  opt.backend = "omp";
  millsim::sim::Simulation sim(scene, opt);
  std::string what;
  try {
    sim.run();
  } catch (const millsim::core::SimulationError& e) {
    what = e.what();
  }
  EXPECT_NE(what.find("DEM: particle "), std::string::npos) << what;
  EXPECT_NE(what.find("diverged at solver step"), std::string::npos) << what;
  EXPECT_NE(what.find("Likely cause: dt = 1.76e-06 s"), std::string::npos) << what;
  // The last good state: the fields frame written at t = 0 (the run fails before the next).
  EXPECT_TRUE(std::filesystem::exists(out + "/fields.xdmf"));
  EXPECT_TRUE(std::filesystem::exists(out + "/series.csv"));
  std::ifstream js(out + "/summary.json");
  const auto summary = nlohmann::json::parse(js);
  EXPECT_EQ(summary["status"], "failed");
}

}  // namespace
