#pragma once
// Time-step limit of the laminar viscous term (Lo & Shao, viscosity.hpp) for the explicit
// integrators. Host side, evaluated once per set-up.
//
// The term is linear in the velocities: dv_a/dt = -sum_b 2 nu V_b |fac_ab| r^2/(r^2 + eta^2) v_ab
// (rho_a = rho_b). On the lattice of spacing dp a velocity mode exp(i k.x) decays at
//   lambda(k) = nu sum_b 2 V_b |fac(r_b)| r_b^2/(r_b^2 + eta^2) (1 - cos k.r_b),
// largest for the shortest waves; laminarRateMax returns max_k lambda(k) / nu over the
// Brillouin zone (Wendland, h = sqrt(2) dp, 2D: 6.31 / h^2; h = 0.8 sqrt(3) dp, 3D: 6.69 / h^2).
// An integrator is stable for that mode while mu = lambda dt stays below its limit:
//   - symplectic (predictor-corrector, v_(n+1) = (1 - mu + mu^2/2) v_n): mu <= 2;
//   - Verlet: the leap-frog v_(n+1) = v_(n-1) - 2 mu v_n has a parasitic root of modulus
//     1 + mu, which only the Euler step every Ns steps holds back: stable for mu <= 0.1353 at
//     Ns = 40 (verletViscousLimit, from the spectral radius of the Ns-step cycle), 15 times
//     tighter than the symplectic scheme.
// Measured (tests/validation/test_sph_spin_up.cpp, 2D, Verlet): stable at mu = 0.12, growing
// noise at 0.137 (1.01 x the limit), thousands of particles out of the density bounds at 0.36. The CFL condition
// of the paper (eq. 40) has no viscous term, so a run with a large nu can sit past the limit.
#include <algorithm>
#include <cmath>
#include <complex>

#include "millsim/core/error.hpp"

namespace millsim::sph {

template <class Kernel>
double laminarRateMax(const Kernel& kernel, int dim, double h, double dp, double eta2) {
  struct Offset {
    double x, y, z, w;
  };
  const int n = static_cast<int>(std::ceil(2 * h / dp));
  const int nz = dim == 3 ? n : 0;
  Offset neighbours[4096];
  int count = 0;
  for (int k = -nz; k <= nz; ++k)
    for (int j = -n; j <= n; ++j)
      for (int i = -n; i <= n; ++i) {
        const double x = i * dp, y = j * dp, z = k * dp, r2 = x * x + y * y + z * z;
        if (r2 <= 0 || r2 >= 4 * h * h || count == 4096) continue;
        const double fac = std::abs(double(kernel.fac(static_cast<decltype(kernel.h)>(std::sqrt(r2)))));
        neighbours[count++] = {x, y, z, 2 * std::pow(dp, dim) * fac * r2 / (r2 + eta2)};
      }
  // The neighbour set is symmetric in each axis, so k in [0, pi/dp]^dim covers the zone.
  const int steps = 24;
  const double pi = std::acos(-1.0), dk = pi / dp / steps;
  double best = 0;
  for (int c = 0; c <= (dim == 3 ? steps : 0); ++c)
    for (int b = 0; b <= steps; ++b)
      for (int a = 0; a <= steps; ++a) {
        double rate = 0;
        for (int q = 0; q < count; ++q) {
          const Offset& o = neighbours[q];
          rate += o.w * (1 - std::cos(dk * (a * o.x + b * o.y + c * o.z)));
        }
        best = std::max(best, rate);
      }
  return best;
}

// Largest mu = lambda dt for which the Verlet cycle (ns - 1 leap-frog steps and one Euler step)
// does not grow a decaying mode dv/dt = -lambda v (ns >= 1; leap-frog alone, with no Euler
// step, is unstable for any mu > 0).
inline double verletViscousLimit(int ns) {
  auto radius = [ns](double mu) {
    // State (v_n, v_(n-1)); Euler: v_(n+1) = (1 - mu) v_n; leap-frog: v_(n+1) = v_(n-1) - 2 mu v_n.
    double m[2][2] = {{1 - mu, 0}, {1, 0}};
    for (int s = 1; s < ns; ++s) {
      const double a = -2 * mu * m[0][0] + m[1][0], b = -2 * mu * m[0][1] + m[1][1];
      m[1][0] = m[0][0];
      m[1][1] = m[0][1];
      m[0][0] = a;
      m[0][1] = b;
    }
    const double tr = m[0][0] + m[1][1], det = m[0][0] * m[1][1] - m[0][1] * m[1][0];
    const std::complex<double> disc = std::sqrt(std::complex<double>(tr * tr - 4 * det));
    return std::max(std::abs(0.5 * (tr + disc)), std::abs(0.5 * (tr - disc)));
  };
  // Stable from mu = 0 up to the limit: walk up in 1% steps to the first growth, then bisect.
  double lo = 1e-6, hi = lo;
  while (hi < 2 && radius(hi) <= 1 + 1e-12) {
    lo = hi;
    hi *= 1.01;
  }
  for (int it = 0; it < 40; ++it) {
    const double mid = 0.5 * (lo + hi);
    (radius(mid) <= 1 + 1e-12 ? lo : hi) = mid;
  }
  return lo;
}

// Stability limit of the time step for a laminar viscosity nu, times kViscousDtMargin for the
// particle disorder the lattice estimate does not see. Infinite when nu = 0.
inline constexpr double kViscousDtMargin = 0.7;
template <class Kernel>
double laminarDtLimit(const Kernel& kernel, int dim, double h, double dp, double eta2, double nu, bool symplectic,
                      int verlet_steps) {
  if (nu <= 0) return INFINITY;
  if (!symplectic && verlet_steps <= 0)
    throw core::InputError(
        "sph: Verlet without Euler steps (verlet_steps = 0) is unstable with the laminar "
        "viscosity for any time step; set verlet_steps (DualSPHysics: 40) or use the symplectic "
        "integrator");
  const double mu = symplectic ? 2.0 : verletViscousLimit(verlet_steps);
  return kViscousDtMargin * mu / (nu * laminarRateMax(kernel, dim, h, dp, eta2));
}

}  // namespace millsim::sph
