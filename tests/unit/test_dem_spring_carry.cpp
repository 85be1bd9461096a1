// The tangential springs must survive neighbour-list rebuilds exactly: at each rebuild the
// loaded springs are set aside in a compact table, the particles renumbered, the list rebuilt
// over the old one and every new slot's spring looked up (DemSolver::rebuildNeighbours). The
// rebuilds' timing depends on the skin only, so the same dense bed run with two skins (a
// rebuild every few steps against one every few tens) must give the same physics up to the
// order of the floating-point sums (bound 1e-9 after 400 steps, as for the thread test). A
// spring dropped or given to the wrong pair at a rebuild restarts a sticking contact's
// tangential force and changes velocities at order one (checked by dropping every spring at
// the set-aside: relative difference 0.38).
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>

#include "support/dem_fixture.hpp"

namespace millsim {
namespace {

struct SkinRun {
  dem::DemHostState state;
  std::int64_t rebuilds = 0;
};

SkinRun runWithSkin(double skin_over_rmin) {
  dem::DemSetup setup = testing::drumSetup(0.4, 0.5, 0.004, 0.005, {-0.17, -0.17, -0.01}, {0.17, 0.17, 0.095});
  setup.skin = skin_over_rmin * 0.004;
  auto e = dem::makeDemEngineOmp(setup, false);
  e->setState(testing::denseDrumBed());
  const double dt = 5e-6;
  e->initialize(testing::turningDrum(0));
  for (int k = 1; k <= 400; ++k) e->step(testing::turningDrum(k * dt), dt);
  return {testing::state(*e), e->neighbourRebuilds()};
}

TEST(DemSpringCarry, RebuildsDoNotChangeThePhysics) {
  const SkinRun often = runWithSkin(0.05), seldom = runWithSkin(0.5);
  ASSERT_GT(often.rebuilds, 3 * seldom.rebuilds);  // the two runs carry springs at different times
  ASSERT_GT(seldom.rebuilds, 1);
  double diff = 0, scale = 0, dissipated1 = 0, dissipated2 = 0;
  for (std::size_t k = 0; k < often.state.vel.size(); ++k) {
    diff = std::max(diff, std::abs(often.state.vel[k] - seldom.state.vel[k]));
    scale = std::max(scale, std::abs(often.state.vel[k]));
  }
  for (std::size_t i = 0; i < often.state.size(); ++i) {
    dissipated1 += often.state.dissipated[i];
    dissipated2 += seldom.state.dissipated[i];
  }
  ASSERT_GT(dissipated1, 0.0);  // the balls did collide
  EXPECT_LT(diff / scale, 1e-9);
  EXPECT_NEAR(dissipated2, dissipated1, 1e-9 * dissipated1);
}

}  // namespace
}  // namespace millsim
