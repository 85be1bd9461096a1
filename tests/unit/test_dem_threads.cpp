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
#include <vector>

#include "support/dem_fixture.hpp"

namespace millsim {
namespace {

// The dense bed of dem_fixture.hpp (~4 000 balls, more than the OpenMP threshold; after 400
// steps many lasting contacts, some across every chunk boundary).
dem::DemHostState run(int threads) {
  omp_set_num_threads(threads);
  const dem::DemHostState s = testing::runDenseDrumBed(400);
  omp_set_num_threads(1);
  return s;
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
