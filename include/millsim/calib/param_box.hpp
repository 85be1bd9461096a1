#pragma once
// The search box in physical units and its map to the unit square, where the surrogates and the
// proposal search work (so a length scale or an exclusion radius means the same fraction of
// either range).
#include <array>

namespace millsim::calib {

using Point2 = std::array<double, 2>;  // (e, mu) or, in unit coordinates, (u, v) in [0, 1]^2

struct ParamBox {
  double e_min = 0.30, e_max = 0.55;    // restitution range (paper section 3.9)
  double mu_min = 0.30, mu_max = 0.70;  // kinetic friction range (paper section 3.9)

  Point2 toUnit(double e, double mu) const {
    return {(e - e_min) / (e_max - e_min), (mu - mu_min) / (mu_max - mu_min)};
  }
  Point2 fromUnit(const Point2& u) const { return {e_min + u[0] * (e_max - e_min), mu_min + u[1] * (mu_max - mu_min)}; }
};

}  // namespace millsim::calib
