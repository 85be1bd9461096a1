// Cell-linked neighbour search (sort by cell key) against brute force: the set of pairs closer
// than the cutoff must be identical, for random, clustered and boundary-straddling point sets,
// in 2D and 3D. GPU runs of the same check live in tests/gpu.
#include <gtest/gtest.h>

#include <algorithm>
#include <random>
#include <set>
#include <utility>
#include <vector>

#include "millsim/neighbors/cell_list.hpp"

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
