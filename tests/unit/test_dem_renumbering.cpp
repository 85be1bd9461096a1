// The DEM solver renumbers its particles in cell order at every neighbour rebuild and keeps each
// pair's tangential spring with the pair's lower-numbered side. These tests check that the
// springs survive renumbering (with the sign flip when the owner changes), that a checkpoint
// round trip keeps them, and that the physics does not depend on the input numbering.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <random>
#include <vector>

#include "dem/reorder_kernels.hpp"
#include "support/dem_fixture.hpp"

namespace millsim {
namespace {

using core::Vec3;

TEST(SpringTransfer, FollowsRenumberingAndFlipsWhenOwnerChanges) {
  // Old numbering: pairs (0,2) with spring a and (1,2) with spring b, owned by the lower index.
  const std::vector<int> old_start{0, 1, 2, 2};
  const std::vector<int> old_partner{2, 2};
  const std::vector<Vec3<double>> old_xi{{1e-6, 2e-6, 3e-6}, {-4e-6, 5e-6, 0.0}};
  // New particle k is old particle old_of_new[k]: old 2 -> new 0, old 0 -> new 1, old 1 -> new 2.
  const std::vector<int> old_of_new{2, 0, 1};
  // New half list: (0,1) = old (2,0): owner changed, spring seen from the other side;
  // (0,2) = old (2,1): changed too; (1,2) = old (0,1): a pair that had no spring.
  const std::vector<int> start{0, 2, 3, 3};
  const std::vector<int> list{1, 2, 2};
  std::vector<Vec3<double>> xi(3, {9, 9, 9});
  const dem::SpringTable<double> old{old_start.data(), old_partner.data(), old_xi.data()};
  const dem::TransferPairSprings<double> transfer{old, old_of_new.data(), start.data(), list.data(), xi.data()};
  for (int i = 0; i < 3; ++i) transfer(i);
  EXPECT_EQ(xi[0].x, -1e-6);
  EXPECT_EQ(xi[0].y, -2e-6);
  EXPECT_EQ(xi[0].z, -3e-6);
  EXPECT_EQ(xi[1].x, 4e-6);
  EXPECT_EQ(xi[1].y, -5e-6);
  EXPECT_EQ(xi[2].x, 0.0);
  EXPECT_EQ(xi[2].z, 0.0);
}

// 60 balls of 4-6 mm in a 0.1 m x 20 mm drum turning at 15 rpm with 4 lifters: a bed with lasting
// frictional contacts between balls and with all wall kinds, and particles that keep changing
// cells (so the numbering keeps changing). Balls start on a tight lattice in the lower half.
std::vector<testing::Ball> tumblingCharge() {
  std::vector<testing::Ball> balls;
  std::mt19937 rng(7);
  std::uniform_real_distribution<double> radius(0.002, 0.003), jitter(-2e-4, 2e-4);
  for (int iz = 0; iz < 3; ++iz)
    for (int iy = 0; iy < 4; ++iy)
      for (int ix = 0; ix < 5; ++ix)
        balls.push_back({-0.015 + 0.0065 * ix + jitter(rng), -0.04 + 0.0065 * iy + jitter(rng),
                         0.0035 + 0.0065 * iz + jitter(rng), 0, 0, 0, radius(rng)});
  return balls;
}

dem::DrumState drumAt(double t) {
  dem::DrumState w;
  w.radius = 0.05;
  w.z_back = 0.02;
  w.omega = 0.5 * std::acos(-1.0);  // 15 rpm
  w.phi = w.omega * t;
  w.lifter_count = 4;
  w.lifter_height = 0.006;
  w.lifter_width = 0.004;
  return w;
}

std::unique_ptr<dem::DemEngine> drumEngine(const dem::DemHostState& s) {
  auto e = dem::makeDemEngineOmp(testing::drumSetup(0.5, 0.5, 0.002, 0.003, {-0.06, -0.06, -0.01}, {0.06, 0.06, 0.05}),
                                 false);
  e->setState(s);
  return e;
}

constexpr double kDt = 2e-6;  // ~ t_c / 60 for these balls at 1 m/s

void advance(dem::DemEngine& e, int& step, int steps) {
  for (int k = 0; k < steps; ++k) {
    ++step;
    e.step(drumAt(step * kDt), kDt);
  }
}

// Largest difference of velocities and spins between two states, over the largest speed (so a
// number near machine precision when they agree, of order 1 when they do not).
double relativeDifference(const dem::DemHostState& a, const dem::DemHostState& b) {
  double diff = 0, scale = 0;
  for (std::size_t k = 0; k < a.vel.size(); ++k) {
    diff = std::max({diff, std::abs(a.vel[k] - b.vel[k]), 0.003 * std::abs(a.omega[k] - b.omega[k])});
    scale = std::max({scale, std::abs(a.vel[k]), 0.003 * std::abs(a.omega[k])});
  }
  return diff / scale;
}

// Settles the charge for 0.15 s so most balls are in lasting, sticking and sliding contacts.
dem::DemHostState settledCharge(int& step) {
  auto e = drumEngine(testing::hostState(tumblingCharge(), 7800.0));
  e->initialize(drumAt(0));
  advance(*e, step, 75000);
  return testing::state(*e);
}

TEST(DemRenumbering, CheckpointRoundTripKeepsTheSprings) {
  int step = 0;
  const dem::DemHostState start = settledCharge(step);
  int contacts = 0;
  for (auto key : start.hist_id) contacts += key != dem::kNoPartner;
  ASSERT_GT(contacts, 60) << "the test needs a bed with many loaded contacts";

  auto direct = drumEngine(start);
  direct->initialize(drumAt(step * kDt));
  auto restarted = drumEngine(testing::state(*direct));  // through the host format once more
  restarted->initialize(drumAt(step * kDt));
  int s1 = step, s2 = step;
  advance(*direct, s1, 2000);
  advance(*restarted, s2, 2000);
  // Same state and same springs: the two runs differ only by summation order (~1e-16), which
  // 2000 steps of a dense frictional bed amplify to ~1e-12 at most.
  EXPECT_LT(relativeDifference(testing::state(*direct), testing::state(*restarted)), 1e-9);

  // Control: the same restart without its springs departs at the percent level, so the test
  // above would see lost or sign-flipped springs.
  dem::DemHostState no_springs = start;
  std::fill(no_springs.hist_xi.begin(), no_springs.hist_xi.end(), 0.0);
  auto forgetful = drumEngine(no_springs);
  forgetful->initialize(drumAt(step * kDt));
  int s3 = step;
  advance(*forgetful, s3, 2000);
  EXPECT_GT(relativeDifference(testing::state(*direct), testing::state(*forgetful)), 1e-3);
}

TEST(DemRenumbering, ResultDoesNotDependOnInputNumbering) {
  int step = 0;
  const dem::DemHostState start = settledCharge(step);
  // The same bed with its particles (and their springs' keys) listed in reverse order.
  const std::size_t n = start.size();
  auto rev = [n](std::size_t i) { return n - 1 - i; };
  dem::DemHostState reversed = start;
  std::fill(reversed.hist_id.begin(), reversed.hist_id.end(), dem::kNoPartner);
  std::vector<int> used(n, 0);
  for (std::size_t i = 0; i < n; ++i) {
    for (int q = 0; q < 3; ++q) {
      reversed.pos[3 * rev(i) + q] = start.pos[3 * i + q];
      reversed.vel[3 * rev(i) + q] = start.vel[3 * i + q];
      reversed.omega[3 * rev(i) + q] = start.omega[3 * i + q];
      reversed.force[3 * rev(i) + q] = start.force[3 * i + q];
      reversed.torque[3 * rev(i) + q] = start.torque[3 * i + q];
    }
    reversed.radius[rev(i)] = start.radius[i];
    reversed.mass[rev(i)] = start.mass[i];
    reversed.inertia[rev(i)] = start.inertia[i];
    reversed.dissipated[rev(i)] = start.dissipated[i];
    reversed.work_in[rev(i)] = start.work_in[i];
  }
  for (std::size_t i = 0; i < n; ++i)
    for (int k = 0; k < dem::kHistorySlots; ++k) {
      const std::int64_t key = start.hist_id[i * dem::kHistorySlots + k];
      if (key == dem::kNoPartner) continue;
      // A spring lives with the lower number: reversing makes the partner the lower one.
      const bool wall = key < 0;
      const std::size_t owner = wall ? rev(i) : rev(static_cast<std::size_t>(key));
      const std::int64_t new_key = wall ? key : static_cast<std::int64_t>(rev(i));
      const double sign = wall ? 1.0 : -1.0;
      const std::size_t e = owner * dem::kHistorySlots + used[owner]++;
      reversed.hist_id[e] = new_key;
      for (int q = 0; q < 3; ++q)
        reversed.hist_xi[3 * e + q] = sign * start.hist_xi[3 * (i * dem::kHistorySlots + k) + q];
    }

  auto a = drumEngine(start), b = drumEngine(reversed);
  a->initialize(drumAt(step * kDt));
  b->initialize(drumAt(step * kDt));
  int sa = step, sb = step;
  advance(*a, sa, 2000);
  advance(*b, sb, 2000);
  dem::DemHostState sa_state = testing::state(*a), sb_state = testing::state(*b), sb_back = sa_state;
  for (std::size_t i = 0; i < n; ++i)
    for (int q = 0; q < 3; ++q) {
      sb_back.vel[3 * i + q] = sb_state.vel[3 * rev(i) + q];
      sb_back.omega[3 * i + q] = sb_state.omega[3 * rev(i) + q];
    }
  EXPECT_LT(relativeDifference(sa_state, sb_back), 1e-9);
}

}  // namespace
}  // namespace millsim
