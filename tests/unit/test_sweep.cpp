// `millsim sweep` (src/sim/sweep.cpp): the grid's runs in order, the same results whether on one
// process or spread over ranks (the MPI code path, on threads: tests/support/thread_ranks.hpp),
// a run that goes unstable becomes a failed row while the others go on, bad input fails first.
#include <gtest/gtest.h>

#include <cmath>
#include <filesystem>
#include <fstream>
#include <sstream>

#include "millsim/core/error.hpp"
#include "millsim/sim/sweep.hpp"
#include "support/thread_ranks.hpp"

namespace millsim::sim {
namespace {

SweepSpec smallSweep(const std::string& out) {
  SweepSpec spec;
  spec.case_path = std::string(MILLSIM_SOURCE_DIR) + "/cases/minimal_drum.xml";
  spec.sets = {"time.end=0.4", "output.fields_every=0"};
  spec.axes = {{"dem.restitution", {"0.3", "0.6"}}, {"dem.friction", {"0.2", "0.5"}}};
  spec.run.out_dir = out;
  spec.run.backend = "omp";
  spec.run.threads = 1;
  return spec;
}

// --ensemble: the grid's runs in one DEM solver give each run's row as alone (over a window
// short enough that the order of the solver's sums has not grown past 1e-6, measured in
// tests/support/ensemble_cases.hpp), and each run's folder gets its summary and series.
TEST(Sweep, AnEnsembleGivesTheRowsOfSeparateRuns) {
  const auto tmp = std::filesystem::temp_directory_path();
  SweepSpec spec = smallSweep((tmp / "millsim_sweep_alone").string());
  spec.sets = {"time.end=0.12", "compaction.duration=0.05", "drum.start_time=0.05", "output.fields_every=0",
               "output.checkpoint_every=0"};
  const auto alone = runSweep(spec);
  spec.run.out_dir = (tmp / "millsim_sweep_ensemble").string();
  spec.ensemble = true;
  const auto together = runSweep(spec);
  ASSERT_EQ(together.size(), alone.size());
  for (std::size_t k = 0; k < alone.size(); ++k) {
    EXPECT_EQ(together[k].status, "ok") << together[k].error;
    EXPECT_EQ(together[k].values, alone[k].values);
    EXPECT_EQ(together[k].steps, alone[k].steps);
    ASSERT_GT(std::abs(alone[k].power_W), 1e-3) << k;
    EXPECT_NEAR(together[k].power_W, alone[k].power_W, 1e-6 * std::abs(alone[k].power_W)) << k;
    EXPECT_TRUE(std::filesystem::exists(std::filesystem::path(together[k].out_dir) / "summary.json"));
    EXPECT_TRUE(std::filesystem::exists(std::filesystem::path(together[k].out_dir) / "series.csv"));
  }
  EXPECT_NE(alone[0].power_W, alone[3].power_W);  // the settings reached the runs
  // A varied setting one solver cannot hold is bad input, before anything runs.
  spec.axes = {{"dem.youngs_modulus", {"1e8", "2e8"}}};
  EXPECT_THROW(sweepSettings(spec), core::InputError);
}

// A run whose solver step diverges stops a shared solver, and with it every run of the
// ensemble: the sweep then runs them alone, so the stable run keeps its "ok" row. (dt 5e-4 s is
// 25x the minimal drum's contact-time step: its balls are thrown to 1e19 m within 200 steps.)
TEST(Sweep, AnEnsembleThatDivergesRunsItsRunsAlone) {
  const auto tmp = std::filesystem::temp_directory_path();
  SweepSpec spec = smallSweep((tmp / "millsim_sweep_ensemble_diverges").string());
  spec.sets = {"time.end=0.6", "time.dt=fixed", "output.fields_every=0", "output.checkpoint_every=0"};
  spec.axes = {{"time.dt_fixed", {"2e-5", "5e-4"}}};
  spec.ensemble = true;
  const auto rows = runSweep(spec);
  ASSERT_EQ(rows.size(), 2u);
  EXPECT_EQ(rows[0].status, "ok") << rows[0].error;
  EXPECT_EQ(rows[1].status, "failed");
  EXPECT_NE(rows[1].error.find("diverged"), std::string::npos) << rows[1].error;
  EXPECT_GT(rows[0].steps, 20000);  // ran to its end: 0.6 s at 2e-5 s
}

TEST(Sweep, GridInOrderWithTheFirstAxisSlowest) {
  const auto sets = sweepSettings(smallSweep("unused"));
  ASSERT_EQ(sets.size(), 4u);
  EXPECT_EQ(sets[1].back(), "dem.friction=0.5");
  EXPECT_EQ(sets[1][sets[1].size() - 2], "dem.restitution=0.3");
  EXPECT_EQ(sets[2][sets[2].size() - 2], "dem.restitution=0.6");
  EXPECT_EQ(sets[0][0], "time.end=0.4");  // the common settings first
}

TEST(Sweep, RanksGiveTheResultsOfOneProcess) {
  const auto tmp = std::filesystem::temp_directory_path();
  const auto serial = runSweep(smallSweep((tmp / "millsim_sweep_serial").string()));
  ASSERT_EQ(serial.size(), 4u);
  std::vector<std::vector<SweepRow>> per_rank(3);
  millsim::testing::runOnRanks(3, [&](const core::RankGroup& ranks) {
    per_rank[ranks.rank()] = runSweep(smallSweep((tmp / "millsim_sweep_ranks").string()), &ranks);
  });
  for (const auto& rows : per_rank) {
    ASSERT_EQ(rows.size(), 4u);
    for (std::size_t k = 0; k < 4; ++k) {
      EXPECT_EQ(rows[k].index, static_cast<int>(k));
      EXPECT_EQ(rows[k].values, serial[k].values);
      EXPECT_EQ(rows[k].status, "ok");
      // A deterministic simulation: bit-identical wherever it ran (JSON round-trips doubles).
      EXPECT_EQ(rows[k].power_W, serial[k].power_W) << k;
      EXPECT_EQ(rows[k].steps, serial[k].steps) << k;
    }
  }
  // The settings reached the runs: restitution changes the power (0.3 -> 0.6 at mu = 0.2).
  EXPECT_NE(serial[0].power_W, serial[2].power_W);
  EXPECT_TRUE(std::filesystem::exists(tmp / "millsim_sweep_ranks" / "run_003" / "summary.json"));
}

TEST(Sweep, AnUnstableRunIsAFailedRowAndTheOthersGoOn) {
  SweepSpec spec = smallSweep((std::filesystem::temp_directory_path() / "millsim_sweep_fail").string());
  spec.sets.push_back("time.dt=fixed");
  spec.axes = {{"time.dt_fixed", {"2e-3", "1e-5"}}};  // 2 ms: far past the contact time, balls escape
  const auto rows = runSweep(spec);
  ASSERT_EQ(rows.size(), 2u);
  EXPECT_EQ(rows[0].status, "failed");
  EXPECT_NE(rows[0].error.find("escaped"), std::string::npos) << rows[0].error;
  EXPECT_EQ(rows[1].status, "ok");
  EXPECT_NEAR(rows[1].simulated_s, 0.4, 1e-6);
  const std::string csv = spec.run.out_dir + "/sweep.csv";
  writeSweepCsv(rows, spec.axes, csv);
  std::ifstream in(csv);
  std::string header, first;
  std::getline(in, header);
  std::getline(in, first);
  EXPECT_EQ(header.rfind("index,time.dt_fixed,status,angle_of_repose_deg", 0), 0u);
  EXPECT_EQ(first.rfind("0,2e-3,failed,", 0), 0u) << first;
}

// A combination the case file accepts but the simulation cannot set up (a ball larger than the
// drum's free space) is a failed row naming the cause; the other run goes on.
TEST(Sweep, ARunThatCannotStartIsAFailedRow) {
  SweepSpec spec = smallSweep((std::filesystem::temp_directory_path() / "millsim_sweep_nostart").string());
  spec.sets.push_back("time.end=0.05");
  spec.axes = {{"charge.top_size", {"0.09", "0.01"}}, {"charge.min_size", {"0.01"}}};
  const auto rows = runSweep(spec);
  ASSERT_EQ(rows.size(), 2u);
  EXPECT_EQ(rows[0].status, "failed");
  EXPECT_NE(rows[0].error.find("does not fit"), std::string::npos) << rows[0].error;
  EXPECT_EQ(rows[1].status, "ok");
}

TEST(Sweep, BadInputFailsBeforeAnythingRuns) {
  SweepSpec spec = smallSweep("unused");
  spec.axes = {{"dem.restitution", {"0.3", "-1"}}};
  EXPECT_THROW(sweepSettings(spec), core::InputError);
  spec.axes = {{"dem.no_such", {"1"}}};
  EXPECT_THROW(runSweep(spec), core::InputError);
  spec.axes = {{"dem.friction", {"0.2"}}, {"dem.friction", {"0.3"}}};
  EXPECT_THROW(sweepSettings(spec), core::InputError);
}

}  // namespace
}  // namespace millsim::sim
