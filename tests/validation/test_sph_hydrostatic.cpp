// Issue 4, Done-when 1: a 2D water column (H = 1 m, dp = H/40) held for 2 s in a DBC tank
// (cases/hydrostatic_2d.xml) keeps its hydrostatic pressure, loses no particle and conserves
// its mass exactly, with both integrators, and in single precision (Verlet) with the same bounds.
#include <gtest/gtest.h>

#include <cmath>

#include "support/case_run.hpp"

namespace millsim {
namespace {

class Hydrostatic : public ::testing::TestWithParam<const char*> {};

TEST_P(Hydrostatic, BottomPressureMassAndStillness) {
  // "integrator" or "integrator/float".
  const std::string param = GetParam(), integrator = param.substr(0, param.find('/'));
  const std::string precision = param.find("/float") != std::string::npos ? "float" : "double";
  const auto r = testing::runCase("hydrostatic_2d", {"sph.integrator=" + integrator, "output.fields_every=0"},
                                  "hydrostatic_" + integrator + "_" + precision, 1, precision);
  ASSERT_EQ(r.summary["status"], "ok");
  ASSERT_EQ(r.summary["precision"], precision);
  const double rho0 = 1000, g = 9.81, H = 1.0, dp = 0.025;
  // Probe "bottom" sits at the centre of the first fluid row, y = dp/2: after settling its
  // pressure is rho0 g (H - dp/2) (1.25% below rho0 g H). Issue: within 3% of rho0 g H; the
  // 1% bound against the exact value at the probe is ours (DBC walls carry the column with a
  // ~1 dp gap, which shifts the pressure by ~0.5%).
  const auto& p = r.series.at("p_bottom_Pa");
  const auto& t = r.series.at("time_s");
  double mean = 0;
  int n = 0;
  for (std::size_t i = 0; i < t.size(); ++i)
    if (t[i] >= 1.5) {  // last 0.5 s, after the settling of the first second
      mean += p[i];
      ++n;
    }
  mean /= n;
  EXPECT_NEAR(mean, rho0 * g * H, 0.03 * rho0 * g * H);
  EXPECT_NEAR(mean, rho0 * g * (H - 0.5 * dp), 0.01 * rho0 * g * H);
  // Half depth: rho0 g H / 2 within 3%.
  double mid = 0;
  for (std::size_t i = 0; i < t.size(); ++i)
    if (t[i] >= 1.5) mid += r.series.at("p_mid_Pa")[i] / n;
  EXPECT_NEAR(mid, 0.5 * rho0 * g * H, 0.03 * 0.5 * rho0 * g * H);
  // Nothing leaves, the fluid mass is exactly N m.
  EXPECT_EQ(r.summary["excluded"]["total"], 0);
  EXPECT_EQ(r.summary["fluid_mass_kg"]["active"].get<double>(), r.summary["fluid_mass_kg"]["initial"].get<double>());
  EXPECT_EQ(r.summary["particles"]["sph_fluid"], 1600);
  // Still: the largest speed stays below 1% of sqrt(g H).
  double vmax = 0;
  for (std::size_t i = 0; i < t.size(); ++i)
    if (t[i] >= 0.5) vmax = std::max(vmax, r.series.at("max_speed_m_s")[i]);
  EXPECT_LT(vmax, 0.01 * std::sqrt(g * H));
}

INSTANTIATE_TEST_SUITE_P(Sph, Hydrostatic, ::testing::Values("verlet", "symplectic", "verlet/float"));

}  // namespace
}  // namespace millsim
