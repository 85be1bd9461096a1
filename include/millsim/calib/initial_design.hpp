#pragma once
// Space-filling initial candidates: a maximin Latin hypercube in the unit square. Each of the
// n rows and n columns of an n x n grid holds one point (every e level and every mu level is
// tried once, as a Latin hypercube does), points at the cell centres, and of `tries` random
// permutations the one with the largest smallest pairwise distance is kept (Morris & Mitchell
// 1995). Deterministic for a given seed, so a resumed calibration proposes the same six.
#include <cstdint>
#include <vector>

#include "millsim/calib/param_box.hpp"

namespace millsim::calib {

// n >= 1 points in [0, 1]^2. Defaults: 2000 tries, seed 1.
std::vector<Point2> maximinLatinHypercube(int n, std::uint64_t seed = 1, int tries = 2000);

}  // namespace millsim::calib
