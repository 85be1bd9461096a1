#pragma once
// Martin & Moyce (1952) dam break, column width a, height 2a (n^2 = 2): surge front Z/a against
// T = t sqrt(2 g / a) (shared/reference/sph.md, from M&M's tables as copied in pysph's
// db_exp_data.py), and the comparison of a run's front with it.
//
// The experiment's time origin is uncertain (the column was released by removing a gate, which
// takes a few milliseconds); comparisons in the SPH literature often shift the simulated time
// by a fitted origin. frontError() reports both: raw, and with the least-squares origin T0 in
// [0, 0.3] (t0 < 16 ms for a = 57 mm) over the points T0 >= min_T.
#include <vector>

namespace millsim::sim {

struct FrontPoint {
  double T, z_over_a;
};

inline const std::vector<FrontPoint>& martinMoyceFront() {
  static const std::vector<FrontPoint> kData = {
      {0.41, 1.11}, {0.84, 1.22}, {1.19, 1.44}, {1.43, 1.67}, {1.63, 1.89}, {1.83, 2.11}, {1.98, 2.33}, {2.20, 2.56},
      {2.32, 2.78}, {2.51, 3.00}, {2.65, 3.22}, {2.83, 3.44}, {2.98, 3.67}, {3.11, 3.89}, {3.33, 4.11}};
  return kData;
}

struct FrontComparison {
  double max_error_raw = 0;   // max |Z_sim - Z_data| / Z_data over the data with T <= t_max
  double mean_error_raw = 0;
  double shift_T = 0;         // fitted time origin (dimensionless)
  double max_error_shifted = 0;  // over the data with min_T <= T <= t_max, simulated T shifted
  double mean_error_shifted = 0;
  std::vector<double> errors_raw, errors_shifted;  // signed, per data point used
  int points = 0;
};

// times (s) and front positions (m, from the column's back wall) of a run; a in m.
FrontComparison compareWithMartinMoyce(const std::vector<double>& time_s, const std::vector<double>& front_m,
                                       double a, double g, double t_max = 2.5, double min_T = 0.8);

}  // namespace millsim::sim
