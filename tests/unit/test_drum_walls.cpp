// Analytic drum walls: overlaps and normals of the cylinder, the end plates and the box lifters
// against hand geometry. Drum radius 0.1 m, 4 lifters of 10 mm x 6 mm; the drum is turned so
// lifter 0 stands at the bottom (direction -y), pointing up into the drum.
#include <gtest/gtest.h>

#include <cmath>
#include <vector>

#include "dem/walls/drum_walls.hpp"

using namespace millsim;
using core::Vec3;

namespace {

dem::DrumWalls<double> drum() {
  dem::DrumWalls<double> d{};
  d.radius = 0.1;
  d.z_back = 0.05;
  d.omega = -2.0;
  d.lifter_count = 4;
  d.lifter_height = 0.01;
  d.lifter_width = 0.006;
  for (int k = 0; k < 4; ++k) {
    const double a = -M_PI / 2 + k * M_PI / 2;  // lifter 0 at the bottom
    d.lifter_cos[k] = std::cos(a);
    d.lifter_sin[k] = std::sin(a);
  }
  return d;
}

std::vector<dem::WallContact<double>> contacts(Vec3<double> p, double r) {
  std::vector<dem::WallContact<double>> c;
  drum().forEachContact(p, r, [&](const dem::WallContact<double>& w) { c.push_back(w); });
  return c;
}

}  // namespace

TEST(DrumWalls, BallOnTopOfBottomLifter) {
  // Lifter top face at y = -(0.1 - 0.01) = -0.09; ball of r = 5 mm centred 4 mm above it.
  const auto c = contacts({0.0, -0.086, 0.02}, 0.005);
  ASSERT_EQ(c.size(), 1u);
  EXPECT_EQ(c[0].wall, 3);
  EXPECT_NEAR(c[0].delta, 0.001, 1e-12);
  EXPECT_NEAR(c[0].n.y, 1.0, 1e-12);
  // The contact point turns with the drum: v = omega z x p, at (0, -0.09): v_x = -omega * y.
  EXPECT_NEAR(c[0].velocity.x, 2.0 * -0.09, 1e-12);
}

TEST(DrumWalls, BallAgainstLifterSideAndCylinder) {
  // Ball resting in the corner right of lifter 0: side face at x = +0.003, cylinder below.
  const double r = 0.004;
  const double x = 0.003 + r - 0.0005;
  const double y = -std::sqrt(std::pow(0.1 - r + 0.0002, 2) - x * x);
  const auto c = contacts({x, y, 0.02}, r);
  ASSERT_EQ(c.size(), 2u);
  EXPECT_EQ(c[0].wall, 0);
  EXPECT_NEAR(c[0].delta, 0.0002, 1e-12);
  EXPECT_EQ(c[1].wall, 3);
  EXPECT_NEAR(c[1].delta, 0.0005, 1e-12);
  EXPECT_NEAR(c[1].n.x, 1.0, 1e-12);
}

TEST(DrumWalls, EndPlatesAndFreeBall) {
  const auto front = contacts({0.0, 0.0, 0.003}, 0.005);
  ASSERT_EQ(front.size(), 1u);
  EXPECT_EQ(front[0].wall, 1);
  EXPECT_NEAR(front[0].delta, 0.002, 1e-12);
  EXPECT_NEAR(front[0].n.z, 1.0, 1e-12);
  const auto back = contacts({0.0, 0.0, 0.047}, 0.005);
  ASSERT_EQ(back.size(), 1u);
  EXPECT_EQ(back[0].wall, 2);
  EXPECT_NEAR(back[0].n.z, -1.0, 1e-12);
  EXPECT_TRUE(contacts({0.02, 0.01, 0.025}, 0.005).empty());
  // Near the wall between two lifters (45 deg): cylinder only.
  const double s = (0.1 - 0.004) / std::sqrt(2.0);
  const auto between = contacts({s, -s, 0.025}, 0.005);
  ASSERT_EQ(between.size(), 1u);
  EXPECT_EQ(between[0].wall, 0);
}
