#pragma once
// Time-step limits of the two diffusion terms of the SPH equations for the explicit integrators:
// the laminar viscosity (Lo & Shao, viscosity.hpp) and the density diffusion (Molteni,
// Fourtakas: density_diffusion.hpp). Host side, evaluated once per set-up.
//
// Both are linear in what they diffuse. The viscous term, dv_a/dt = -sum_b 2 nu V_b |fac_ab|
// r^2/(r^2 + eta^2) v_ab (rho_a = rho_b), makes a lattice mode exp(i k.x) decay at
//   lambda(k) = nu sum_b 2 V_b |fac(r_b)| r_b^2/(r_b^2 + eta^2) (1 - cos k.r_b) = nu rate(k),
// and the density diffusion, with its coefficient 2 delta h c0 in place of 4 nu / 2, at
// delta h c0 rate(k). latticeDiffusionRate returns max_k rate(k) over the Brillouin zone
// (Wendland, h = sqrt(2) dp, 2D: 6.31 / h^2; h = 0.8 sqrt(3) dp, 3D: 6.69 / h^2).
// The central form of the viscous term (laminar_central) couples the components: the mode decays
// at nu times the largest eigenvalue of sum_b xi/2 V_b |fac| (r_b r_b^T / (r_b^2 + eta^2))
// (1 - cos k.r_b), xi = 2 (d + 2); longitudinal modes are the fast ones (3 nu k^2 for long
// waves), so its rate is about three times the scalar one.
// An integrator is stable for a mode while mu = lambda dt stays below its limit:
//   - symplectic (predictor-corrector, v_(n+1) = (1 - mu + mu^2/2) v_n): mu <= 2;
//   - Verlet: the leap-frog v_(n+1) = v_(n-1) - 2 mu v_n has a parasitic root of modulus
//     1 + mu, which only the Euler step every Ns steps holds back: stable for mu <= 0.1353 at
//     Ns = 40 (verletDiffusionLimit, from the spectral radius of the Ns-step cycle), 15 times
//     tighter than the symplectic scheme.
// The CFL step of the paper (eq. 40, dt = CFL h / c0) has neither term. For the viscosity that
// leaves a run with a large nu past the limit (tests/validation/test_sph_spin_up.cpp, 2D,
// Verlet: stable at mu = 0.12, growing noise at 0.137, thousands of particles out of the
// density bounds at 0.36). For the density diffusion mu = delta rate h^2 CFL whatever h and c0:
// 0.126 (2D) and 0.134 (3D) at the paper's delta = 0.1, CFL = 0.2, 0.93 and 0.99 of the Verlet
// limit; delta = 0.15 blew the 2D hydrostatic column up within 0.03 s (docs/validation.md).
#include <algorithm>
#include <array>
#include <cmath>
#include <complex>
#include <string>
#include <vector>

#include "millsim/core/error.hpp"

namespace millsim::sph {

// Largest eigenvalue of a symmetric 3x3 matrix (xx, yy, zz, xy, xz, yz), by the trigonometric
// solution of its characteristic cubic.
inline double largestEigenvalue(const std::array<double, 6>& m) {
  const double p1 = m[3] * m[3] + m[4] * m[4] + m[5] * m[5];
  if (p1 == 0) return std::max({m[0], m[1], m[2]});
  const double q = (m[0] + m[1] + m[2]) / 3;
  const double a = m[0] - q, b = m[1] - q, c = m[2] - q;
  const double p = std::sqrt((a * a + b * b + c * c + 2 * p1) / 6);
  // det((M - qI) / p) / 2, clamped to [-1, 1] against round-off.
  const double det = a * (b * c - m[5] * m[5]) - m[3] * (m[3] * c - m[5] * m[4]) + m[4] * (m[3] * m[5] - b * m[4]);
  const double r = std::clamp(det / (2 * p * p * p), -1.0, 1.0);
  return q + 2 * p * std::cos(std::acos(r) / 3);
}

template <class Kernel>
double latticeDiffusionRate(const Kernel& kernel, int dim, double h, double dp, double eta2, bool central = false) {
  struct Offset {
    double x, y, z, w;
  };
  const int n = static_cast<int>(std::ceil(2 * h / dp));
  const int nz = dim == 3 ? n : 0;
  std::vector<Offset> neighbours;  // every lattice neighbour within the support: none may be left out
  for (int k = -nz; k <= nz; ++k)
    for (int j = -n; j <= n; ++j)
      for (int i = -n; i <= n; ++i) {
        const double x = i * dp, y = j * dp, z = k * dp, r2 = x * x + y * y + z * z;
        if (r2 <= 0 || r2 >= 4 * h * h) continue;
        const double fac = std::abs(double(kernel.fac(static_cast<decltype(kernel.h)>(std::sqrt(r2)))));
        neighbours.push_back({x, y, z, 2 * std::pow(dp, dim) * fac * r2 / (r2 + eta2)});
      }
  const double xi = 2.0 * (dim + 2);
  // The neighbour set is symmetric in each axis, so k in [0, pi/dp]^dim covers the zone.
  const int steps = 24;
  const double pi = std::acos(-1.0), dk = pi / dp / steps;
  double best = 0;
  for (int c = 0; c <= (dim == 3 ? steps : 0); ++c)
    for (int b = 0; b <= steps; ++b)
      for (int a = 0; a <= steps; ++a) {
        double rate = 0;
        std::array<double, 6> m{};  // the central form's matrix
        for (const Offset& o : neighbours) {
          const double d = o.w * (1 - std::cos(dk * (a * o.x + b * o.y + c * o.z)));
          if (!central) {
            rate += d;
            continue;
          }
          const double s = 0.5 * xi * d / (o.x * o.x + o.y * o.y + o.z * o.z);
          m[0] += s * o.x * o.x;
          m[1] += s * o.y * o.y;
          m[2] += s * o.z * o.z;
          m[3] += s * o.x * o.y;
          m[4] += s * o.x * o.z;
          m[5] += s * o.y * o.z;
        }
        best = std::max(best, central ? largestEigenvalue(m) : rate);
      }
  return best;
}

// Largest mu = lambda dt for which the Verlet cycle (ns - 1 leap-frog steps and one Euler step)
// does not grow a decaying mode dv/dt = -lambda v (ns >= 1; leap-frog alone, with no Euler
// step, is unstable for any mu > 0).
inline double verletDiffusionLimit(int ns) {
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

// The step limits of one set-up: the laminar viscosity's (nu > 0) at kViscousDtMargin of its
// stability limit, for the particle disorder the lattice estimate does not see; the density
// diffusion's (delta > 0) at the limit itself, so the paper's settings (0.99 of it in 3D, run
// for years in DualSPHysics) keep their CFL step. Infinite for a term that is off.
inline constexpr double kViscousDtMargin = 0.7;
struct DiffusionDtLimits {
  double viscous = INFINITY, ddt = INFINITY;
};
template <class Kernel>
DiffusionDtLimits diffusionDtLimits(const Kernel& kernel, int dim, double h, double dp, double eta2, double nu,
                                    double ddt_delta, double c0, bool symplectic, int verlet_steps,
                                    bool central_viscosity = false) {
  DiffusionDtLimits l;
  if (nu <= 0 && ddt_delta <= 0) return l;
  if (!symplectic && verlet_steps <= 0)
    throw core::InputError(
        "sph: Verlet without Euler steps (verlet_steps = 0) is unstable with the laminar "
        "viscosity or density diffusion for any time step; set verlet_steps (DualSPHysics: 40) "
        "or use the symplectic integrator");
  const double mu = symplectic ? 2.0 : verletDiffusionLimit(verlet_steps);
  const double rate = latticeDiffusionRate(kernel, dim, h, dp, eta2);
  if (nu > 0)
    l.viscous = kViscousDtMargin * mu /
                (nu * (central_viscosity ? latticeDiffusionRate(kernel, dim, h, dp, eta2, true) : rate));
  if (ddt_delta > 0) l.ddt = mu / (ddt_delta * h * c0 * rate);
  return l;
}

}  // namespace millsim::sph
