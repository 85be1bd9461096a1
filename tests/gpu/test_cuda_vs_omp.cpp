// The CUDA backend runs the same functors as OpenMP: a settling pile of balls in a rotating drum
// must give the same state on both. Skips with a message where no GPU (or no CUDA build) exists.
#include <gtest/gtest.h>

#include <cmath>
#include <random>

#include "dem/contact/damping.hpp"
#include "dem/dem_engine.hpp"
#include "dem/dem_kernels.hpp"
#include "millsim/backend/info.hpp"

using namespace millsim;

namespace {

[[maybe_unused]] dem::DemHostState pile(int n) {
  dem::DemHostState s;
  std::mt19937 rng(3);
  std::uniform_real_distribution<double> u(-1.0, 1.0);
  for (int i = 0; i < n; ++i) {
    const double r = 0.005 + 0.001 * (i % 3);
    s.pos.insert(s.pos.end(), {0.03 * u(rng), 0.03 * u(rng), 0.01 + 0.02 * (i % 5) + 0.001 * u(rng)});
    s.vel.insert(s.vel.end(), {0.0, 0.0, 0.0});
    s.omega.insert(s.omega.end(), {0.0, 0.0, 0.0});
    s.radius.push_back(r);
    const double m = 7800 * 4.0 / 3.0 * M_PI * r * r * r;
    s.mass.push_back(m);
    s.inertia.push_back(0.4 * m * r * r);
  }
  return s;
}

}  // namespace

TEST(CudaVsOmp, SameStateAfterSettlingInRotatingDrum) {
#if !defined(MILLSIM_HAVE_CUDA)
  GTEST_SKIP() << "CUDA backend not built (MILLSIM_CUDA=OFF or no nvcc): nothing to compare";
#else
  if (backend::cudaDevices() == 0) GTEST_SKIP() << "no CUDA device on this machine: GPU comparison skipped";
  dem::DemSetup setup;
  setup.k_coef = 4.0 / 3.0 * dem::effectiveModulus(1e8, 0.29);
  setup.alpha = dem::dampingAlpha(dem::DampingModel::kExact, 0.39);
  setup.friction = 0.496;
  setup.gravity = {0, -9.81, 0};
  setup.skin = 0.001;
  setup.max_radius = 0.007;
  setup.domain_lo = {-0.06, -0.06, -0.01};
  setup.domain_hi = {0.06, 0.06, 0.12};
  dem::DrumState drum;
  drum.radius = 0.05;
  drum.z_back = 0.11;
  drum.omega = -3.0;
  drum.lifter_count = 4;
  drum.lifter_height = 0.004;
  drum.lifter_width = 0.004;
  const auto start = pile(60);
  auto omp = dem::makeDemEngineOmp(setup, false);
  auto cuda = dem::makeDemEngineCuda(setup, false);
  for (auto* e : {omp.get(), cuda.get()}) {
    e->setState(start);
    e->initialize(drum);
  }
  const double dt = 2e-6;
  for (int k = 0; k < 3000; ++k) {
    drum.phi += drum.omega * dt;
    omp->step(drum, dt);
    cuda->step(drum, dt);
  }
  dem::DemHostState a, b;
  omp->getState(a);
  cuda->getState(b);
  // 3000 steps of settling with many contacts: the two differ only by rounding (FMA contraction
  // on the GPU), amplified by the contacts; 1e-9 m is 1e-7 of a ball radius.
  double worst = 0;
  for (std::size_t i = 0; i < a.pos.size(); ++i) worst = std::max(worst, std::abs(a.pos[i] - b.pos[i]));
  EXPECT_LT(worst, 1e-9);
  EXPECT_NEAR(omp->sums().dissipated, cuda->sums().dissipated, 1e-6 * omp->sums().dissipated + 1e-15);
#endif
}
