// The DEM contact pass on several OpenMP threads (PartnerScatter<Omp>: each thread owns a
// contiguous chunk of particles, reactions on partners past the chunk's end go through per-
// thread rows) must give the physics of the one-thread pass (DirectSink). Only the order of
// floating-point additions differs, so after a few hundred steps of a dense, colliding bed the
// states agree to round-off growth (bound 1e-9), while a lost or doubled partner reaction
// at a chunk boundary changes the velocities at order one (rows not reduced: 3.1).
#include <gtest/gtest.h>
#include <omp.h>

#include <algorithm>
#include <cmath>
#include <random>
#include <vector>

#include "support/dem_fixture.hpp"

namespace millsim {
namespace {

// ~4 000 balls of 4-5 mm dropped as a jittered lattice onto the bottom of a turning drum with
// lifters: more than the OpenMP threshold (2 048), and after 400 steps of 5 us many lasting
// contacts, some across every chunk boundary.
dem::DemHostState bed() {
  std::vector<testing::Ball> balls;
  std::mt19937 rng(3);
  std::uniform_real_distribution<double> radius(0.004, 0.005), jitter(-5e-4, 5e-4), v(-0.2, 0.2);
  for (int iz = 0; iz < 8; ++iz)
    for (int iy = 0; iy < 22; ++iy)
      for (int ix = 0; ix < 23; ++ix)
        balls.push_back({-0.105 + 0.0095 * ix + jitter(rng), -0.105 + 0.0095 * iy + jitter(rng),
                         0.006 + 0.0095 * iz + jitter(rng), v(rng), v(rng) - 1.0, v(rng), radius(rng)});
  return testing::hostState(balls, 7800.0);
}

dem::DrumState drum(double t) {
  dem::DrumState w;
  w.radius = 0.16;
  w.z_back = 0.085;
  w.omega = 2.0;
  w.phi = w.omega * t;
  w.lifter_count = 8;
  w.lifter_height = 0.01;
  w.lifter_width = 0.01;
  return w;
}

dem::DemHostState run(int threads) {
  omp_set_num_threads(threads);
  auto e = dem::makeDemEngineOmp(testing::drumSetup(0.4, 0.5, 0.004, 0.005, {-0.17, -0.17, -0.01}, {0.17, 0.17, 0.095}),
                                 false);
  e->setState(bed());
  const double dt = 5e-6;
  e->initialize(drum(0));
  for (int k = 1; k <= 400; ++k) e->step(drum(k * dt), dt);
  omp_set_num_threads(1);
  return testing::state(*e);
}

TEST(DemThreads, TwoThreadsGiveTheOneThreadPhysics) {
  const dem::DemHostState one = run(1), two = run(2);
  ASSERT_EQ(one.size(), two.size());
  ASSERT_GT(one.size(), 2048u);  // the multi-thread path only runs above the OpenMP threshold
  double diff = 0, scale = 0, dissipated1 = 0, dissipated2 = 0;
  for (std::size_t k = 0; k < one.vel.size(); ++k) {
    diff = std::max(diff, std::abs(one.vel[k] - two.vel[k]));
    scale = std::max(scale, std::abs(one.vel[k]));
  }
  for (std::size_t i = 0; i < one.size(); ++i) {
    dissipated1 += one.dissipated[i];
    dissipated2 += two.dissipated[i];
  }
  ASSERT_GT(dissipated1, 0.0);  // the balls did collide
  EXPECT_LT(diff / scale, 1e-9);
  EXPECT_NEAR(dissipated2, dissipated1, 1e-9 * dissipated1);
}

}  // namespace
}  // namespace millsim
