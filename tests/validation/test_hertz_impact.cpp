// Hertz impacts against analytic results (shared/reference/contact.md): restitution of the
// exact damping mapping, contact duration, DualSPHysics's damping table, rolling, Coulomb limit
// and energy conservation. Each scene runs through the real DEM engine.
#include <gtest/gtest.h>

#include <cmath>

#include "support/dem_fixture.hpp"

using namespace millsim;
using millsim::testing::Ball;
using millsim::testing::DemScene;

namespace {

constexpr double kR = 0.0075;  // 15 mm ball, the paper's smallest
constexpr double kV = 1.0;     // m/s impact speed

struct ImpactResult {
  double restitution;
  double contact_time;
};

double contactTime(const DemScene& sc, bool wall) {
  const double m = millsim::testing::ballMass(kR, sc.density);
  const double e_star = dem::effectiveModulus(sc.young, sc.poisson);
  return wall ? dem::hertzContactTime(m, kR, e_star, kV) : dem::hertzContactTime(0.5 * m, 0.5 * kR, e_star, kV);
}

// Normal impact, ball on the flat wall (z = 0) or two equal balls head on; dt = t_c / 400.
ImpactResult normalImpact(const DemScene& sc, bool wall) {
  std::vector<Ball> balls;
  const double gap = 0.2 * kR;
  if (wall) {
    balls.push_back({0, 0, kR + gap, 0, 0, -kV, kR});
  } else {
    balls.push_back({0, 0, 0.5, 0, 0, 0.5 * kV, kR});
    balls.push_back({0, 0, 0.5 + 2 * kR + gap, 0, 0, -0.5 * kV, kR});
  }
  auto engine = millsim::testing::makeEngine(sc, balls);
  const double tc = contactTime(sc, wall);
  const double dt = tc / 400;
  double t = 0, t_in = -1, t_out = -1;
  auto overlapping = [&](const dem::DemHostState& s) {
    if (wall) return s.pos[2] < kR;
    return s.pos[5] - s.pos[2] < 2 * kR;
  };
  bool was_in = false;
  for (int k = 0; k < 100000; ++k) {
    engine->step(millsim::testing::stillDrum(), dt);
    t += dt;
    const auto s = millsim::testing::state(*engine);
    const bool in = overlapping(s);
    if (in && !was_in) t_in = t;
    if (!in && was_in) {
      t_out = t;
      const double v_after = wall ? s.vel[2] : (s.vel[5] - s.vel[2]);
      return {v_after / kV, t_out - t_in};
    }
    was_in = in;
  }
  ADD_FAILURE() << "impact did not end";
  return {0, 0};
}

}  // namespace

// Exact damping (Antypov & Elliott 2011) must give the requested e. Tolerance 1% (the issue's
// requirement); dt = t_c/400 keeps the velocity-Verlet error well below it.
class ExactRestitution : public ::testing::TestWithParam<double> {};

TEST_P(ExactRestitution, BallWallAndBallBall) {
  DemScene sc;
  sc.restitution = GetParam();
  for (bool wall : {true, false}) {
    const ImpactResult r = normalImpact(sc, wall);
    EXPECT_NEAR(r.restitution, sc.restitution, 0.01 * sc.restitution) << (wall ? "ball-wall" : "ball-ball");
  }
}

INSTANTIATE_TEST_SUITE_P(Hertz, ExactRestitution, ::testing::Values(0.1, 0.39, 0.9));

// Elastic Hertz contact time t_c = 2.868 (m*^2/(R* E*^2 v))^(1/5); 2% (issue). The measured time
// is quantised by dt = t_c/400 (0.25%).
TEST(HertzContact, DurationMatchesAnalytic) {
  DemScene sc;
  sc.restitution = 1.0;
  for (bool wall : {true, false}) {
    const ImpactResult r = normalImpact(sc, wall);
    const double tc = contactTime(sc, wall);
    EXPECT_NEAR(r.contact_time, tc, 0.02 * tc) << (wall ? "ball-wall" : "ball-ball");
    EXPECT_NEAR(r.restitution, 1.0, 1e-3);
  }
}

// DualSPHysics's own damping formula gives a lower real restitution; reference/contact.md lists
// what numerical integration of its law gives. The table has 3 digits: tolerance 0.005.
TEST(HertzContact, DualSphysicsDampingTable) {
  struct Row {
    double input, wall, ball_ball;
  };
  // wall = ball-wall with DualSPHysics's m* = m/2 (0.377 for 0.39); the others are ball-ball.
  const Row rows[] = {{0.39, 0.377, 0.234}, {0.5, -1, 0.339}, {0.7, -1, 0.569}, {0.9, -1, 0.846}};
  for (const Row& row : rows) {
    DemScene sc;
    sc.damping = dem::DampingModel::kDualSphysics;
    sc.restitution = row.input;
    EXPECT_NEAR(normalImpact(sc, false).restitution, row.ball_ball, 0.005) << "input " << row.input;
    if (row.wall > 0) {
      EXPECT_NEAR(normalImpact(sc, true).restitution, row.wall, 0.005) << "input " << row.input;
    }
  }
}

// A ball thrown flat onto a floor without spin slides, then rolls: v_final = 5/7 v0 and
// w = v/r, reached after t = 2 v0 / (7 mu g) (solid sphere, Coulomb friction). 1% on v; the
// tangential spring adds a small oscillation around the rolling state.
TEST(HertzContact, SlidingBallReachesRollingState) {
  DemScene sc;
  sc.restitution = 0.5;
  sc.friction = 0.3;
  sc.gravity = {0, 0, -9.81};
  const double v0 = 1.0;
  const double m = millsim::testing::ballMass(kR, sc.density);
  const double z0 = kR - std::pow(m * 9.81 / (4.0 / 3.0 * dem::effectiveModulus(sc.young, sc.poisson) * std::sqrt(kR)), 2.0 / 3.0);
  auto engine = millsim::testing::makeEngine(sc, {{0, 0, z0, v0, 0, 0, kR}});
  const double dt = contactTime(sc, true) / 100;
  const double t_roll = 2 * v0 / (7 * sc.friction * 9.81);
  double t = 0;
  while (t < 2.5 * t_roll) {
    engine->step(millsim::testing::stillDrum(), dt);
    t += dt;
  }
  const auto s = millsim::testing::state(*engine);
  EXPECT_NEAR(s.vel[0], 5.0 / 7.0 * v0, 0.01 * v0);
  // Rolling without slip: v_x = w_y r for rotation about +y when moving along +x on a floor below.
  EXPECT_NEAR(s.omega[1] * kR, s.vel[0], 0.01 * v0);
}

// Oblique impact in gross sliding: the tangential impulse is mu times the normal impulse,
// dv_t = mu (1 + e) v_n, and the spin gained is w = 5 dv_t / (2 r). Tolerance 2%: the spring
// phase at the start and end of the contact is short against the sliding phase. Steel stiffness
// (E = 2e11) so the lever arm r - delta of the model is r within 0.2%, as rigid-body theory assumes.
// e = 0.9: the unclipped d^1/4 damping leaves a short tensile tail at the end of the contact
// during which friction is zero; at e = 0.5 it lowers the normal impulse by ~3%, at 0.9 by 0.1%.
TEST(HertzContact, ObliqueImpactFollowsCoulombLimit) {
  DemScene sc;
  sc.young = 2e11;
  sc.restitution = 0.9;
  sc.friction = 0.1;
  const double vn = 1.0, vt = 2.0;
  auto engine = millsim::testing::makeEngine(sc, {{0, 0, kR * 1.2, vt, 0, -vn, kR}});
  const double dt = contactTime(sc, true) / 400;
  for (int k = 0; k < 400000; ++k) {
    engine->step(millsim::testing::stillDrum(), dt);
    const auto s = millsim::testing::state(*engine);
    if (s.pos[2] > 1.2 * kR && s.vel[2] > 0) {
      const double dvn = s.vel[2] + vn;
      const double dvt = vt - s.vel[0];
      EXPECT_NEAR(dvt, sc.friction * dvn, 0.02 * sc.friction * dvn);
      EXPECT_NEAR(std::abs(s.omega[1]) * kR, 2.5 * dvt, 0.02 * 2.5 * dvt);
      return;
    }
  }
  FAIL() << "ball did not leave the wall";
}

// With e = 1 and no friction, kinetic + potential + elastic energy is conserved: a ball bouncing
// on the floor and hitting a second ball, 0.5 s. 1e-4 relative (issue); velocity Verlet's
// energy error inside a contact scales with (dt/t_c)^2: dt = t_c/200 gives ~4e-5.
TEST(HertzContact, EnergyConservedWithoutDissipation) {
  DemScene sc;
  sc.restitution = 1.0;
  sc.friction = 0.0;
  sc.gravity = {0, 0, -9.81};
  auto engine = millsim::testing::makeEngine(sc, {{0, 0, 0.05, 0.02, 0, 0, kR}, {0.004, 0.001, 0.09, 0, 0, 0, kR}});
  const double dt = contactTime(sc, true) / 200;
  auto energy = [&]() {
    const dem::DemSums s = engine->sums();
    return s.kinetic + s.potential + s.elastic;
  };
  const double e0 = energy();
  double worst = 0;
  for (double t = 0; t < 0.5; t += dt) {
    engine->step(millsim::testing::stillDrum(), dt);
    worst = std::max(worst, std::abs(energy() - e0));
  }
  EXPECT_LT(worst / e0, 1e-4);
}
