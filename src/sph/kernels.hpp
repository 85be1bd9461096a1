#pragma once
// SPH smoothing kernels, support 2h, q = r / h (paper eqs. 6-7; normalisations from
// shared/reference/sph.md, which corrects the Wendland constants the paper prints).
//
//   Wendland C2:  W = a_d (1 - q/2)^4 (2q + 1),   a_2 = 7 / (4 pi h^2),  a_3 = 21 / (16 pi h^3)
//   cubic spline: W = a_d (1 - 3/2 q^2 + 3/4 q^3) for q <= 1,  a_d / 4 (2 - q)^3 for 1 < q <= 2,
//                 a_2 = 10 / (7 pi h^2),  a_3 = 1 / (pi h^3)
//
// Gradients are returned as `fac` with grad_a W_ab = fac * (r_a - r_b) (fac < 0), the form every
// pair term uses. Both functions assume r < 2h: the caller tests the support once per pair.
// Units: h in m; W in 1/m^Dim; fac in 1/m^(Dim+2).
#include <cmath>

#include "millsim/core/hd.hpp"

namespace millsim::sph {

template <int Dim, class T>
struct WendlandC2 {
  static constexpr const char* kName = "wendland";
  T h = 0, inv_h = 0, a_d = 0, b = 0;  // b = -5 a_d / h^2

  static WendlandC2 make(double h) {
    const double pi = std::acos(-1.0);
    const double a = Dim == 2 ? 7.0 / (4.0 * pi * h * h) : 21.0 / (16.0 * pi * h * h * h);
    return {T(h), T(1.0 / h), T(a), T(-5.0 * a / (h * h))};
  }
  MILLSIM_HD T w(T r) const {
    const T q = r * inv_h;
    const T s = T(1) - T(0.5) * q;
    const T s2 = s * s;
    return a_d * s2 * s2 * (T(2) * q + T(1));
  }
  MILLSIM_HD MILLSIM_FORCE_INLINE T fac(T r) const {
    const T s = T(1) - T(0.5) * r * inv_h;
    return b * s * s * s;
  }
};

template <int Dim, class T>
struct CubicSpline {
  static constexpr const char* kName = "cubic";
  T h = 0, inv_h = 0, a_d = 0, inv_h2 = 0;

  static CubicSpline make(double h) {
    const double pi = std::acos(-1.0);
    const double a = Dim == 2 ? 10.0 / (7.0 * pi * h * h) : 1.0 / (pi * h * h * h);
    return {T(h), T(1.0 / h), T(a), T(1.0 / (h * h))};
  }
  MILLSIM_HD T w(T r) const {
    const T q = r * inv_h;
    if (q <= T(1)) return a_d * (T(1) - T(1.5) * q * q + T(0.75) * q * q * q);
    const T s = T(2) - q;
    return T(0.25) * a_d * s * s * s;
  }
  // dW/dr / r = (dW/dq) / (h^2 q).
  MILLSIM_HD MILLSIM_FORCE_INLINE T fac(T r) const {
    const T q = r * inv_h;
    if (q <= T(1)) return a_d * inv_h2 * (T(-3) + T(2.25) * q);
    const T s = T(2) - q;
    return T(-0.75) * a_d * inv_h2 * s * s / q;
  }
};

}  // namespace millsim::sph
