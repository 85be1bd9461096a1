// The host's counting sort (backend::sortByKey, Omp): every neighbour build sorts particles by
// cell with it, and the cell lists, the renumbering and the pair loops' summation order all
// follow its order. On several threads each thread sorts its part of the input against offsets
// shared out by key; the result must be the one stable order (equal keys in input order) on
// any thread count, so a run's numbers do not depend on the sort's threads. Checked against
// std::stable_sort for few keys (long runs of equal keys), many keys (empty cells, as in a sparse
// domain), and with one scratch reused across sizes and thread counts, below and above
// kOmpParallelThreshold (2048) and on both sides of the key_count <= n rule for the threads.
#include <gtest/gtest.h>
#include <omp.h>

#include <algorithm>
#include <numeric>
#include <random>
#include <utility>
#include <vector>

#include "millsim/backend/omp.hpp"

namespace millsim {
namespace {

// Random keys in [0, key_count), values 0..n-1, and the stable order std::stable_sort gives them.
struct SortCase {
  std::vector<int> keys, values;
  std::vector<std::pair<int, int>> expected;
  SortCase(int n, int key_count, std::mt19937& rng) : keys(n), values(n), expected(n) {
    std::uniform_int_distribution<int> key(0, key_count - 1);
    for (int& k : keys) k = key(rng);
    std::iota(values.begin(), values.end(), 0);
    for (int i = 0; i < n; ++i) expected[i] = {keys[i], values[i]};
    std::stable_sort(expected.begin(), expected.end(), [](const auto& a, const auto& b) { return a.first < b.first; });
  }
  int wrong() const {
    int w = 0;
    for (std::size_t i = 0; i < keys.size(); ++i) w += keys[i] != expected[i].first || values[i] != expected[i].second;
    return w;
  }
};

TEST(BackendSortByKey, IsTheStableOrderOnAnyThreadCount) {
  const int max_threads = omp_get_max_threads();
  std::mt19937 rng(5);
  std::vector<int> scratch;  // reused, as a cell list does
  // Serial (n below the threshold, or more keys than pairs) and parallel (50 000 and 300 000
  // pairs with up to 200 000 keys).
  for (int n : {1000, 50000, 3, 300000})
    for (int key_count : {7, 4000, 200000})
      for (int threads : {1, 2, 3, 4}) {
        omp_set_num_threads(threads);
        SortCase c(n, key_count, rng);
        backend::sortByKey(backend::Omp{}, c.keys.data(), c.values.data(), n, key_count, scratch);
        EXPECT_EQ(c.wrong(), 0) << "n = " << n << ", " << key_count << " keys, " << threads << " threads";
      }
  omp_set_num_threads(max_threads);
}

// OpenMP may give a smaller team than the threads the sort asked for (OMP_DYNAMIC, or inside
// another parallel region): the scratch is sized for the threads asked, the work shared by the
// team. Here each of two outer threads sorts its own pairs with nested regions off, so its team
// is one thread while omp_get_max_threads() says three.
TEST(BackendSortByKey, IsTheStableOrderWithASmallerTeam) {
  const int max_threads = omp_get_max_threads(), max_levels = omp_get_max_active_levels();
  omp_set_max_active_levels(1);
  int wrong[2] = {-1, -1}, asked[2] = {0, 0};
#pragma omp parallel num_threads(2)
  {
    const int t = omp_get_thread_num();
    omp_set_num_threads(3);  // this thread's request for a nested team
    std::mt19937 rng(17 + t);
    SortCase c(60000, 5000, rng);
    std::vector<int> scratch;
    asked[t] = omp_get_max_threads();
    backend::sortByKey(backend::Omp{}, c.keys.data(), c.values.data(), 60000, 5000, scratch);
    wrong[t] = c.wrong();
  }
  omp_set_max_active_levels(max_levels);
  omp_set_num_threads(max_threads);
  for (int t = 0; t < 2; ++t) {
    EXPECT_EQ(asked[t], 3) << "outer thread " << t;  // the sort asked for three
    EXPECT_EQ(wrong[t], 0) << "outer thread " << t;
  }
}

}  // namespace
}  // namespace millsim
