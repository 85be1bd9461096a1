// SPH building blocks against hand computations and integrals: kernel normalisation and
// gradients, lattice sums, the Tait EOS, the density diffusion terms (sign, hydrostatic zero),
// artificial viscosity and the SPS stress.
#include <gtest/gtest.h>

#include <cmath>
#include <utility>

#include "sph/density_diffusion.hpp"
#include "sph/diffusion_stability.hpp"
#include "sph/eos.hpp"
#include "sph/kernels.hpp"
#include "sph/viscosity.hpp"

namespace millsim {
namespace {

using core::Vec3;
const double kPi = std::acos(-1.0);

// Integral of W over its support by the midpoint rule in r (radial shells): 2 pi r dr (2D),
// 4 pi r^2 dr (3D). 20 000 shells: the rule's error is ~1e-9.
template <class K>
double integral(const K& k, int dim) {
  const int n = 20000;
  const double r_max = 2 * double(k.h), dr = r_max / n;
  double sum = 0;
  for (int i = 0; i < n; ++i) {
    const double r = (i + 0.5) * dr;
    sum += double(k.w(r)) * (dim == 2 ? 2 * kPi * r : 4 * kPi * r * r) * dr;
  }
  return sum;
}

template <class K>
void checkKernel(const K& k, int dim) {
  EXPECT_NEAR(integral(k, dim), 1.0, 1e-6);
  EXPECT_NEAR(double(k.w(2 * double(k.h) * (1 - 1e-12))), 0.0, 1e-9 * double(k.w(0)));
  // Gradient: fac r = dW/dr, against a central difference (step 1e-6 h: error ~1e-10 relative).
  for (double q : {0.1, 0.5, 0.99, 1.01, 1.5, 1.9}) {
    const double r = q * double(k.h), e = 1e-6 * double(k.h);
    const double fd = (double(k.w(r + e)) - double(k.w(r - e))) / (2 * e);
    EXPECT_NEAR(double(k.fac(r)) * r, fd, 1e-6 * std::abs(fd)) << "q = " << q;
  }
}

TEST(SphKernels, NormalisedWithExactGradients) {
  const double h = 0.013;
  checkKernel(sph::WendlandC2<2, double>::make(h), 2);
  checkKernel(sph::WendlandC2<3, double>::make(h), 3);
  checkKernel(sph::CubicSpline<2, double>::make(h), 2);
  checkKernel(sph::CubicSpline<3, double>::make(h), 3);
}

// On a square lattice of spacing dp with h = coefh dp sqrt(2), sum_b V_b W_ab ~ 1 (the discrete
// partition of unity: within 2% for h/dp = 1.2-1.5, shared/reference/sph.md) and
// sum_b V_b grad W_ab = 0 by symmetry.
template <class K>
void latticeSums(const K& k, double dp) {
  double sum = 0, gx = 0, gy = 0;
  for (int i = -10; i <= 10; ++i)
    for (int j = -10; j <= 10; ++j) {
      const Vec3<double> r_ab{-i * dp, -j * dp, 0};
      const double r = std::sqrt(core::norm2(r_ab));
      if (r >= 2 * double(k.h)) continue;
      sum += dp * dp * double(k.w(r));
      if (r > 0) {
        gx += dp * dp * double(k.fac(r)) * r_ab.x;
        gy += dp * dp * double(k.fac(r)) * r_ab.y;
      }
    }
  EXPECT_NEAR(sum, 1.0, 0.02);
  EXPECT_NEAR(gx, 0.0, 1e-9 / dp);
  EXPECT_NEAR(gy, 0.0, 1e-9 / dp);
}

TEST(SphKernels, LatticePartitionOfUnity) {
  const double dp = 0.01, h = dp * std::sqrt(2.0);  // coefh = 1 in 2D
  latticeSums(sph::WendlandC2<2, double>::make(h), dp);
  latticeSums(sph::CubicSpline<2, double>::make(h), dp);
}

TEST(SphEos, TaitPressureAndItsInverse) {
  const auto eos = sph::TaitEos<double>::make(1000.0, 30.0, 7.0);
  EXPECT_DOUBLE_EQ(eos.b, 30.0 * 30.0 * 1000.0 / 7.0);
  EXPECT_DOUBLE_EQ(eos.pressure(1000.0), 0.0);
  EXPECT_NEAR(eos.pressure(1010.0), eos.b * (std::pow(1.01, 7) - 1), 1e-9 * eos.b);
  EXPECT_NEAR(eos.density(eos.pressure(1013.7)), 1013.7, 1e-9);
  // Speed of sound: dP/drho at rho0 = c0^2.
  const double e = 1e-4;
  EXPECT_NEAR((eos.pressure(1000 + e) - eos.pressure(1000 - e)) / (2 * e), 900.0, 1e-4);
}

TEST(SphDensityDiffusion, FourtakasRemovesTheHydrostaticDifference) {
  // Two particles dz = 2 mm apart in a column at rest, 0.3 m deep: the lower is denser by the
  // Tait hydrostatic increment (0.022 kg/m3). Molteni's term diffuses that real difference away;
  // Fourtakas's takes out rho0 [(1 + rho0 g dz / B)^(1/gamma) - 1], the increment measured from
  // the free surface, which differs from the local one by the factor (1 + P/B)^(1/gamma - 1)
  // (DualSPHysics's form, as in the paper): it takes out 1.9% too much here, leaving -1.9% of
  // Molteni's term.
  const double rho0 = 1000, c0 = 30, gamma = 7, g = 9.81, h = 0.005;
  const auto eos = sph::TaitEos<double>::make(rho0, c0, gamma);
  const double coef = 2 * 0.1 * h * c0, eta2 = 0.01 * h * h;
  sph::DdtFourtakas2019<double> fourtakas{coef, eta2, rho0, rho0 * g / eos.b, 1 / gamma};
  sph::DdtMolteni2009<double> molteni{coef, eta2};
  const double depth_a = 0.300, dz = 0.002;  // a above b
  const double rho_a = eos.density(rho0 * g * depth_a), rho_b = eos.density(rho0 * g * (depth_a + dz));
  const double r2 = dz * dz, fac = -1e7, vol = 1e-6;
  const double full = molteni(rho_a, rho_b, dz, r2, fac, vol);
  const double left = fourtakas(rho_a, rho_b, dz, r2, fac, vol);
  const double expected_ratio = std::pow(1 + rho0 * g * depth_a / eos.b, 1 / gamma - 1) - 1;
  EXPECT_NEAR(left / full, expected_ratio, 0.05 * std::abs(expected_ratio));
  EXPECT_LT(std::abs(left), 0.025 * std::abs(full));
  // At the free surface (depth 0) the hydrostatic part is taken out exactly, to the series'
  // error: the ratio is ~(1 - 1/gamma) x / 2 with x = rho0 g dz / B ~ 1.5e-4.
  const double rho_s = eos.density(rho0 * g * dz);
  EXPECT_LT(std::abs(fourtakas(rho0, rho_s, dz, r2, fac, vol)),
            1e-4 * std::abs(molteni(rho0, rho_s, dz, r2, fac, vol)));
  // The series replacing pow: (1 + x)^(1/gamma) - 1 to x^3, error ~0.03 x^4, at x = 1e-3 (a
  // kernel support in a 10 m deep column) below 1e-9 relative.
  const double x = 1e-3, a = 1 / gamma;
  const double series = a * x * (1 + (a - 1) * x * (0.5 + (a - 2) * x / 6));
  EXPECT_NEAR(series, std::pow(1 + x, a) - 1, 1e-9 * series);
}

TEST(SphDensityDiffusion, BothTermsSmoothADensityBump) {
  // fac < 0 always: a denser neighbour must raise drho_a/dt, a lighter one lower it.
  const double h = 0.005, c0 = 30;
  sph::DdtMolteni2009<double> molteni{2 * 0.1 * h * c0, 0.01 * h * h};
  sph::DdtFourtakas2019<double> fourtakas{2 * 0.1 * h * c0, 0.01 * h * h, 1000, 0.0, 1 / 7.0};  // g = 0
  const double r2 = 0.004 * 0.004, fac = -2e7, vol = 1e-5;
  EXPECT_GT(molteni(1000, 1005, 0, r2, fac, vol), 0);
  EXPECT_LT(molteni(1005, 1000, 0, r2, fac, vol), 0);
  EXPECT_GT(fourtakas(1000, 1005, 0, r2, fac, vol), 0);
  // Without gravity both are the same Laplacian.
  EXPECT_NEAR(fourtakas(1000, 1005, 0, r2, fac, vol), molteni(1000, 1005, 0, r2, fac, vol), 1e-12);
}

TEST(SphViscosity, ArtificialOpposesApproachOnly) {
  sph::ViscosityArtificial<double> visc{0.1, 0.01, 0.01, 30, 1e-6};
  const Vec3<double> r_ab{0.008, 0, 0};
  const double fac = -1e6, r2 = core::norm2(r_ab);
  const auto z = sph::zeroSym3<double>();
  // a approaches b (v_ab . r_ab < 0): a is pushed back along +x.
  const Vec3<double> approach = visc(r_ab, {-1, 0, 0}, r2, fac, 1000, 1000, 1e-4, false, z, z);
  EXPECT_GT(approach.x, 0);
  // Hand value: mu = h v.r / (r^2 + eta2), Pi = -alpha c0 mu / rho, dv = -m Pi fac r_ab.
  const double mu = 0.01 * (-0.008) / (r2 + 1e-6), pi = -0.1 * 30 * mu / 1000;
  EXPECT_NEAR(approach.x, -1e-4 * pi * fac * 0.008, 1e-12);
  EXPECT_DOUBLE_EQ(visc(r_ab, {1, 0, 0}, r2, fac, 1000, 1000, 1e-4, false, z, z).x, 0.0);
  // Walls use alpha * visco_bound_factor.
  EXPECT_NEAR(visc(r_ab, {-1, 0, 0}, r2, fac, 1000, 1000, 1e-4, true, z, z).x, 0.1 * approach.x, 1e-15);
}

// The laminar term of Lo & Shao (2002), sum_b 4 nu m_b (r_ab . grad W_ab) / ((rho_a + rho_b)
// (r^2 + eta^2)) v_ab, is the SPH form of nu lap(v). On a uniform lattice (the particle's full
// support inside it, rho = rho0) a quadratic field u = (c y^2, 0) must give nu lap(u) = (2 c nu,
// 0), and simple shear nothing. The lattice sum converges to the Laplacian as h/dp grows
// (computed independently: -2.9% at the cases' h/dp = 0.8 sqrt(2), -0.26% at 1.5, -0.08% at 2,
// -0.009% at 3, with eta = 0; eta^2 = 0.01 h^2 adds a -1.5% bias): asserted at h/dp = 2 and 3
// within 0.2% and 0.02%, which a wrong factor, density average or sign fails by far.
TEST(SphViscosity, LaminarTermConvergesToTheLaplacianOnALattice) {
  const double dp = 0.01, rho0 = 1000, m = rho0 * dp * dp, nu = 1e-3, c = 3.0;
  const auto z = sph::zeroSym3<double>();
  for (const auto& [h_over_dp, tol] : {std::pair{2.0, 0.002}, std::pair{3.0, 0.0002}}) {
    const double h = h_over_dp * dp;
    const auto k = sph::WendlandC2<2, double>::make(h);
    const sph::ViscosityLaminar<double> visc{nu, 0.0};
    for (bool quadratic : {true, false}) {
      auto u = [&](double y) { return quadratic ? c * y * y : c * y; };
      const double ya = 0.37 * dp;  // a off the lattice's symmetry lines
      Vec3<double> acc{0, 0, 0};
      const int reach = static_cast<int>(std::ceil(2 * h / dp)) + 1;
      for (int i = -reach; i <= reach; ++i)
        for (int j = -reach; j <= reach; ++j) {
          const Vec3<double> r_ab{-i * dp, -j * dp, 0};  // a at (0, ya), b at (i dp, ya + j dp)
          const double r2 = core::norm2(r_ab);
          if (r2 <= 0 || r2 >= 4 * h * h) continue;
          const Vec3<double> v_ab{u(ya) - u(ya + j * dp), 0, 0};
          acc += visc(r_ab, v_ab, r2, k.fac(std::sqrt(r2)), rho0, rho0, m, false, z, z);
        }
      const double expected = quadratic ? 2 * c * nu : 0.0;
      EXPECT_NEAR(acc.x, expected, tol * 2 * c * nu)
          << "h/dp = " << h_over_dp << (quadratic ? " quadratic" : " linear");
      EXPECT_NEAR(acc.y, 0.0, 1e-12);
    }
  }
}

// The central form (Monaghan-Cleary-Gingold, xi = 2 (d + 2)) is the SPH form of nu (lap v + 2
// grad div v). On the same lattice: shear u = (c y^2, 0) gives 2 c nu along x (div u = 0), a
// compression u = (c x^2, 0) gives 6 c nu (lap 2c plus 2 grad div = 4c), a linear field
// nothing. The square lattice's fourth moments are not isotropic, so the sums converge more
// slowly than Lo & Shao's (eta = 0; shear / compression): -4.1% / +1.3% at h/dp = 2, -0.89% /
// +0.28% at 3, -0.29% / +0.10% at 4, -0.12% / +0.04% at 5. Asserted at 3 and 5 within 1.2% and
// 0.2%: xi = 2 (d + 1) instead of 2 (d + 2) would be 25% off.
TEST(SphViscosity, LaminarCentralIsLaplacianPlusTwiceGradDiv) {
  const double dp = 0.01, rho0 = 1000, m = rho0 * dp * dp, nu = 1e-3, c = 3.0;
  const auto z = sph::zeroSym3<double>();
  for (const auto& [h_over_dp, tol] : {std::pair{3.0, 0.012}, std::pair{5.0, 0.002}}) {
    const double h = h_over_dp * dp;
    const auto k = sph::WendlandC2<2, double>::make(h);
    const sph::ViscosityLaminarCentral<double> visc{nu, 0.0, 8.0};
    // Field (u(x, y), 0): shear c y^2, compression c x^2, linear c (x + y).
    enum { kShear, kCompression, kLinear };
    for (int field : {kShear, kCompression, kLinear}) {
      auto u = [&](double x, double y) {
        return field == kShear ? c * y * y : field == kCompression ? c * x * x : c * (x + y);
      };
      const double xa = 0.21 * dp, ya = 0.37 * dp;  // a off the lattice's symmetry lines
      Vec3<double> acc{0, 0, 0};
      const int reach = static_cast<int>(std::ceil(2 * h / dp)) + 1;
      for (int i = -reach; i <= reach; ++i)
        for (int j = -reach; j <= reach; ++j) {
          const Vec3<double> r_ab{-i * dp, -j * dp, 0};
          const double r2 = core::norm2(r_ab);
          if (r2 <= 0 || r2 >= 4 * h * h) continue;
          const Vec3<double> v_ab{u(xa, ya) - u(xa + i * dp, ya + j * dp), 0, 0};
          acc += visc(r_ab, v_ab, r2, k.fac(std::sqrt(r2)), rho0, rho0, m, false, z, z);
        }
      const double expected = field == kShear ? 2 * c * nu : field == kCompression ? 6 * c * nu : 0.0;
      EXPECT_NEAR(acc.x, expected, field == kLinear ? 1e-12 : tol * expected)
          << "h/dp = " << h_over_dp << " field " << field;
      EXPECT_NEAR(acc.y, 0.0, 1e-12);
    }
  }
}

// Why the central form: its pair force lies on the line of centres (no torque on the pair, so
// the fluid's angular momentum is kept) and vanishes for a rigid rotation (v_ab = w x r_ab);
// Lo & Shao's does neither.
TEST(SphViscosity, LaminarCentralPairForceIsCentralAndRigidRotationFree) {
  const auto z = sph::zeroSym3<double>();
  const Vec3<double> r_ab{0.003, -0.001, 0.002}, w{0.5, -2.0, 1.5};
  const double r2 = core::norm2(r_ab), fac = -2e7, m = 1e-3;
  const sph::ViscosityLaminarCentral<double> central{1e-3, 0.0, 10.0};
  const sph::ViscosityLaminar<double> lo_shao{1e-3, 0.0};
  const Vec3<double> v_ab{0.2, 0.7, -0.4};
  const Vec3<double> f = central(r_ab, v_ab, r2, fac, 1000, 1000, m, false, z, z);
  EXPECT_GT(core::norm(f), 1e-3);
  EXPECT_LT(core::norm(core::cross(r_ab, f)), 1e-12 * core::norm(f) * std::sqrt(r2));
  // A rigid rotation: the central force vanishes (against its size for a motion of the same
  // speed along r_ab); Lo & Shao's is perpendicular to r_ab, a torque on the pair.
  const Vec3<double> rigid = core::cross(w, r_ab);
  const Vec3<double> along = (core::norm(rigid) / std::sqrt(r2)) * r_ab;
  EXPECT_LT(core::norm(central(r_ab, rigid, r2, fac, 1000, 1000, m, false, z, z)),
            1e-12 * core::norm(central(r_ab, along, r2, fac, 1000, 1000, m, false, z, z)));
  const Vec3<double> g = lo_shao(r_ab, rigid, r2, fac, 1000, 1000, m, false, z, z);
  EXPECT_NEAR(core::norm(core::cross(r_ab, g)), std::sqrt(r2) * core::norm(g), 1e-12 * std::sqrt(r2) * core::norm(g));
  EXPECT_GT(core::norm(g), 0.0);
}

// The central form's step limit: the largest decay rate over the zone is the largest
// eigenvalue of its mode matrix. Checked against the functor itself on the mode that has it
// for this kernel and h (Wendland, h = sqrt(2) dp, 2D): the x-polarised wave v = ((-1)^i, 0)
// at k = (pi/dp, 0), a longitudinal one: 17.48 / h^2, 2.77 times Lo & Shao's 6.31 / h^2
// (their fastest mode is the checkerboard); and the eigenvalue routine against matrices with
// known eigenvalues.
TEST(SphViscousStability, CentralRateIsTheLongitudinalRateOfTheFunctor) {
  EXPECT_NEAR(sph::largestEigenvalue({2, 3, 1, 0, 0, 0}), 3.0, 1e-12);
  // [[4, 1, 0], [1, 4, 0], [0, 0, 1]]: eigenvalues 5, 3, 1.
  EXPECT_NEAR(sph::largestEigenvalue({4, 4, 1, 1, 0, 0}), 5.0, 1e-12);
  const double dp = 0.001, rho0 = 1000, nu = 1e-3;
  const auto z = sph::zeroSym3<double>();
  const double h = std::sqrt(2.0) * dp, eta2 = 0.01 * h * h;
  const auto k = sph::WendlandC2<2, double>::make(h);
  const sph::ViscosityLaminarCentral<double> visc{nu, eta2, 8.0};
  double acc = 0;  // on a (v_a = (1, 0)) from b (v_b = ((-1)^i, 0))
  for (int i = -3; i <= 3; ++i)
    for (int j = -3; j <= 3; ++j) {
      const Vec3<double> r_ab{-i * dp, -j * dp, 0};
      const double r2 = core::norm2(r_ab);
      if (r2 <= 0 || r2 >= 4 * h * h) continue;
      const Vec3<double> v_ab{1.0 - (i % 2 == 0 ? 1.0 : -1.0), 0, 0};
      acc += visc(r_ab, v_ab, r2, k.fac(std::sqrt(r2)), rho0, rho0, rho0 * dp * dp, false, z, z).x;
    }
  const double central = sph::latticeDiffusionRate(k, 2, h, dp, eta2, true);
  EXPECT_NEAR(central * nu, -acc, 1e-9 * central * nu);
}

// The Verlet scheme's diffusion limit (diffusion_stability.hpp) against the recurrence itself:
// dv/dt = -lambda v stepped with Euler every Ns steps and leap-frog otherwise decays at 0.95 x
// the limit and grows at 1.05 x it. Ns = 40 (DualSPHysics's default): 0.1353 (an independent scan of the
// cycle's spectral radius in 1% steps put the first growth between 0.1353 and 0.1366).
TEST(SphViscousStability, VerletLimitSeparatesDecayFromGrowth) {
  for (int ns : {10, 40, 80}) {
    const double limit = sph::verletDiffusionLimit(ns);
    auto amplitude = [ns](double mu) {
      double v = 1, v_m1 = 1, peak = 0;
      for (int step = 0; step < 400 * ns; ++step) {
        const bool euler = (step + 1) % ns == 0;
        const double next = euler ? v - mu * v : v_m1 - 2 * mu * v;
        v_m1 = v;
        v = next;
        if (step > 300 * ns) peak = std::max(peak, std::abs(v));
      }
      return peak;
    };
    EXPECT_LT(amplitude(0.95 * limit), 1e-3) << "Ns = " << ns;
    EXPECT_GT(amplitude(1.05 * limit), 1.0) << "Ns = " << ns;
  }
  EXPECT_NEAR(sph::verletDiffusionLimit(40), 0.1353, 0.0003);
}

// The fastest decay rate of the laminar term on a lattice: at least that of the checkerboard
// mode v = cos(pi (i + j)) computed with the viscosity functor itself, and (for these kernels
// and h) reached at the zone's corner, so equal to it.
TEST(SphViscousStability, LaminarRateIsTheCheckerboardRateOfTheFunctor) {
  const double dp = 0.001, rho0 = 1000, nu = 1e-3;
  const auto z = sph::zeroSym3<double>();
  const double h = std::sqrt(2.0) * dp, eta2 = 0.01 * h * h;
  const auto k = sph::WendlandC2<2, double>::make(h);
  const sph::ViscosityLaminar<double> visc{nu, eta2};
  double acc = 0;  // on a (v_a = 1) from its neighbours b (v_b = (-1)^(i + j))
  for (int i = -3; i <= 3; ++i)
    for (int j = -3; j <= 3; ++j) {
      const Vec3<double> r_ab{-i * dp, -j * dp, 0};
      const double r2 = core::norm2(r_ab);
      if (r2 <= 0 || r2 >= 4 * h * h) continue;
      const Vec3<double> v_ab{1.0 - ((i + j) % 2 == 0 ? 1.0 : -1.0), 0, 0};
      acc += visc(r_ab, v_ab, r2, k.fac(std::sqrt(r2)), rho0, rho0, rho0 * dp * dp, false, z, z).x;
    }
  const double rate = sph::latticeDiffusionRate(k, 2, h, dp, eta2);
  EXPECT_NEAR(rate * nu, -acc, 1e-9 * rate * nu);
}

TEST(SphViscosity, SpsStressOfSimpleShear) {
  // u = gamma_dot y: S_xy = gamma_dot / 2, |S| = sqrt(2 S_ij S_ij) = gamma_dot,
  // nu_sps = (Cs dp)^2 gamma_dot, tau_xy = rho 2 nu_sps S_xy, tau_xx = tau_yy = tau_zz =
  // -rho 2/3 C_I dp^2 gamma_dot^2 (the trace of S is 0).
  const double cs = 0.12, ci = 0.0066, dp = 0.01, rho = 1000, gd = 3.0;
  const sph::SpsStress<double> sps{cs * cs * dp * dp, 2.0 / 3.0 * ci * dp * dp};
  const sph::Sym3<double> s{0, 0, 0, gd / 2, 0, 0};
  const auto tau = sps(s, rho);
  const double nu_sps = cs * cs * dp * dp * gd;
  EXPECT_NEAR(tau.xy, rho * 2 * nu_sps * gd / 2, 1e-12);
  EXPECT_NEAR(tau.xx, -rho * 2.0 / 3.0 * ci * dp * dp * gd * gd, 1e-12);
  EXPECT_DOUBLE_EQ(tau.xx, tau.zz);
  EXPECT_DOUBLE_EQ(tau.xz, 0.0);
}

}  // namespace
}  // namespace millsim
