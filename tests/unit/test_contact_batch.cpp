// The host's contact pass in blocks of pairs (src/dem/contact_batch.hpp) against the pair-by-pair
// loop that CUDA runs (ContactForces::operator()).
//  - The block evaluation is touchingPair, the same function, run in a vectorised loop: with no
//    FMA contraction (ISO C++ mode) and correctly rounded square roots and divisions at every
//    vector width, each pair's results must equal the one-pair call bit for bit, at every SIMD
//    level this CPU has. An ISA or lane bug (a wrong mask on the sliding branch, a lane mixed up)
//    changes results at order one.
//  - Whole runs: the blocks book the same contributions in another order, so a dense colliding
//    bed after 400 steps agrees with the pair-by-pair pass to round-off growth (1e-9, as for the
//    thread count in test_dem_threads.cpp; a lost or doubled booking changes velocities at order
//    one), and runs at the different SIMD levels agree exactly (same bits per pair, same order).
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <random>
#include <stdexcept>
#include <vector>

#include "dem/contact/hertz.hpp"
#include "dem/contact_batch.hpp"
#include "millsim/backend/simd.hpp"
#include "support/dem_fixture.hpp"

namespace millsim {
namespace {

using backend::SimdLevel;

std::vector<SimdLevel> cpuLevels() {
  std::vector<SimdLevel> levels;
  for (SimdLevel l : {SimdLevel::kBaseline, SimdLevel::kAvx2, SimdLevel::kAvx512})
    if (static_cast<int>(l) <= static_cast<int>(backend::cpuSimdLevel())) levels.push_back(l);
  return levels;
}

// Random touching pairs of 1-20 mm steel balls: overlaps up to 1% of the smaller radius,
// velocities to 2 m/s, spins to 200 rad/s, and springs that are new (zero), small (sticking) or
// long (sliding: the Coulomb branch), so every branch of the law is taken in some lanes.
template <class T>
struct Pairs {
  std::vector<core::Vec3<T>> d, dv, wi, wj, s;
  std::vector<T> dist2, ri, rj, mi, mj;
};

template <class T>
Pairs<T> randomPairs(int n, unsigned seed) {
  std::mt19937 rng(seed);
  std::uniform_real_distribution<double> u(-1.0, 1.0), radius(0.001, 0.01), overlap(1e-5, 1e-2), unit(0.0, 1.0);
  Pairs<T> p;
  for (int k = 0; k < n; ++k) {
    const double ri = radius(rng), rj = radius(rng);
    double nx = u(rng), ny = u(rng), nz = u(rng);
    const double len = std::sqrt(nx * nx + ny * ny + nz * nz) + 1e-12;
    const double dist = (ri + rj) - overlap(rng) * std::min(ri, rj);
    const core::Vec3<T> d{T(dist * nx / len), T(dist * ny / len), T(dist * nz / len)};
    p.d.push_back(d);
    p.dist2.push_back(core::norm2(d));
    p.ri.push_back(T(ri));
    p.rj.push_back(T(rj));
    p.mi.push_back(T(testing::ballMass(ri, 7800.0)));
    p.mj.push_back(T(testing::ballMass(rj, 7800.0)));
    p.dv.push_back({T(2 * u(rng)), T(2 * u(rng)), T(2 * u(rng))});
    p.wi.push_back({T(200 * u(rng)), T(200 * u(rng)), T(200 * u(rng))});
    p.wj.push_back({T(200 * u(rng)), T(200 * u(rng)), T(200 * u(rng))});
    const double kind = unit(rng), scale = kind < 0.25 ? 0.0 : (kind < 0.6 ? 1e-7 : 1e-4);
    p.s.push_back({T(scale * u(rng)), T(scale * u(rng)), T(scale * u(rng))});
  }
  return p;
}

template <class T, class Law>
void expectBlocksEqualPairCalls(const Law& law) {
  const int n = 3 * dem::PairBlock<T>::kSize - 5;  // full blocks and a partial one
  const Pairs<T> p = randomPairs<T>(n, 11);
  const T dt = T(2e-6);
  int sliding = 0;
  for (SimdLevel level : cpuLevels()) {
    SCOPED_TRACE(backend::simdLevelName(level));
    for (int first = 0; first < n; first += dem::PairBlock<T>::kSize) {
      const int count = std::min(n - first, dem::PairBlock<T>::kSize);
      dem::PairBlock<T> b;
      for (int k = 0; k < count; ++k) {
        const int q = first + k;
        b.dx[k] = p.d[q].x, b.dy[k] = p.d[q].y, b.dz[k] = p.d[q].z, b.dist2[k] = p.dist2[q];
        b.ri[k] = p.ri[q], b.rj[k] = p.rj[q], b.mi[k] = p.mi[q], b.mj[k] = p.mj[q];
        b.dvx[k] = p.dv[q].x, b.dvy[k] = p.dv[q].y, b.dvz[k] = p.dv[q].z;
        b.wix[k] = p.wi[q].x, b.wiy[k] = p.wi[q].y, b.wiz[k] = p.wi[q].z;
        b.wjx[k] = p.wj[q].x, b.wjy[k] = p.wj[q].y, b.wjz[k] = p.wj[q].z;
        b.sx[k] = p.s[q].x, b.sy[k] = p.s[q].y, b.sz[k] = p.s[q].z;
      }
      dem::evaluatePairBlock(b, count, law, dt, level);
      for (int k = 0; k < count; ++k) {
        const int q = first + k;
        core::Vec3<T> s = p.s[q];
        const dem::TouchingPair<T> t = dem::touchingPair(law, p.d[q], p.dist2[q], p.ri[q], p.rj[q], p.mi[q], p.mj[q],
                                                         p.dv[q], p.wi[q], p.wj[q], s, dt);
        ASSERT_EQ(b.fx[k], t.c.force.x) << "pair " << q;
        ASSERT_EQ(b.fy[k], t.c.force.y) << "pair " << q;
        ASSERT_EQ(b.fz[k], t.c.force.z) << "pair " << q;
        ASSERT_EQ(b.tx[k], t.nxft.x) << "pair " << q;
        ASSERT_EQ(b.ty[k], t.nxft.y) << "pair " << q;
        ASSERT_EQ(b.tz[k], t.nxft.z) << "pair " << q;
        ASSERT_EQ(b.ai[k], t.ai) << "pair " << q;
        ASSERT_EQ(b.aj[k], t.aj) << "pair " << q;
        ASSERT_EQ(b.diss[k], t.c.dissipation_rate) << "pair " << q;
        ASSERT_EQ(b.elastic[k], t.c.elastic_energy) << "pair " << q;
        ASSERT_EQ(b.sx[k], s.x) << "pair " << q;
        ASSERT_EQ(b.sy[k], s.y) << "pair " << q;
        ASSERT_EQ(b.sz[k], s.z) << "pair " << q;
        // Sliding: the spring was reset to carry the Coulomb force, |F_t| = mu F_n.
        const T ft = core::norm(t.c.force_t), fn = core::dot(t.c.force, t.n);
        if (level == SimdLevel::kBaseline && fn > T(0) && std::abs(ft - law.p.friction * fn) < T(1e-4) * ft) ++sliding;
      }
    }
  }
  // Both branches of the Coulomb limit were exercised (else the test would not see a bad mask).
  EXPECT_GT(sliding, n / 10);
  EXPECT_LT(sliding, n - n / 10);
}

template <class T>
dem::HertzParams<T> steel() {
  // E = 200 GPa, nu = 0.3: E* = E / (2 (1 - nu^2)); 4/3 E*; alpha for e = 0.39 (order of).
  return {T(4.0 / 3.0 * 200e9 / (2 * (1 - 0.09))), T(1.2), T(0.5)};
}

TEST(ContactBatch, HertzMindlinBlocksEqualPairCallsAtEverySimdLevel) {
  expectBlocksEqualPairCalls<double>(dem::HertzMindlin<double>{steel<double>()});
  expectBlocksEqualPairCalls<float>(dem::HertzMindlin<float>{steel<float>()});
}

TEST(ContactBatch, TanhSmoothedBlocksEqualPairCallsAtEverySimdLevel) {
  expectBlocksEqualPairCalls<double>(dem::HertzMindlin<double, dem::FrictionSmoothing::kTanh>{steel<double>()});
}

// The dense bed of dem_fixture.hpp (as in test_dem_threads.cpp), one thread, 400 steps.
dem::DemHostState runBed(SimdLevel level) {
  const backend::ScopedSimdLevel simd(level);
  return testing::runDenseDrumBed(400);
}

TEST(ContactBatch, BlockedPassGivesThePairByPairPhysics) {
  const dem::DemHostState pairwise = runBed(SimdLevel::kScalar);
  const dem::DemHostState blocked = runBed(SimdLevel::kBaseline);
  ASSERT_EQ(pairwise.size(), blocked.size());
  double diff = 0, scale = 0, dissipated_p = 0, dissipated_b = 0, work_in_diff = 0;
  for (std::size_t k = 0; k < pairwise.vel.size(); ++k) {
    diff = std::max(diff, std::abs(pairwise.vel[k] - blocked.vel[k]));
    diff = std::max(diff, std::abs(pairwise.omega[k] - blocked.omega[k]) * 0.005);  // as a rim speed
    scale = std::max(scale, std::abs(pairwise.vel[k]));
  }
  for (std::size_t i = 0; i < pairwise.size(); ++i) {
    dissipated_p += pairwise.dissipated[i];
    dissipated_b += blocked.dissipated[i];
    work_in_diff += std::abs(pairwise.work_in[i] - blocked.work_in[i]);
  }
  ASSERT_GT(dissipated_p, 0.0);  // the balls did collide
  EXPECT_LT(diff / scale, 1e-9);
  EXPECT_NEAR(dissipated_b, dissipated_p, 1e-9 * dissipated_p);
  EXPECT_LT(work_in_diff, 1e-9 * dissipated_p);
}

TEST(ContactBatch, RunsAtEverySimdLevelAgreeExactly) {
  const std::vector<SimdLevel> levels = cpuLevels();
  if (levels.size() < 2) GTEST_SKIP() << "this CPU has only the baseline level";
  const dem::DemHostState first = runBed(levels.front());
  for (std::size_t l = 1; l < levels.size(); ++l) {
    SCOPED_TRACE(backend::simdLevelName(levels[l]));
    const dem::DemHostState other = runBed(levels[l]);
    ASSERT_EQ(first.pos, other.pos);
    ASSERT_EQ(first.vel, other.vel);
    ASSERT_EQ(first.omega, other.omega);
    ASSERT_EQ(first.dissipated, other.dissipated);
  }
}

TEST(ContactBatch, UnknownOrUnsupportedLevelsAreRefused) {
  EXPECT_THROW(backend::parseSimdLevel("sse9"), std::invalid_argument);
  EXPECT_EQ(backend::parseSimdLevel("avx2"), SimdLevel::kAvx2);
  if (backend::cpuSimdLevel() != SimdLevel::kAvx512) {
    EXPECT_THROW(backend::setSimdLevel(SimdLevel::kAvx512), std::invalid_argument);
  }
}

// A comparison at the scalar level that fails half way (an exception, a fatal assertion) must
// hand the process back at the level it found: the later tests run at that level.
TEST(ContactBatch, ScopedLevelIsGivenBackWhenItsScopeThrows) {
  const SimdLevel before = backend::simdLevel();
  try {
    const backend::ScopedSimdLevel scalar(SimdLevel::kScalar);
    EXPECT_EQ(backend::simdLevel(), SimdLevel::kScalar);
    throw std::runtime_error("a failed run");
  } catch (const std::runtime_error&) {
  }
  EXPECT_EQ(backend::simdLevel(), before);
}

}  // namespace
}  // namespace millsim
