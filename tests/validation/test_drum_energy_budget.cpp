// Energy budget of the shipped 300 mm mill over one second of rotation (issue 9, Done-when 4):
// the work the drum walls do on the balls equals the change of kinetic, potential and elastic
// energy plus what the contacts dissipated, within 2 % of the work put in.
//
// Window: t = 2 s (the piston has pushed the charge in, the drum starts) to t = 3 s, from the
// series.csv rows, so the compaction does not enter. The residual is the integration error of
// velocity Verlet's bookkeeping (dissipation and wall work at the half-step velocity: first order
// in dt, docs/validation.md "Stability"); at the case's dt = t_c/50 it is well below the bound
// for both damping models. The bound comes from the issue; a bookkeeping error (a missed wall
// work term, dissipation booked twice for a pair) is tens of percent of the work.
#include <gtest/gtest.h>

#include <cmath>
#include <string>
#include <vector>

#include "support/case_run.hpp"

namespace millsim {
namespace {

struct Budget {
  double work = 0, residual = 0;
};

Budget windowBudget(const testing::CaseOutput& r, double t0, double t1) {
  const auto& t = r.series.at("time_s");
  auto row = [&](double at) {
    std::size_t best = 0;
    for (std::size_t k = 0; k < t.size(); ++k)
      if (std::abs(t[k] - at) < std::abs(t[best] - at)) best = k;
    return best;
  };
  const std::size_t a = row(t0), b = row(t1);
  auto d = [&](const char* col) { return r.series.at(col)[b] - r.series.at(col)[a]; };
  Budget out;
  out.work = d("work_in_J");
  out.residual = out.work - (d("kinetic_J") + d("potential_J") + d("elastic_J") + d("dissipated_J"));
  return out;
}

void expectBudgetCloses(const std::vector<std::string>& overrides, const std::string& name) {
  std::vector<std::string> o = overrides;
  for (const char* s :
       {"time.end=3", "output.fields_every=0", "output.checkpoint_every=0", "angle_of_repose.enabled=false"})
    o.push_back(s);
  const testing::CaseOutput r = testing::runCase("ball_mill_300_balls", o, name);
  ASSERT_EQ(r.summary["status"], "ok");
  const Budget b = windowBudget(r, 2.0, 3.0);
  ::testing::Test::RecordProperty("work_in_J", std::to_string(b.work));
  ::testing::Test::RecordProperty("residual_relative", std::to_string(b.residual / b.work));
  ASSERT_GT(b.work, 0.0);  // the drum lifts the charge
  EXPECT_LT(std::abs(b.residual), 0.02 * b.work) << "work " << b.work << " J, residual " << b.residual << " J";
}

TEST(DrumEnergyBudget, ClosesOverOneSecondExactDamping) { expectBudgetCloses({}, "budget_exact"); }

TEST(DrumEnergyBudget, ClosesOverOneSecondPaperContactModel) {
  expectBudgetCloses({"dem.damping=dualsphysics", "dem.friction_smoothing=tanh"}, "budget_paper");
}

// The same budget with the paper's DCDEM balls (10 mm balls of 19 elements at dp = 2.5 mm in the
// small test drum, 0.7 s of rotation after the compaction): the element contacts book their
// dissipation and wall work per element and the bodies integrate the summed loads, so the
// budget must close as tightly as with spheres (measured: -0.93% of the work; spheres in the
// same drum and window -0.85%).
TEST(DrumEnergyBudget, ClosesWithDcdemBalls) {
  const testing::CaseOutput r = testing::runCase(
      "minimal_drum",
      {"dem.representation=dcdem", "dem.element_spacing=0.0025", "output.fields_every=0", "output.checkpoint_every=0"},
      "budget_dcdem");
  ASSERT_EQ(r.summary["status"], "ok");
  const Budget b = windowBudget(r, 0.3, 1.0);
  ::testing::Test::RecordProperty("residual_relative", std::to_string(b.residual / b.work));
  ASSERT_GT(b.work, 0.0);
  EXPECT_LT(std::abs(b.residual), 0.02 * b.work) << "work " << b.work << " J, residual " << b.residual << " J";
}

}  // namespace
}  // namespace millsim
