// An ensemble (several drum cases in one DEM solver, issue 10) must give each case what it gives
// alone: the cases sit in separate slabs of one domain with their own drums and contact laws,
// so with its own time step every ball follows the same equations as in its own run. What
// differs is only the order of floating-point sums (the cell order of the particles covers all
// cases, and the neighbour list is rebuilt when ANY ball has moved half the skin), so the
// energies agree to round-off grown by the dynamics over the window; a wrong law, wall or
// slab for one case (case 2's friction applied to case 1, a drum turned by another case's
// motion, a pair across two cases) moves them by percents.
#include <gtest/gtest.h>

#include <cmath>
#include <filesystem>
#include <string>
#include <vector>

#include "millsim/core/error.hpp"
#include "millsim/io/case_xml.hpp"
#include "millsim/sim/ensemble_run.hpp"
#include "millsim/sim/simulation.hpp"
#include "support/ensemble_cases.hpp"

namespace millsim {
namespace {

const std::string kMinimal = testing::minimalDrumCase();
// The three drums, the window and why 1e-6 of the work bounds the difference:
// tests/support/ensemble_cases.hpp.

sim::RunOptions quietOptions() {
  sim::RunOptions opt;
  opt.backend = "omp";
  opt.write_outputs = false;
  opt.threads = 1;
  return opt;
}

TEST(DrumEnsemble, EachCaseMovesAsItDoesAlone) {
  sim::EnsembleSpec spec;
  spec.run = quietOptions();
  std::vector<sim::RunSummary> alone;
  for (const auto& sets : testing::ensembleTestDrums()) {
    const scene::Scene s = io::loadCaseFile(kMinimal, sets);
    sim::Simulation solo(s, quietOptions());
    alone.push_back(solo.run());
    spec.scenes.push_back(s);
    spec.out_dirs.push_back("unused");
  }
  const std::vector<sim::RunSummary> together = sim::runEnsemble(spec);
  ASSERT_EQ(together.size(), alone.size());
  ASSERT_GT(alone[1].dt, 1.1 * alone[0].dt);  // the cases really step differently
  for (std::size_t k = 0; k < alone.size(); ++k) {
    const sim::RunSummary &a = alone[k], &e = together[k];
    SCOPED_TRACE("case " + std::to_string(k));
    EXPECT_EQ(e.status, "ok");
    EXPECT_EQ(e.particles, a.particles);
    EXPECT_EQ(e.steps, a.steps);
    EXPECT_DOUBLE_EQ(e.dt, a.dt);  // its own step, not the ensemble's smallest
    // Energies at the end and the work the pistons and the drums put in.
    const double scale = a.energy_work_in;
    ASSERT_GT(scale, 0.0);
    ASSERT_GT(std::abs(a.power_W), 1e-3);  // the drum turns (while the charge still settles: either sign)
    EXPECT_NEAR(e.energy_work_in, a.energy_work_in, 1e-6 * scale);
    EXPECT_NEAR(e.energy_dissipated, a.energy_dissipated, 1e-6 * scale);
    EXPECT_NEAR(e.energy_kinetic, a.energy_kinetic, 1e-6 * scale);
    EXPECT_NEAR(e.energy_potential - a.energy_potential, 0.0, 1e-6 * scale);
    EXPECT_NEAR(e.power_W, a.power_W, 1e-6 * std::abs(a.power_W));
    // The budget of each case closes over its own balls and drum.
    EXPECT_NEAR(e.energy_residual, a.energy_residual, 1e-6 * scale);
  }
}

TEST(DrumEnsemble, CasesThatCannotShareASolverAreRefusedByName) {
  sim::EnsembleSpec spec;
  spec.run = quietOptions();
  spec.scenes.push_back(io::loadCaseFile(kMinimal, {}));
  spec.scenes.push_back(io::loadCaseFile(kMinimal, {"dem.youngs_modulus=2e8"}));
  spec.out_dirs = {"a", "b"};
  try {
    sim::runEnsemble(spec);
    FAIL() << "an ensemble of two stiffnesses ran";
  } catch (const core::InputError& err) {
    const std::string m = err.what();
    EXPECT_NE(m.find("minimal_drum.xml"), std::string::npos) << m;
    EXPECT_NE(m.find("youngs_modulus"), std::string::npos) << m;
  }
  spec.scenes[1] = io::loadCaseFile(kMinimal, {"dem.representation=dcdem", "dem.element_spacing=0.0025"});
  EXPECT_THROW(sim::runEnsemble(spec), core::InputError);
}

}  // namespace
}  // namespace millsim
