// No-slip at moving DBC walls with the laminar viscosity (Lo & Shao), and the viscous time-step
// limit: the spin-up of a fluid in a 2D drum started impulsively at Omega. The azimuthal
// velocity obeys the diffusion equation
//   du/dt = nu (u'' + u'/r - u/r^2),  u(R, t) = Omega R,  u(r, 0) = 0,
// whose solution is u = Omega r - sum_n c_n J1(a_n r/R) exp(-a_n^2 nu t / R^2), a_n the zeros
// of J1 and c_n = -2 Omega R / (a_n J0(a_n)) (the expansion of Omega r in J1(a_n r/R)). The
// profile is compared at t nu / R^2 = 0.02 .. 0.2. No gravity, drum completely full, R = 40 dp,
// nu = 5e-4 m2/s, c0 = 1 m/s (20 x the wall speed).
//
// At these settings the CFL step of the paper's eq. 40 (0.2 h / c0) puts the Verlet scheme at
// 2.6 times its viscous stability limit (diffusion_stability.hpp): without the limit, thousands of
// particles left the density bounds within 0.1 s. With it: none, and the profile below.
// Accuracy (docs/validation.md), wall particles at their own velocity (DBC, `wall_velocity =
// dbc`): the fluid lags the analytic profile everywhere, most next to the wall early (-0.13
// Omega R at r = 0.92 R, t nu/R^2 = 0.02, the sharpest shear) and by -0.05 Omega R in the
// interior at 0.1: the wall slips. The rms error over the profile reaches 6.1% of Omega R; the
// symplectic scheme gives the same to 3 digits (a spatial error, not the integrator's). With the
// no-slip wall velocity of Adami et al. 2012 (`wall_velocity = no_slip`, WallNoSlipVelocity in
// sph_kernels.hpp) the lag halves everywhere: rms 3.3% (3.0% with the wall's velocity taken
// at the particle instead of mirrored in its turning frame, before 2026-12-04), -0.057 Omega R at
// 0.93 R at 0.02 (a boundary layer sqrt(nu t) = 5.6 dp thick there), -0.03 in the interior at 0.1.
#include <gtest/gtest.h>

#include <array>
#include <cmath>
#include <cstdio>
#include <vector>

#include "sph/geometry.hpp"
#include "sph/sph_engine.hpp"
#include "sph/sph_kernels.hpp"

namespace millsim {
namespace {

// Zeros of J1 by Newton from McMahon's estimate (n + 1/4) pi.
std::vector<double> besselJ1Zeros(int count) {
  std::vector<double> z;
  const double pi = std::acos(-1.0);
  for (int n = 1; n <= count; ++n) {
    double x = (n + 0.25) * pi;
    for (int k = 0; k < 50; ++k) {
      // J1' = J0 - J1 / x
      const double f = std::cyl_bessel_j(1.0, x), df = std::cyl_bessel_j(0.0, x) - f / x;
      x -= f / df;
    }
    z.push_back(x);
  }
  return z;
}

double spinUpVelocity(double r, double t, double R, double omega, double nu, const std::vector<double>& zeros) {
  double u = omega * r;
  for (double a : zeros) {
    const double c = -2.0 * omega * R / (a * std::cyl_bessel_j(0.0, a));
    u -= c * std::cyl_bessel_j(1.0, a * r / R) * std::exp(-a * a * nu * t / (R * R));
  }
  return u;
}

struct SpinUpResult {
  double rms_error = 0;   // largest over the sample times of the rms of (u_sph - u_exact) / (Omega R)
  double wall_error = 0;  // (u_sph - u_exact) / (Omega R) in the ring next to the wall at the last time
  double max_speed = 0;   // largest fluid speed / (Omega R) at the sample times
  double dt_ratio = 0;    // the CFL step over the viscous limit at the start
  long long excluded = 0;
};

SpinUpResult runSpinUp(int n_radius, const char* integrator, const char* csv, const char* wall_velocity = "dbc",
                       const char* boundary = "dbc") {
  const double R = 0.05, omega = 1.0, nu = 5e-4, rho0 = 1000;
  const double dp = R / n_radius;
  sph::SphSetup s;
  s.dimension = 2;
  s.dp = dp;
  s.h = dp * std::sqrt(2.0);
  s.c0 = 1.0;  // 20 x the wall speed (Mach 0.05); the rotation's pressure rho Omega^2 R^2 / 2 is 1.25 Pa
  s.rho0 = rho0;
  s.viscosity = "laminar";
  s.nu = nu;
  s.ddt = "fourtakas";
  s.shifting = true;
  s.integrator = integrator;
  s.wall_velocity = wall_velocity;
  s.boundary = boundary;
  s.gravity = {0, 0, 0};
  s.rho_min = 900;
  s.rho_max = 1100;
  s.domain_lo = {-2 * R, -2 * R, -1};
  s.domain_hi = {2 * R, 2 * R, 1};
  sph::SphHostState st;
  const int n = n_radius + 4;
  for (int j = -n; j < n; ++j)
    for (int i = -n; i < n; ++i) {
      const double x = (i + 0.5) * dp, y = (j + 0.5) * dp, r = std::hypot(x, y);
      int code = -1;
      if (r < R - 0.5 * dp)
        code = sph::kFluid;
      else if (r >= R && r < R + 3 * dp)
        code = sph::kBoundMoving;
      if (code < 0) continue;
      st.pos.insert(st.pos.end(), {x, y, 0.0});
      st.vel.insert(st.vel.end(), {0.0, 0.0, 0.0});
      st.rho.push_back(rho0);
      st.code.push_back(code);
      // mDBC: the wall particles mirror radially across r = R, as a drum's mantle does.
      const std::array<double, 3> g =
          code == sph::kFluid ? std::array<double, 3>{} : sph::drumGhost(sph::DrumGeometry{R, 0}, x, y, 0);
      st.ghost.insert(st.ghost.end(), g.begin(), g.end());
    }
  auto e = sph::makeSphEngineOmp(s);
  e->setState(st);
  // The wall turns at Omega from t = 0 (impulsive start).
  auto motion = [&](double t) { return sph::SphMotion{omega * t, omega}; };
  e->initialize(motion(0));
  SpinUpResult res;
  res.dt_ratio = s.cfl * s.h / s.c0 / e->viscousDtLimit();
  const std::vector<double> zeros = besselJ1Zeros(60);
  std::FILE* out = std::fopen(csv, "w");
  if (out) std::fprintf(out, "t_nu_over_R2,r_over_R,u_sph_over_OmegaR,u_exact_over_OmegaR,particles\n");
  double t = 0;
  for (double tau : {0.02, 0.05, 0.1, 0.2}) {
    const double t_end = tau * R * R / nu;
    while (t < t_end - 1e-12) {
      const double dt = std::min(e->nextDt(), t_end - t);
      e->step(dt, motion(t + 0.5 * dt), motion(t + dt));
      t += dt;
    }
    sph::SphHostState now;
    e->getState(now);
    const sph::SphSums sm = e->sums();
    res.excluded += sm.excluded_density + sm.excluded_domain;
    res.max_speed = std::max(res.max_speed, sm.max_speed / (omega * R));
    // Azimuthal velocity in rings of width 2 dp, inside R - dp (the wall's own kernel reach is
    // where a DBC wall's no-slip is imposed; the comparison starts one spacing inside it).
    const int bins = n_radius / 2;
    std::vector<double> sum(bins, 0.0), sum_r(bins, 0.0);
    std::vector<int> count(bins, 0);
    for (std::size_t k = 0; k < now.size(); ++k) {
      if (now.code[k] != sph::kFluid) continue;
      const double x = now.pos[3 * k], y = now.pos[3 * k + 1], r = std::hypot(x, y);
      const int b = static_cast<int>(r / (2 * dp));
      if (b >= bins || r > R - dp) continue;
      sum[b] += (-y * now.vel[3 * k] + x * now.vel[3 * k + 1]) / r;
      sum_r[b] += r;
      ++count[b];
    }
    double sq = 0, last = 0;
    int used = 0;
    for (int b = 0; b < bins; ++b) {
      if (count[b] < 4) continue;
      const double r = sum_r[b] / count[b];
      const double u = sum[b] / count[b], ue = spinUpVelocity(r, t, R, omega, nu, zeros);
      const double err = (u - ue) / (omega * R);
      sq += err * err;
      last = err;
      ++used;
      if (out) std::fprintf(out, "%g,%g,%g,%g,%d\n", tau, r / R, u / (omega * R), ue / (omega * R), count[b]);
    }
    res.rms_error = std::max(res.rms_error, std::sqrt(sq / std::max(used, 1)));
    res.wall_error = last;
  }
  if (out) std::fclose(out);
  return res;
}

// Verlet at 2.6 times its viscous limit by the CFL step alone, held stable by the limit; then
// the symplectic scheme on the same case: the profile error is spatial (the wall's slip), not
// the integrator's, so the two agree closely (measured: the same rms to 3 digits).
TEST(SphSpinUp, VerletStaysStableAndSymplecticGivesTheSameProfile) {
  const SpinUpResult r = runSpinUp(40, "verlet", "sph_spin_up_R40dp_verlet.csv");
  std::printf(
      "spin-up, R = 40 dp, Verlet: CFL step / viscous limit %.2f, rms error %.4f Omega R, next to the "
      "wall %.4f Omega R, max speed %.4f Omega R, %lld excluded\n",
      r.dt_ratio, r.rms_error, r.wall_error, r.max_speed, r.excluded);
  // The case is one the CFL step alone would make unstable (lambda dt = 0.36 against 0.135).
  EXPECT_GT(r.dt_ratio, 2.0);
  // Stable: nothing leaves the density bounds (+-10%) and no particle outruns the wall (a
  // growing mode shows as speeds of several Omega R).
  EXPECT_EQ(r.excluded, 0);
  EXPECT_LT(r.max_speed, 1.05);
  // No-slip: at t nu/R^2 = 0.2 the ring next to the wall moves with the analytic speed within
  // 3% of Omega R (measured -0.45%).
  EXPECT_NEAR(r.wall_error, 0.0, 0.03);
  // The profile: rms error at each time within 8% of Omega R, a regression bound on a known
  // spatial error (measured 6.1% here, 5.4% at c0 = 5 m/s; see the top of the file).
  EXPECT_LT(r.rms_error, 0.08);

  const SpinUpResult s = runSpinUp(40, "symplectic", "sph_spin_up_R40dp_symplectic.csv");
  std::printf(
      "spin-up, R = 40 dp, symplectic: CFL step / viscous limit %.2f, rms error %.4f Omega R, next to the "
      "wall %.4f Omega R, %lld excluded\n",
      s.dt_ratio, s.rms_error, s.wall_error, s.excluded);
  // Its limit (mu <= 2) is 15 times the Verlet one's: the CFL step is well inside it.
  EXPECT_LT(s.dt_ratio, 1.0);
  EXPECT_EQ(s.excluded, 0);
  // The same profile: rms and wall-ring errors within 0.2% of Omega R of Verlet's (a tenth of
  // the slip the no-slip wall velocity removes, below; the integrators' own errors at these
  // steps are O(dt^2) of a diffusion over ~1e4 steps, far smaller).
  EXPECT_NEAR(s.rms_error, r.rms_error, 0.002);
  EXPECT_NEAR(s.wall_error, r.wall_error, 0.002);
}

// The no-slip wall velocity (Adami et al. 2012) removes most of the slip.
TEST(SphSpinUp, NoSlipWallVelocityHalvesTheProfileError) {
  const SpinUpResult r = runSpinUp(40, "verlet", "sph_spin_up_R40dp_noslip.csv", "no_slip");
  std::printf(
      "spin-up, R = 40 dp, Verlet, no_slip walls: rms error %.4f Omega R, next to the wall %.4f Omega R, "
      "max speed %.4f Omega R, %lld excluded\n",
      r.rms_error, r.wall_error, r.max_speed, r.excluded);
  EXPECT_EQ(r.excluded, 0);
  EXPECT_LT(r.max_speed, 1.05);
  EXPECT_NEAR(r.wall_error, 0.0, 0.03);
  // Half the DBC wall's error: measured 3.3% of Omega R against 6.1% with the wall particles at
  // their own velocity (the tests above), so the bound fails if the no-slip velocity is lost.
  // (3.0% before 2026-12-04, when the wall took its velocity at the particle, a layer outside
  // the surface: the fluid next to it then ran 0.9% ahead of the wall, now 0.2% behind.)
  EXPECT_LT(r.rms_error, 0.04);
}

// Diagnostic (docs/validation.md, "mDBC and the no-slip velocity"): mDBC walls with either
// no-slip velocity. ~1 min each.
TEST(SphSpinUp, DISABLED_MdbcWalls) {
  for (const char* wall_velocity : {"no_slip", "no_slip_ghost"}) {
    const SpinUpResult r = runSpinUp(40, "verlet", "sph_spin_up_R40dp_mdbc.csv", wall_velocity, "mdbc");
    std::printf(
        "spin-up, R = 40 dp, Verlet, mdbc + %s: rms error %.4f Omega R, next to the wall %.4f Omega R, "
        "max speed %.4f Omega R, %lld excluded\n",
        wall_velocity, r.rms_error, r.wall_error, r.max_speed, r.excluded);
  }
}

}  // namespace
}  // namespace millsim
