// Initially overlapping dense packing (the compaction case): 64 balls on a lattice whose spacing
// is 10% less than a diameter, in a still drum under gravity. The stored elastic energy must be
// released without blowing up: energy can only come from the initial elastic energy and the fall,
// so at every step KE <= E_elastic(0) + (PE(0) - PE(t)) (damping only removes energy; 1e-6
// relative slack for rounding), and where the balls end is bounded by energy too (below).
#include <gtest/gtest.h>

#include <cmath>

#include "support/dem_fixture.hpp"

using millsim::testing::Ball;
using millsim::testing::DemScene;

TEST(OverlapPacking, ReleasesElasticEnergyWithoutBlowingUp) {
  DemScene sc;
  sc.restitution = 0.39;
  sc.friction = 0.5;
  sc.gravity = {0, 0, -9.81};
  const double r = 0.005, spacing = 0.9 * 2 * r;
  std::vector<Ball> balls;
  for (int i = 0; i < 4; ++i)
    for (int j = 0; j < 4; ++j)
      for (int k = 0; k < 4; ++k) balls.push_back({i * spacing - 0.015, j * spacing - 0.015, r + k * spacing, 0, 0, 0, r});
  auto engine = millsim::testing::makeEngine(sc, balls);
  const auto s0 = engine->sums();
  ASSERT_GT(s0.elastic, 0.0);
  const double m = millsim::testing::ballMass(r, sc.density);
  const double e_star = millsim::dem::effectiveModulus(sc.young, sc.poisson);
  // Overlaps of 1 mm: much faster than 2 m/s impacts, so dt from the overlap's own stiffness.
  const double dt = millsim::dem::hertzContactTime(0.5 * m, 0.5 * r, e_star, 5.0) / 50;
  for (int step = 0; step < 20000; ++step) {
    engine->step(millsim::testing::stillDrum(), dt);
    const auto s = engine->sums();
    ASSERT_TRUE(std::isfinite(s.kinetic));
    ASSERT_LE(s.kinetic, (s0.elastic + s0.potential - s.potential) * (1 + 1e-6)) << "step " << step;
  }
  // Where the balls are after 20 000 steps (~20 ms: the released balls are still in flight),
  // from energy alone: none can rise above the lattice's top by more than the whole stored
  // elastic energy could lift it (E_el(0) / (m g)), none can sink into the end plate deeper than
  // the Hertz overlap under the weight of all 64 balls, (3 * 64 m g / (4 E* sqrt(r)))^(2/3), and
  // none can travel farther than the fastest any ball could move (all the energy available,
  // E_el(0) plus the lattice's fall, in that one ball) for the time run.
  const auto st = millsim::testing::state(*engine);
  const double g = 9.81, z_top = r + 3 * spacing;
  const double rise = s0.elastic / (m * g);
  const double sink = std::pow(3 * 64 * m * g / (4 * e_star * std::sqrt(r)), 2.0 / 3.0);
  const double v_max = std::sqrt(2 * (s0.elastic + 64 * m * g * z_top) / m), reach = v_max * 20000 * dt;
  ASSERT_EQ(st.size(), balls.size());
  for (std::size_t i = 0; i < st.size(); ++i) {
    EXPECT_LE(st.pos[3 * i + 2], z_top + rise) << "ball " << i;
    EXPECT_GE(st.pos[3 * i + 2], r - sink) << "ball " << i;
  }
  // The state comes back in the input order (DemHostState keeps each ball's number).
  for (std::size_t i = 0; i < st.size(); ++i)
    EXPECT_LE(std::hypot(st.pos[3 * i] - balls[i].x, st.pos[3 * i + 1] - balls[i].y), reach) << "ball " << i;
}
