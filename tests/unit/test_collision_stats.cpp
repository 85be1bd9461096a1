// Beinert collision typology of the stirred mill (src/dem/collision_stats.hpp): each mode's
// energy for a contact that moves in that mode only, written out from the definitions (seed 004
// eqs. 12-17; Beinert et al. 2015), and the pair hook's booking of a contact step: dissipation
// to the dominant mode, the normal-damping part, collisions counted only when a contact begins.
#include <gtest/gtest.h>

#include "dem/collision_stats.hpp"

namespace {

using millsim::core::Vec3;
using millsim::dem::beinertEnergies;
using millsim::dem::CollisionTally;
using millsim::dem::ContactResult;
using millsim::dem::kModeImpact;
using millsim::dem::kModeRolling;
using millsim::dem::kModeShearing;
using millsim::dem::kModeTorsion;
using millsim::dem::StirredPairExtra;

const Vec3<double> kZero{0, 0, 0};
const Vec3<double> kN{1, 0, 0};  // contact normal
constexpr double kM = 2.5e-5;    // kg, one 2 mm zirconia bead (6000 kg/m3)
constexpr double kR = 1e-3;      // m

// The one mode that must be non-zero; the others vanish to rounding.
void expectOnly(const millsim::dem::BeinertEnergies<double>& b, int mode, double value) {
  for (int q = 0; q < millsim::dem::kModeCount; ++q) {
    if (q == mode)
      EXPECT_NEAR(b.e[q], value, 1e-12 * value) << "mode " << q;
    else
      EXPECT_NEAR(b.e[q], 0.0, 1e-15 * value) << "mode " << q;
  }
}

// Head-on approach at 0.3 m/s each: impact E_i = 1/2 m (v_rel . n)^2 with v_rel = 0.6 m/s.
TEST(BeinertTypology, HeadOnApproachIsImpactOnly) {
  const auto b = beinertEnergies(kN, kR, kR, kM, Vec3<double>{-0.3, 0, 0}, Vec3<double>{0.3, 0, 0}, kZero, kZero);
  expectOnly(b, kModeImpact, 0.5 * kM * 0.36);
}

// One bead sliding past the other at 0.2 m/s without turning: shearing 1/2 m |v_slip|^2.
TEST(BeinertTypology, SlidingWithoutRotationIsShearingOnly) {
  const auto b = beinertEnergies(kN, kR, kR, kM, Vec3<double>{0, 0.2, 0}, kZero, kZero, kZero);
  expectOnly(b, kModeShearing, 0.5 * kM * 0.04);
}

// Two equal beads turning in opposite senses about an axis across the normal, w_j = -w_i: their
// surfaces move together at the contact (no slip), the relative rotation 2w is rolling,
// E_r = 1/5 m r^2 |2w|^2 with r = 2 ri rj / (ri + rj) = R.
TEST(BeinertTypology, CounterRotationWithoutSlipIsRollingOnly) {
  const double w = 40.0;
  const auto b = beinertEnergies(kN, kR, kR, kM, kZero, kZero, Vec3<double>{0, 0, w}, Vec3<double>{0, 0, -w});
  expectOnly(b, kModeRolling, 0.2 * kM * kR * kR * 4 * w * w);
}

// Spin about the normal: torsion E_t = 1/5 m r^2 ((w_i - w_j) . n)^2; unequal radii give the
// harmonic radius r = 2 ri rj / (ri + rj) (1 mm and 3 mm: 1.5 mm).
TEST(BeinertTypology, SpinAboutTheNormalIsTorsionWithTheHarmonicRadius) {
  const double w = 25.0, rj = 3e-3, r = 2 * kR * rj / (kR + rj);
  ASSERT_NEAR(r, 1.5e-3, 1e-15);
  const auto b = beinertEnergies(kN, kR, rj, kM, kZero, kZero, Vec3<double>{w, 0, 0}, kZero);
  expectOnly(b, kModeTorsion, 0.2 * kM * r * r * w * w);
}

// A spinning bead against a still one, the spin across the normal: its surface slides over the
// other's (v_slip = -(ri w_i) x n, |v_slip| = R w) while the relative rotation w_i also rolls, so
// shearing = 1/2 m R^2 w^2 and rolling = 1/5 m R^2 w^2: both, shearing dominant (5/2 of rolling).
TEST(BeinertTypology, SpinningAgainstAStillBeadSlidesAndRolls) {
  const double w = 30.0;
  const auto b = beinertEnergies(kN, kR, kR, kM, kZero, kZero, Vec3<double>{0, 0, w}, kZero);
  EXPECT_NEAR(b.e[kModeShearing], 0.5 * kM * kR * kR * w * w, 1e-12 * b.e[kModeShearing]);
  EXPECT_NEAR(b.e[kModeRolling], 0.2 * kM * kR * kR * w * w, 1e-12 * b.e[kModeRolling]);
  EXPECT_EQ(b.e[kModeImpact], 0.0);
  EXPECT_EQ(b.e[kModeTorsion], 0.0);
}

// The hook books one contact step: the whole dissipation (rate x dt) to the dominant mode, the
// normal-damping part as the total less the tangential work (force_t . v_t <= 0 is dissipative),
// and a collision with its energies only on the step that begins the contact.
TEST(BeinertTypology, PairHookBooksDissipationToTheDominantModeAndCountsBeginnings) {
  CollisionTally tally[1] = {};
  StirredPairExtra<double, false, true> hook{};
  hook.tally = tally;
  hook.dt = 1e-6;
  // Sliding at 0.2 m/s (shearing dominates) with a slower approach 0.05 m/s.
  const Vec3<double> vi{-0.05, 0.2, 0}, vj = kZero;
  ContactResult<double> c{};
  c.force_t = Vec3<double>{0, -0.3, 0};  // friction against the slip
  c.dissipation_rate = 0.09;             // W: 0.06 tangential (0.3 N x 0.2 m/s) + 0.03 normal damping
  const Vec3<double> v_rel = vi - vj;
  hook.pairContact(0, kN, kR, kR, kM, vi - vj, kZero, kZero, v_rel, c, true);
  hook.pairContact(0, kN, kR, kR, kM, vi - vj, kZero, kZero, v_rel, c, false);
  EXPECT_NEAR(tally[0].dissipated[kModeShearing], 2 * 0.09e-6, 1e-20);
  EXPECT_EQ(tally[0].dissipated[kModeImpact], 0.0);
  EXPECT_EQ(tally[0].dissipated[kModeRolling], 0.0);
  EXPECT_EQ(tally[0].dissipated[kModeTorsion], 0.0);
  EXPECT_NEAR(tally[0].dissipated_normal, 2 * 0.03e-6, 1e-20);
  EXPECT_EQ(tally[0].collisions, 1.0);
  EXPECT_NEAR(tally[0].energy[kModeShearing], 0.5 * kM * 0.04, 1e-20);
  EXPECT_NEAR(tally[0].energy[kModeImpact], 0.5 * kM * 0.0025, 1e-20);
}

}  // namespace
