// The wet mill (issue 5 Done-when 5, the part a short GPU lease can check) on CUDA against
// OpenMP: cases/wet_drum_small.xml's charge packed once, the slurry poured into it on each
// backend, then coupled steps (SPH step, DEM sub-steps, the fluid's loads on the balls and the
// balls' shells placed for the fluid) on the device. Both in double.
//
// Tolerances: two correct runs differ by their arithmetic only (summation order, FMA, the
// DEM's atomics), and in these first steps of the pour that difference stays at rounding level.
// Measured here (2026-12-03, OpenMP, double) from the same packed charge: one against two
// threads, 200 coupled steps: balls 4.2e-17 m apart, fluid 8.3e-17 m (max), kinetic energies
// 7e-15; ball positions scaled by (1 + 1e-15) before the pour, after 200 steps: balls 5.8e-16 m,
// fluid 9.3e-16 m (max) and 2.0e-16 m (rms), energies 2.2e-14; after 400 steps 1.0e-15 m,
// 2.4e-15 m, 1.8e-14: no exponential growth yet. The bounds leave six orders for the GPU's
// rounding (1e-9 m, as the DEM drum test) and stay far under a coupling error: a ball whose
// fluid force (its buoyancy, ~0.06 N on a 33 g ball) were lost would be ~0.1 mm off after these
// 200 steps (11 ms). The largest fluid difference gets 1e-6 m: shifting's free-surface test is a
// threshold, which one particle on its edge may take differently on each backend.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstdio>

#include "support/cuda_skip.hpp"
#include "support/ensemble_cases.hpp"
#include "support/wet_pour.hpp"

using namespace millsim;

namespace {
constexpr double kBallBound = 1e-9, kFluidRmsBound = 1e-9, kFluidMaxBound = 1e-6, kEnergyBound = 1e-8;
}  // namespace

TEST(WetMillCudaVsOmp, PourAndCoupledStepsAgree) {
  MILLSIM_SKIP_WITHOUT_CUDA();
  const millsim::testing::PackedCharge packed = millsim::testing::packCharge(
      millsim::testing::sourceCase("wet_drum_small"), {"output.fields_every=0", "output.checkpoint_every=0"});
  constexpr int kSteps = 200;
  const millsim::testing::PourResult omp = millsim::testing::pourAndStep(packed, "omp", kSteps);
  const millsim::testing::PourResult cuda = millsim::testing::pourAndStep(packed, "cuda", kSteps);
  ASSERT_EQ(cuda.ball_pos.size(), omp.ball_pos.size());
  ASSERT_EQ(cuda.fluid_pos.size(), omp.fluid_pos.size()) << "fluid particles lost on one backend";
  double ball = 0, fluid_max = 0, fluid_sq = 0;
  for (std::size_t i = 0; i < omp.ball_pos.size(); ++i)
    ball = std::max(ball, std::abs(cuda.ball_pos[i] - omp.ball_pos[i]));
  for (std::size_t i = 0; i < omp.fluid_pos.size(); ++i) {
    const double d = std::abs(cuda.fluid_pos[i] - omp.fluid_pos[i]);
    fluid_max = std::max(fluid_max, d);
    fluid_sq += d * d;
  }
  const double fluid_rms = std::sqrt(fluid_sq / double(omp.fluid_pos.size() / 3));
  const double ke_fluid = std::abs(cuda.slurry_kinetic / omp.slurry_kinetic - 1);
  const double ke_balls = std::abs(cuda.ball_kinetic / omp.ball_kinetic - 1);
  std::printf(
      "after %d coupled steps: balls %.3g m apart (max), fluid %.3g m (max) %.3g m (rms); kinetic energy "
      "slurry %.3g, balls %.3g relative; SPH steps %lld / %lld\n",
      kSteps, ball, fluid_max, fluid_rms, ke_fluid, ke_balls, cuda.sph_steps, omp.sph_steps);
  EXPECT_EQ(cuda.sph_steps, omp.sph_steps);
  EXPECT_LT(ball, kBallBound);
  EXPECT_LT(fluid_rms, kFluidRmsBound);
  EXPECT_LT(fluid_max, kFluidMaxBound);
  EXPECT_LT(ke_fluid, kEnergyBound);
  EXPECT_LT(ke_balls, kEnergyBound);
}
