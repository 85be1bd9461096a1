#include "dem/charge.hpp"

#include <algorithm>
#include <cmath>
#include <random>
#include <unordered_map>

namespace millsim::dem {

std::vector<BallClass> bondClasses(double top, double min_size, double step, double exponent) {
  std::vector<BallClass> classes;
  const int n = static_cast<int>(std::floor((top - min_size) / step + 1e-9)) + 1;
  double below = 0.0;
  for (int i = 0; i < n; ++i) {
    const double x = min_size + i * step;
    const double y = std::pow(std::min(x / top, 1.0), exponent);
    classes.push_back({x, y - below, 0});
    below = y;
  }
  // Renormalise in case the top class is not exactly `top` (rounding of the step).
  double total = 0.0;
  for (auto& c : classes) total += c.mass_fraction;
  for (auto& c : classes) c.mass_fraction /= total;
  return classes;
}

void fillCounts(std::vector<BallClass>& classes, double volume) {
  for (auto& c : classes) {
    const double v = std::acos(-1.0) / 6.0 * c.diameter * c.diameter * c.diameter;
    c.count = static_cast<int>(std::lround(c.mass_fraction * volume / v));
  }
}

namespace {

// Hash grid of already placed balls so each overlap test looks at nearby cells only.
class PlacementGrid {
 public:
  explicit PlacementGrid(double cell) : m_cell(cell) {}
  bool fits(double x, double y, double z, double r, const Placement& p) const {
    const long cx = idx(x), cy = idx(y), cz = idx(z);
    for (long i = cx - 1; i <= cx + 1; ++i)
      for (long j = cy - 1; j <= cy + 1; ++j)
        for (long k = cz - 1; k <= cz + 1; ++k) {
          auto it = m_cells.find(key(i, j, k));
          if (it == m_cells.end()) continue;
          for (int b : it->second) {
            const double dx = x - p.pos[3 * b], dy = y - p.pos[3 * b + 1], dz = z - p.pos[3 * b + 2];
            const double reach = r + p.radius[b];
            if (dx * dx + dy * dy + dz * dz < reach * reach) return false;
          }
        }
    return true;
  }
  void add(double x, double y, double z, int ball) { m_cells[key(idx(x), idx(y), idx(z))].push_back(ball); }

 private:
  long idx(double v) const { return static_cast<long>(std::floor(v / m_cell)); }
  static long long key(long i, long j, long k) { return ((i + 4096) * 8192LL + (j + 4096)) * 8192LL + (k + 4096); }
  double m_cell;
  std::unordered_map<long long, std::vector<int>> m_cells;
};

}  // namespace

bool placeBalls(const std::vector<BallClass>& classes, double radius, double length, std::uint64_t seed,
                Placement& out) {
  std::vector<double> radii;
  for (const auto& c : classes)
    for (int k = 0; k < c.count; ++k) radii.push_back(0.5 * c.diameter);
  std::sort(radii.begin(), radii.end(), std::greater<>());
  const double r_max = radii.empty() ? 0.0 : radii.front();
  PlacementGrid grid(2.0 * r_max);
  std::mt19937_64 rng(seed);
  std::uniform_real_distribution<double> u01(0.0, 1.0);
  out.pos.clear();
  out.radius.clear();
  constexpr int kAttempts = 20000;
  for (double r : radii) {
    const double rc = radius - r, zlo = r, zhi = length - r;
    if (rc <= 0 || zhi <= zlo) return false;
    bool placed = false;
    for (int a = 0; a < kAttempts && !placed; ++a) {
      // Uniform in the disc: radius ~ sqrt(u).
      const double rr = rc * std::sqrt(u01(rng)), th = 2.0 * std::acos(-1.0) * u01(rng);
      const double x = rr * std::cos(th), y = rr * std::sin(th), z = zlo + (zhi - zlo) * u01(rng);
      if (!grid.fits(x, y, z, r, out)) continue;
      grid.add(x, y, z, static_cast<int>(out.radius.size()));
      out.pos.insert(out.pos.end(), {x, y, z});
      out.radius.push_back(r);
      placed = true;
    }
    if (!placed) return false;
  }
  return true;
}

}  // namespace millsim::dem
