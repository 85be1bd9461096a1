#pragma once
// Tait equation of state (paper eq. 28):  P = B ((rho / rho0)^gamma - 1),  B = c0^2 rho0 / gamma.
// c0 is the numerical speed of sound. millsim follows DualSPHysics's rule (the paper's code):
//   c0 = coefsound * sqrt(|g| * hswl),
// hswl the still-water height (by default the height of the fluid at the start), coefsound 20
// by default, so c0 >= 10 sqrt(g H0) as the paper asks (density varies by about 1%).
// Units: rho in kg/m^3, P in Pa, c0 in m/s. gamma = 7 for water-like liquids.
#include <cmath>

#include "millsim/core/hd.hpp"

namespace millsim::sph {

template <class T>
struct TaitEos {
  T rho0 = 1000, b = 0, gamma = 7, inv_rho0 = 0.001;

  static TaitEos make(double rho0, double c0, double gamma) {
    return {T(rho0), T(c0 * c0 * rho0 / gamma), T(gamma), T(1.0 / rho0)};
  }
  MILLSIM_HD T pressure(T rho) const {
    const T x = rho * inv_rho0;
    if (gamma == T(7)) {  // the usual case without pow: x^7 = x^4 x^2 x
      const T x2 = x * x;
      return b * (x2 * x2 * x2 * x - T(1));
    }
    return b * (std::pow(x, gamma) - T(1));
  }
  // Density at which the pressure is p (the inverse), for hydrostatic initial states.
  MILLSIM_HD T density(T p) const { return rho0 * std::pow(T(1) + p / b, T(1) / gamma); }
};

}  // namespace millsim::sph
