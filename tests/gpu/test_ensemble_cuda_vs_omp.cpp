// An ensemble of drums (several cases in one DEM solver, issue 10) on CUDA against OpenMP: the
// three small drums of tests/validation/test_drum_ensemble.cpp (different drums, charges, ball
// sizes, restitution and friction) over 0.05 s of compaction and 0.07 s of rotation, double.
// Both backends run the same functors; only the order of the sums differs (atomics on the GPU),
// which two orders of one ensemble on the CPU showed to move the energies by 5e-12 (t = 0.1 s) to
// 4e-8 (t = 0.15 s) of the work put in, so 1e-6 of the work separates order from error.
// Skips with the reason where no GPU (or no CUDA build) exists.
#include <gtest/gtest.h>

#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <string>
#include <vector>

#include "millsim/backend/info.hpp"
#include "millsim/io/case_xml.hpp"
#include "millsim/sim/ensemble_run.hpp"
#include "support/cuda_skip.hpp"
#include "support/ensemble_cases.hpp"

using namespace millsim;

namespace {

// Each case by its own automatic step (the 12 mm drum rests while the others finish): the
// per-case step and skin tables and the resting cases run on the device too.
[[maybe_unused]] std::vector<sim::RunSummary> runOn(const std::string& backend) {
  const auto sets = millsim::testing::ensembleTestDrums();
  sim::EnsembleSpec spec;
  spec.run.backend = backend;
  spec.run.write_outputs = false;
  for (const auto& s : sets) {
    spec.scenes.push_back(io::loadCaseFile(millsim::testing::minimalDrumCase(), s));
    spec.out_dirs.push_back("");
  }
  return sim::runEnsemble(spec);
}

}  // namespace

TEST(CudaVsOmp, EnsembleOfThreeDrumsMatchesOpenMp) {
  MILLSIM_SKIP_WITHOUT_CUDA();
#if defined(MILLSIM_HAVE_CUDA)
  const std::vector<sim::RunSummary> omp = runOn("omp"), cuda = runOn("cuda");
  ASSERT_EQ(cuda.size(), omp.size());
  for (std::size_t k = 0; k < omp.size(); ++k) {
    const sim::RunSummary &a = omp[k], &g = cuda[k];
    SCOPED_TRACE("case " + std::to_string(k));
    EXPECT_EQ(g.backend, "cuda");
    EXPECT_EQ(g.steps, a.steps);
    const double scale = a.energy_work_in;
    ASSERT_GT(scale, 0.0);
    std::printf("ensemble case %zu: work %.6e J, kinetic omp %.9e cuda %.9e, dissipated omp %.9e cuda %.9e\n", k, scale,
                a.energy_kinetic, g.energy_kinetic, a.energy_dissipated, g.energy_dissipated);
    EXPECT_NEAR(g.energy_work_in, a.energy_work_in, 1e-6 * scale);
    EXPECT_NEAR(g.energy_dissipated, a.energy_dissipated, 1e-6 * scale);
    EXPECT_NEAR(g.energy_kinetic, a.energy_kinetic, 1e-6 * scale);
    EXPECT_NEAR(g.energy_potential, a.energy_potential, 1e-6 * scale);
    EXPECT_NEAR(g.power_W, a.power_W, 1e-6 * std::abs(a.power_W));
  }
#endif
}
