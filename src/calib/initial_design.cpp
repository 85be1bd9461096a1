// Maximin Latin hypercube by random restarts (see header).
#include "millsim/calib/initial_design.hpp"

#include <algorithm>
#include <cmath>
#include <limits>
#include <numeric>
#include <random>
#include <stdexcept>

namespace millsim::calib {

std::vector<Point2> maximinLatinHypercube(int n, std::uint64_t seed, int tries) {
  if (n < 1) throw std::invalid_argument("maximinLatinHypercube: n must be >= 1");
  std::mt19937_64 rng(seed);
  std::vector<int> perm(n);
  std::iota(perm.begin(), perm.end(), 0);
  std::vector<Point2> best;
  double best_d = -1;
  for (int t = 0; t < std::max(1, tries); ++t) {
    std::shuffle(perm.begin(), perm.end(), rng);
    std::vector<Point2> pts(n);
    for (int i = 0; i < n; ++i) pts[i] = {(i + 0.5) / n, (perm[i] + 0.5) / n};
    double dmin = std::numeric_limits<double>::infinity();
    for (int i = 0; i < n; ++i)
      for (int j = 0; j < i; ++j) dmin = std::min(dmin, std::hypot(pts[i][0] - pts[j][0], pts[i][1] - pts[j][1]));
    if (dmin > best_d) {
      best_d = dmin;
      best = pts;
    }
  }
  return best;
}

}  // namespace millsim::calib
