// The host's counting sort (backend::sortByKey, Omp): every neighbour build sorts particles by
// cell with it, and the cell lists, the renumbering and the pair loops' summation order all
// follow its order. On several threads each thread sorts its part of the input against offsets
// shared out by key; the result must be the one stable order (equal keys in input order) on
// any thread count, so a run's numbers do not depend on the sort's threads. Checked against
// std::stable_sort for few keys (long runs of equal keys), more keys than pairs (empty cells,
// as in a sparse domain), and with one scratch reused across sizes and thread counts, below and
// above kOmpParallelThreshold (2048).
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

TEST(BackendSortByKey, IsTheStableOrderOnAnyThreadCount) {
  std::mt19937 rng(5);
  std::vector<int> scratch;  // reused, as a cell list does
  for (int n : {1000, 50000, 3})
    for (int key_count : {7, 4000, 200000})
      for (int threads : {1, 2, 3, 4}) {
        omp_set_num_threads(threads);
        std::uniform_int_distribution<int> key(0, key_count - 1);
        std::vector<int> keys(n), values(n);
        for (int& k : keys) k = key(rng);
        std::iota(values.begin(), values.end(), 0);
        std::vector<std::pair<int, int>> expected(n);
        for (int i = 0; i < n; ++i) expected[i] = {keys[i], values[i]};
        std::stable_sort(expected.begin(), expected.end(),
                         [](const auto& a, const auto& b) { return a.first < b.first; });

        backend::sortByKey(backend::Omp{}, keys.data(), values.data(), n, key_count, scratch);
        int wrong = 0;
        for (int i = 0; i < n; ++i) wrong += keys[i] != expected[i].first || values[i] != expected[i].second;
        EXPECT_EQ(wrong, 0) << "n = " << n << ", " << key_count << " keys, " << threads << " threads";
      }
  omp_set_num_threads(1);
}

}  // namespace
}  // namespace millsim
