#include "millsim/sim/martin_moyce.hpp"

#include <algorithm>
#include <cmath>
#include <limits>

namespace millsim::sim {
namespace {

// Linear interpolation of Z/a at dimensionless time T; NaN outside the run.
double frontAt(const std::vector<double>& T, const std::vector<double>& z, double t) {
  if (T.empty() || t < T.front() || t > T.back()) return std::numeric_limits<double>::quiet_NaN();
  const auto it = std::lower_bound(T.begin(), T.end(), t);
  const std::size_t i = static_cast<std::size_t>(it - T.begin());
  if (i == 0) return z[0];
  const double w = (t - T[i - 1]) / (T[i] - T[i - 1]);
  return z[i - 1] + w * (z[i] - z[i - 1]);
}

}  // namespace

FrontComparison compareWithMartinMoyce(const std::vector<double>& time_s, const std::vector<double>& front_m,
                                       double a, double g, double t_max, double min_T) {
  const double scale = std::sqrt(2 * g / a);
  std::vector<double> T(time_s.size()), z(front_m.size());
  for (std::size_t i = 0; i < T.size(); ++i) {
    T[i] = time_s[i] * scale;
    z[i] = front_m[i] / a;
  }
  FrontComparison c;
  auto errors = [&](double shift, double from) {
    std::vector<double> e;
    for (const FrontPoint& p : martinMoyceFront()) {
      if (p.T > t_max + 1e-9 || p.T < from) continue;
      e.push_back((frontAt(T, z, p.T - shift) - p.z_over_a) / p.z_over_a);
    }
    return e;
  };
  auto stats = [](const std::vector<double>& e, double& max_abs, double& mean_abs) {
    max_abs = 0;
    mean_abs = 0;
    for (double v : e) {
      max_abs = std::max(max_abs, std::abs(v));
      mean_abs += std::abs(v) / double(e.size());
    }
    if (e.empty() || std::isnan(max_abs)) max_abs = mean_abs = std::numeric_limits<double>::quiet_NaN();
  };
  c.errors_raw = errors(0, 0);
  stats(c.errors_raw, c.max_error_raw, c.mean_error_raw);
  double best = std::numeric_limits<double>::infinity();
  for (int k = 0; k <= 300; ++k) {  // T0 in [0, 0.3] by 0.001
    const double shift = 0.001 * k;
    double sse = 0;
    for (double v : errors(shift, min_T)) sse += v * v;
    if (sse < best) {
      best = sse;
      c.shift_T = shift;
    }
  }
  c.errors_shifted = errors(c.shift_T, min_T);
  stats(c.errors_shifted, c.max_error_shifted, c.mean_error_shifted);
  c.points = static_cast<int>(c.errors_raw.size());
  return c;
}

}  // namespace millsim::sim
