// Grid + compass search for the minimum of a surrogate away from evaluated points.
#include "millsim/calib/surface_search.hpp"

#include <algorithm>
#include <cmath>

namespace millsim::calib {

namespace {

bool allowed(const Point2& x, const std::vector<Point2>& evaluated, double exclusion) {
  if (x[0] < 0 || x[0] > 1 || x[1] < 0 || x[1] > 1) return false;
  for (const Point2& p : evaluated)
    if (std::hypot(x[0] - p[0], x[1] - p[1]) < exclusion) return false;
  return true;
}

}  // namespace

SearchResult minimiseSurface(const std::function<double(const Point2&)>& f, const std::vector<Point2>& evaluated,
                             const SearchOptions& options) {
  const int n = std::max(2, options.grid);
  struct Node {
    double value;
    Point2 x;
  };
  std::vector<Node> nodes;
  nodes.reserve(static_cast<std::size_t>(n) * n);
  for (int j = 0; j < n; ++j)
    for (int i = 0; i < n; ++i) {
      const Point2 x{static_cast<double>(i) / (n - 1), static_cast<double>(j) / (n - 1)};
      if (allowed(x, evaluated, options.exclusion)) nodes.push_back({f(x), x});
    }
  SearchResult result;
  if (nodes.empty()) return result;
  const std::size_t starts = std::min<std::size_t>(std::max(1, options.starts), nodes.size());
  std::partial_sort(nodes.begin(), nodes.begin() + static_cast<std::ptrdiff_t>(starts), nodes.end(),
                    [](const Node& a, const Node& b) { return a.value < b.value; });
  result.found = true;
  result.x = nodes[0].x;
  result.value = nodes[0].value;
  static const double kDirections[8][2] = {{1, 0}, {-1, 0}, {0, 1}, {0, -1}, {1, 1}, {1, -1}, {-1, 1}, {-1, -1}};
  for (std::size_t s = 0; s < starts; ++s) {
    Point2 x = nodes[s].x;
    double fx = nodes[s].value;
    for (double step = 1.0 / (n - 1); step > 1e-4;) {
      bool moved = false;
      for (const auto& d : kDirections) {
        const Point2 y{x[0] + step * d[0], x[1] + step * d[1]};
        if (!allowed(y, evaluated, options.exclusion)) continue;
        const double fy = f(y);
        if (fy < fx) {
          x = y;
          fx = fy;
          moved = true;
          break;
        }
      }
      if (!moved) step *= 0.5;
    }
    if (fx < result.value) {
      result.x = x;
      result.value = fx;
    }
  }
  return result;
}

}  // namespace millsim::calib
