#pragma once
// Minimum of a surrogate surface over the unit square, away from the points already evaluated:
// a dense grid (default 101 x 101), then a compass search (step halved on failure, from the
// grid spacing down to 1e-4) from the best few grid points. Both methods propose with it: the
// paper method minimises the interpolated SSE, the GP method minimises minus the expected
// improvement. Points closer than `exclusion` (unit-square distance) to an evaluated point are
// never proposed: an exact interpolant's minimum often sits on the best data point, and
// proposing it again would cost a simulation and learn nothing.
#include <functional>
#include <vector>

#include "millsim/calib/param_box.hpp"

namespace millsim::calib {

struct SearchOptions {
  int grid = 101;           // grid points per axis
  int starts = 5;           // best grid points refined by the compass search
  double exclusion = 0.02;  // no proposal within this distance of an evaluated point (unit square)
};

struct SearchResult {
  Point2 x{0.5, 0.5};  // unit coordinates
  double value = 0;
  bool found = false;  // false when every grid point is excluded
};

SearchResult minimiseSurface(const std::function<double(const Point2&)>& f, const std::vector<Point2>& evaluated,
                             const SearchOptions& options = {});

}  // namespace millsim::calib
