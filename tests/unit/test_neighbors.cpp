// Cell-linked neighbour search (sort by cell key) against brute force: the set of pairs closer
// than the cutoff must be identical, for random, clustered and boundary-straddling point sets,
// in 2D and 3D. GPU runs of the same check live in tests/gpu. The host's vectorised distance
// filter for renumbered lists (slot_filter.hpp) must give the scalar test's hits bit for bit.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <iterator>
#include <limits>
#include <random>
#include <set>
#include <utility>
#include <vector>

#include "millsim/backend/simd.hpp"
#include "millsim/neighbors/cell_list.hpp"
#include "millsim/neighbors/slot_filter.hpp"
#include "support/simd_levels.hpp"

using millsim::core::Vec3;

namespace {

using PairSet = std::set<std::pair<int, int>>;

PairSet bruteForce(const std::vector<Vec3<double>>& p, double cut, bool two_d) {
  PairSet s;
  for (int i = 0; i < static_cast<int>(p.size()); ++i)
    for (int j = 0; j < static_cast<int>(p.size()); ++j) {
      if (i == j) continue;
      Vec3<double> d = p[i] - p[j];
      if (two_d) d.z = 0;
      if (millsim::core::norm2(d) < cut * cut) s.insert({i, j});
    }
  return s;
}

PairSet cellSearch(const std::vector<Vec3<double>>& p, double cut, bool two_d, Vec3<double> lo, Vec3<double> hi) {
  millsim::neighbors::CellList<millsim::backend::Omp, double> cells;
  cells.setGrid(millsim::neighbors::makeGrid<double>(lo, hi, cut, two_d));
  cells.build(p.data(), static_cast<int>(p.size()));
  const auto view = cells.view();
  PairSet s;
  for (int i = 0; i < static_cast<int>(p.size()); ++i)
    view.forEachCandidate(p[i], [&](int j) {
      if (i == j) return;
      Vec3<double> d = p[i] - p[j];
      if (two_d) d.z = 0;
      if (millsim::core::norm2(d) < cut * cut) s.insert({i, j});
    });
  return s;
}

enum class Layout { kRandom, kClustered, kStraddling };

std::vector<Vec3<double>> makePoints(Layout layout, bool two_d, int n, unsigned seed) {
  std::mt19937 rng(seed);
  std::uniform_real_distribution<double> u(0.0, 1.0);
  std::normal_distribution<double> g(0.0, 0.02);
  std::vector<Vec3<double>> p;
  for (int i = 0; i < n; ++i) {
    Vec3<double> q{u(rng), u(rng), two_d ? 0.0 : u(rng)};
    if (layout == Layout::kClustered) {
      // Three tight clusters: many particles per cell, many empty cells.
      const double c = 0.2 + 0.3 * (i % 3);
      q = {c + g(rng), c + g(rng), two_d ? 0.0 : c + g(rng)};
    } else if (layout == Layout::kStraddling) {
      // On and across the grid boundary (the grid covers [0, 1]) and exactly on cell faces.
      const double faces[] = {-0.05, 0.0, 0.1, 0.5, 1.0, 1.05};
      q.x = faces[i % 6] + 1e-12 * (i % 2);
      q.y = (i % 4 == 0) ? 1.0 : q.y;
    }
    p.push_back(q);
  }
  return p;
}

}  // namespace

class NeighbourSearch : public ::testing::TestWithParam<std::tuple<Layout, bool>> {};

TEST_P(NeighbourSearch, EqualsBruteForce) {
  const auto [layout, two_d] = GetParam();
  const double cut = 0.1;
  for (unsigned seed = 1; seed <= 3; ++seed) {
    const auto p = makePoints(layout, two_d, 600, seed);
    const PairSet expected = bruteForce(p, cut, two_d);
    const PairSet found = cellSearch(p, cut, two_d, {0, 0, 0}, {1, 1, 1});
    ASSERT_FALSE(expected.empty());
    EXPECT_EQ(found, expected) << "seed " << seed;
  }
}

INSTANTIATE_TEST_SUITE_P(Layouts, NeighbourSearch,
                         ::testing::Combine(::testing::Values(Layout::kRandom, Layout::kClustered, Layout::kStraddling),
                                            ::testing::Bool()));

TEST(CellGrid, KeysSortedAndRangesCoverEveryParticle) {
  const auto p = makePoints(Layout::kRandom, false, 1000, 7);
  millsim::neighbors::CellList<millsim::backend::Omp, double> cells;
  cells.setGrid(millsim::neighbors::makeGrid<double>({0, 0, 0}, {1, 1, 1}, 0.1, false));
  cells.build(p.data(), static_cast<int>(p.size()));
  const auto v = cells.view();
  std::vector<int> seen(p.size(), 0);
  for (int k = 0; k < v.grid.cellCount(); ++k)
    for (int s = v.cell_start[k]; s < v.cell_end[k]; ++s) {
      EXPECT_EQ(v.grid.cellOf(p[v.order[s]]), k);
      ++seen[v.order[s]];
    }
  for (int c : seen) EXPECT_EQ(c, 1);
}

namespace {

// One to three ranges [begin, end), each up to 40 slots long at several offsets (full vectors,
// partial tails of every length, empty ranges), points at about the radius (a quarter to a half
// are hits), one NaN position (never a hit): hits and squared distances equal to the plain
// test's, bit for bit, at every level, and nothing written past the buffer's stated size.
template <class T>
void checkSlotFilter() {
  std::mt19937 rng(11);
  std::uniform_real_distribution<T> u(T(-1), T(1));
  std::vector<Vec3<T>> pos(240);
  for (auto& q : pos) q = {u(rng), u(rng), u(rng)};
  pos[37].y = std::numeric_limits<T>::quiet_NaN();
  const Vec3<T> p{T(0.1), T(-0.2), T(0.05)};
  const T radius2 = T(0.8);
  const int kSentinel = -7;
  std::uniform_int_distribution<int> extra(0, 40);
  for (const auto level : millsim::testing::hostSimdLevels()) {
    const millsim::backend::ScopedSimdLevel simd(level);
    for (int ranges = 1; ranges <= 3; ++ranges)
      for (int begin0 : {0, 1, 5, 16, 29})
        for (int len = 0; len <= 40; ++len) {
          int begin[3], end[3], total = 0;
          for (int k = 0; k < ranges; ++k) {
            begin[k] = k == 0 ? begin0 : end[k - 1] + extra(rng) % 7;
            end[k] = begin[k] + (k == 0 ? len : extra(rng));
            total += end[k] - begin[k];
          }
          std::vector<int> want;
          std::vector<T> want_r2;
          for (int k = 0; k < ranges; ++k)
            for (int s = begin[k]; s < end[k]; ++s) {
              const T r2 = millsim::core::norm2(p - pos[s]);
              if (r2 < radius2) want.push_back(s), want_r2.push_back(r2);
            }
          std::vector<int> hit(total + millsim::neighbors::kSlotFilterPad + 1, kSentinel);
          std::vector<T> hit_r2(hit.size());
          const int n = millsim::neighbors::filterRangesInOrder(begin, end, ranges, p, radius2, pos.data(), hit.data(),
                                                                hit_r2.data());
          ASSERT_EQ(n, static_cast<int>(want.size())) << simdLevelName(level) << " ranges " << ranges << " len " << len;
          for (int k = 0; k < n; ++k) {
            EXPECT_EQ(hit[k], want[k]) << simdLevelName(level);
            EXPECT_EQ(hit_r2[k], want_r2[k]) << simdLevelName(level);
          }
          EXPECT_EQ(hit.back(), kSentinel) << simdLevelName(level) << ": wrote past the buffer";
        }
  }
}

}  // namespace

TEST(SlotFilter, EveryLevelGivesThePlainTestsHitsFloat) { checkSlotFilter<float>(); }
TEST(SlotFilter, EveryLevelGivesThePlainTestsHitsDouble) { checkSlotFilter<double>(); }

// A list renumbered in cell order (as the SPH and DEM solvers do) searched with forEachWithin:
// the pairs equal brute force at every level, in 2D and 3D, float and double.
template <class T>
void checkRenumberedSearch(bool two_d) {
  const double cut = 0.1;
  const auto pd = makePoints(Layout::kClustered, two_d, 800, 5);
  const PairSet expected = bruteForce(pd, cut, two_d);
  millsim::neighbors::CellList<millsim::backend::Omp, T> cells;
  cells.setGrid(millsim::neighbors::makeGrid<T>({0, 0, 0}, {1, 1, 1}, T(cut), two_d));
  std::vector<Vec3<T>> p(pd.size());
  for (std::size_t i = 0; i < pd.size(); ++i) p[i] = {T(pd[i].x), T(pd[i].y), T(pd[i].z)};
  cells.build(p.data(), static_cast<int>(p.size()));
  std::vector<int> id(p.size());  // renumbering: slot s holds original particle order[s]
  std::vector<Vec3<T>> q(p.size());
  for (std::size_t s = 0; s < p.size(); ++s) id[s] = cells.view().order[s], q[s] = p[id[s]];
  EXPECT_FALSE(cells.view().in_order);
  cells.renumberedInOrder();
  const auto view = cells.view();
  ASSERT_TRUE(view.in_order);
  const T cut2 = T(cut * cut);
  for (const auto level : millsim::testing::hostSimdLevels()) {
    const millsim::backend::ScopedSimdLevel simd(level);
    PairSet found;
    for (int s = 0; s < static_cast<int>(q.size()); ++s)
      view.forEachWithin(q[s], cut2, q.data(), [&](int j, Vec3<T>, T) {
        if (j != s) found.insert({id[s], id[j]});
      });
    // Pairs within float rounding of the cutoff may differ from the double brute force.
    PairSet diff;
    std::set_symmetric_difference(found.begin(), found.end(), expected.begin(), expected.end(),
                                  std::inserter(diff, diff.begin()));
    for (const auto& [i, j] : diff) {
      Vec3<double> d = pd[i] - pd[j];
      EXPECT_NEAR(std::sqrt(millsim::core::norm2(d)), cut, 1e-6) << simdLevelName(level) << " pair " << i << "-" << j;
    }
    EXPECT_GT(found.size(), 1000u);
  }
}

TEST(SlotFilter, RenumberedSearchEqualsBruteForce) {
  for (bool two_d : {false, true}) {
    checkRenumberedSearch<double>(two_d);
    checkRenumberedSearch<float>(two_d);
  }
}
