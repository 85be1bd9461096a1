#pragma once
// Density diffusion terms added to the continuity equation of fluid particle a (paper eqs.
// 17-20; shared/reference/sph.md), for fluid-fluid pairs (DualSPHysics "DDT2Full": pairs with
// boundary particles get none). With r_ab = r_a - r_b and grad_a W_ab = fac r_ab:
//
//   D_a = -2 delta h c0 sum_b psi_ab fac r^2 / (r^2 + eta^2) V_b,
//   Molteni & Colagrossi 2009:  psi_ab = rho_b - rho_a
//   Fourtakas et al. 2019:      psi_ab = (rho_b - rho_a) - rho^H_ab,
//                               rho^H_ab = rho0 [(1 + rho0 |g| (z_a - z_b) / B)^(1/gamma) - 1]
//
// (fac < 0, so D_a moves rho_a towards its neighbours: a Brookshaw Laplacian.) Fourtakas takes
// out the hydrostatic density difference, so a fluid at rest under gravity gets D_a = 0 and
// DDT does not pull a tall column towards uniform density. z is the height along -g.
// The paper writes eq. 18/19 with the opposite sign convention of r_ab; the sign here is the
// one for which a density bump decays (tested). delta: 0.1 by default (DualSPHysics).
#include <cmath>

#include "millsim/core/hd.hpp"

namespace millsim::sph {

struct DdtNone {
  static constexpr const char* kName = "none";
  static constexpr bool kActive = false;
  template <class T>
  MILLSIM_HD T operator()(T, T, T, T, T, T) const {
    return T(0);
  }
};

template <class T>
struct DdtMolteni2009 {
  static constexpr const char* kName = "molteni";
  static constexpr bool kActive = true;
  T coef = 0;  // 2 delta h c0
  T eta2 = 0;
  // Contribution of neighbour b to drho_a/dt.
  MILLSIM_HD MILLSIM_FORCE_INLINE T operator()(T rho_a, T rho_b, T /*height_ab*/, T r2, T fac, T vol_b) const {
    return -coef * (rho_b - rho_a) * fac * r2 / (r2 + eta2) * vol_b;
  }
};

template <class T>
struct DdtFourtakas2019 {
  static constexpr const char* kName = "fourtakas";
  static constexpr bool kActive = true;
  T coef = 0;  // 2 delta h c0
  T eta2 = 0;
  T rho0 = 0;
  T gz = 0;  // rho0 |g| / B
  T inv_gamma = 0;
  // (1 + x)^(1/gamma) - 1 by its Taylor series to x^3: x = rho0 g dz / B is below ~1e-3 over a
  // kernel support (density varies by ~1% over the whole fluid depth), the x^4 term is ~0.03 x^4
  // (1e-9 relative, 1e-10 kg/m3), and pow() per pair was 30% of the interaction time.
  MILLSIM_HD MILLSIM_FORCE_INLINE T operator()(T rho_a, T rho_b, T height_ab, T r2, T fac, T vol_b) const {
    const T x = gz * height_ab;
    const T a = inv_gamma;
    const T rho_h = rho0 * a * x * (T(1) + (a - T(1)) * x * (T(0.5) + (a - T(2)) * x * (T(1) / T(6))));
    return -coef * ((rho_b - rho_a) - rho_h) * fac * r2 / (r2 + eta2) * vol_b;
  }
};

}  // namespace millsim::sph
