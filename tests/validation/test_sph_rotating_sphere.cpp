// The viscous torque on a sphere turning in place at a constant rate Omega inside a fixed
// concentric spherical container of radius R, full of fluid, in creeping flow (Lamb; Landau &
// Lifshitz, Fluid Mechanics, sec. 20, problem 2):
//   T = 8 pi mu Omega a^3 / (1 - (a / R)^3),
// and its 2D counterpart, a cylinder turning inside a coaxial one (circular Couette flow), per
// unit length: T = 4 pi mu Omega a^2 / (1 - (a / R)^2).
//
// Why: the towed sphere (test_sph_towed_sphere.cpp) got 80% of creeping flow's drag at a = 3
// and 4 dp, where the 2D towed cylinder gets 90% at 4 dp and all of it at 6 dp (the cause, found
// here: shell and fluid on two lattices; docs/validation.md, "One lattice"). A sphere's
// Stokes drag is two thirds shear stress and one third pressure; the turning sphere's torque is
// shear stress alone, with no pressure field and no tube, so it tests the viscous operator and
// the no-slip wall velocity on a convex 3D surface on their own, and costs a few seconds at a =
// 3 dp. The flow is purely azimuthal, u = Omega a^3 sin(theta) (R^3 / r^2 - r) / (R^3 - a^3)
// in 3D; at Re = Omega a^2 / nu = 0.05 the secondary (centrifugal) circulation changes the
// torque by O(Re^2).
//
// The body is a shell of 3 layers of the fluid's lattice (as a wet-mill ball carries), the
// fluid filling a <= |x| < R; the container's wall: 3 layers of the same lattice at R <= |x| <
// R + 3 dp. Started impulsively; the slowest mode of the gap decays about as exp(-pi^2 nu t /
// (R - a)^2), so the torque is averaged over 0.7 .. 1.0 (R - a)^2 / nu.
#include <gtest/gtest.h>

#include <array>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <sstream>
#include <string>

#include "sph/geometry.hpp"
#include "sph/sph_engine.hpp"
#include "sph/sph_kernels.hpp"
#include "support/env_runs.hpp"
#include "support/lattice_offset.hpp"
#include "support/tow_body.hpp"

namespace millsim {
namespace {

struct SpinResult {
  double torque_ratio = 0;  // measured T / the analytic torque
  double off_axis = 0;      // |T_x, T_y| / |T_z| and |F| / (T_z / a)
  long long steps = 0, particles = 0, excluded = 0;
  double wall_s = 0;
};

// A body shell of `layers` spherical (2D: circular) layers at radii a - (k + 1/2) dp, each with
// points about dp apart (Fibonacci spiral in 3D), instead of the cut cube lattice of
// addSphereShell: a smooth surface at every resolution, to tell the lattice cut's effect apart.
void addLayeredShell(sph::SphHostState& st, const std::array<double, 3>& c, double a, double dp, int dim, int layers,
                     double rho0) {
  st.body.resize(st.size(), -1);
  st.offset.resize(3 * st.size(), 0.0);
  const double pi = std::acos(-1.0), golden = pi * (3 - std::sqrt(5.0));
  for (int k = 0; k < layers; ++k) {
    const double r = a - (k + 0.5) * dp;
    if (r <= 0) break;
    const int n = std::max(1, static_cast<int>(std::lround(dim == 3 ? 4 * pi * r * r / (dp * dp) : 2 * pi * r / dp)));
    for (int q = 0; q < n; ++q) {
      std::array<double, 3> x{};
      if (dim == 3) {
        const double zc = 1 - (2 * q + 1.0) / n, rc = std::sqrt(1 - zc * zc), phi = golden * q;
        x = {r * rc * std::cos(phi), r * rc * std::sin(phi), r * zc};
      } else {
        x = {r * std::cos(2 * pi * q / n), r * std::sin(2 * pi * q / n), 0.0};
      }
      st.pos.insert(st.pos.end(), {c[0] + x[0], c[1] + x[1], c[2] + x[2]});
      st.vel.insert(st.vel.end(), {0.0, 0.0, 0.0});
      st.rho.push_back(rho0);
      st.code.push_back(sph::kBoundBody);
      st.body.push_back(0);
      st.offset.insert(st.offset.end(), x.begin(), x.end());
    }
  }
}

// The centre sits offset_dp (in dp) from a cell corner of the fluid's lattice: by default a
// generic spot (support/lattice_offset.hpp), the shell and the fluid cut there by sph::latticeCut.
SpinResult spinSphere(int dim, int n_radius, double r_over_a, const std::string& wall_velocity,
                      const std::string& viscosity, const std::string& shell = "shared",
                      const std::array<double, 3>& offset_dp = testing::kGenericLatticeOffset) {
  const double a = 0.003, re = 0.05, nu = 1e-3, rho0 = 1000, mu = rho0 * nu;
  const double dp = a / n_radius, R = r_over_a * a;
  const double omega = re * nu / (a * a);
  const auto wall0 = std::chrono::steady_clock::now();
  // h as the towed sphere / cylinder; the wall speed Omega a = 0.017 m/s.
  const double h = (dim == 3 ? 0.8 * std::sqrt(3.0) : std::sqrt(2.0)) * dp;
  sph::SphSetup s = testing::viscousBodySetup(dim, dp, h, nu, viscosity, wall_velocity);
  const double m = R + 6 * dp;
  s.domain_lo = {-m, -m, dim == 3 ? -m : -1.0};
  s.domain_hi = {m, m, dim == 3 ? m : 1.0};
  // Body and container centred on c, the lattice's cell corner nearest the origin moved by offset_dp.
  const std::array<double, 3> c{offset_dp[0] * dp, offset_dp[1] * dp, dim == 3 ? offset_dp[2] * dp : 0.0};

  // Fluid and container wall on the lattice (i + 1/2) dp. Shell "shared" (the wet mill's set-up):
  // the body's shell cut from the same lattice, the fluid filling a <= |x| < R, dp from the first
  // wall particle on either side. "lattice": the shell on a lattice through the centre, the fluid
  // carved to a + dp/2 and filled to R - dp/2 (the set-up before 2026-12-05); "layered": above.
  sph::SphHostState st;
  const bool shared = shell == "shared";
  const int n = static_cast<int>(std::ceil((R + 4 * dp) / dp));  // 3 wall layers, the offset
  const sph::LatticeCut cut = sph::latticeCut(c, a, dp, dim, sph::cellCentredLattice(dp));  // the shell's
  const int k0 = dim == 3 ? -n : 0, k1 = dim == 3 ? n : 1;
  for (int k = k0; k < k1; ++k)
    for (int j = -n; j < n; ++j)
      for (int i = -n; i < n; ++i) {
        const double x = sph::latticeCoord(0.5 * dp, dp, i), y = sph::latticeCoord(0.5 * dp, dp, j),
                     z = dim == 3 ? sph::latticeCoord(0.5 * dp, dp, k) : 0.0;
        const double dx = x - c[0], dy = y - c[1], dz = dim == 3 ? z - c[2] : 0.0;
        const double d = std::sqrt(dx * dx + dy * dy + dz * dz);
        int code = -1;
        const double gap = shared ? 0.0 : 0.5 * dp;
        if ((shared ? !sph::insideRadius(dx, dy, dz, cut.radius) : d >= a + gap) && d < R - gap) code = sph::kFluid;
        if (d >= R && d < R + 3 * dp) code = sph::kBoundFixed;
        if (code < 0) continue;
        st.pos.insert(st.pos.end(), {x, y, z});
        st.vel.insert(st.vel.end(), {0.0, 0.0, 0.0});
        st.rho.push_back(rho0);
        st.code.push_back(code);
      }
  if (shell == "layered")
    addLayeredShell(st, c, a, dp, dim, 3, rho0);
  else if (shared)
    sph::addSphereShell(st, c, a, dp, dim, 3, 0, rho0, cut);
  else
    sph::addSphereShell(st, c, a, dp, dim, 3, 0, rho0);

  auto e = sph::makeSphEngineOmp(s);
  e->setState(st);
  const double t_gap = (R - a) * (R - a) / nu;
  const testing::TowAverage spin = testing::towAndAverage(*e, c, {0, 0, 0}, t_gap, 0.7 * t_gap, {0, 0, omega});
  SpinResult r;
  r.particles = static_cast<long long>(st.size());
  r.steps = spin.steps;
  const double pi = std::acos(-1.0);
  const double expected = dim == 3 ? 8 * pi * mu * omega * std::pow(a, 3) / (1 - std::pow(a / R, 3))
                                   : 4 * pi * mu * omega * a * a / (1 - std::pow(a / R, 2));
  const double tz = -spin.torque[2];  // the fluid holds the body back: its torque opposes Omega
  r.torque_ratio = tz / expected;
  r.off_axis = std::max(std::hypot(spin.torque[0], spin.torque[1]) / std::abs(tz),
                        std::hypot(spin.force[0], spin.force[1], spin.force[2]) * a / std::abs(tz));
  const sph::SphSums sums = e->sums();
  r.excluded = sums.excluded_density + sums.excluded_domain;
  r.wall_s = std::chrono::duration<double>(std::chrono::steady_clock::now() - wall0).count();
  std::printf(
      "rotating %s, a = %d dp, R = %.2f a, %s, wall_velocity = %s, %s shell, centre at (%.2f, %.2f, %.2f) dp from a "
      "cell corner: %lld particles, %lld steps, %.0f s: torque / analytic %.4f, off-axis %.2e\n",
      dim == 3 ? "sphere" : "cylinder", n_radius, r_over_a, viscosity.c_str(), wall_velocity.c_str(), shell.c_str(),
      offset_dp[0], offset_dp[1], dim == 3 ? offset_dp[2] : 0.0, r.particles, r.steps, r.wall_s, r.torque_ratio,
      r.off_axis);
  return r;
}

// The form of the viscous term decides the torque on a turning wall, at every resolution.
// Lo & Shao's pair force points along v_ab, so the stress its pair sum carries across a surface
// is mu grad v, not mu (grad v + grad v^T) (viscosity.hpp). For circular Couette flow, u = A r +
// B / r with A = -Omega a^2 / (R^2 - a^2), B = Omega a^2 R^2 / (R^2 - a^2), the wall stress is
// mu (A - B / a^2) against the true -2 mu B / a^2: Lo & Shao's torque is (B - A a^2) / (2 B) =
// 5/9 of the true one at R = 3 a, so the central form's torque must be 9/5 = 1.8 times Lo &
// Shao's. With shell, fluid and wall on one lattice (docs/validation.md, "One lattice") and the
// centre at the generic offset, the central torque is 0.994 of the analytic one at a = 8 dp, Lo
// & Shao's 0.546 (5/9 - 1.7%). Asserted at a = 8 dp (~25 s): each within 5% of its own limit,
// the spread over resolutions and centre offsets (+-3%) with a margin. (Shell and fluid on two
// lattices, the set-up before 2026-12-05, gave 0.83 and 0.46: the gap between them, not the
// viscous term.) Off the axis: the lattice cut of a circle off a cell corner is not symmetric,
// which leaves a force and an in-plane torque of 2.3% (central) and 4.0% (Lo & Shao) of T_z /
// a, T_z; bound at 5%, as the symmetric set-up's exact zero is asserted below.
TEST(SphRotatingSphere, CentralViscosityGivesTheTurningCylinderItsTorque) {
  const SpinResult central = spinSphere(2, 8, 3.0, "no_slip", "laminar_central");
  const SpinResult lo_shao = spinSphere(2, 8, 3.0, "no_slip", "laminar");
  EXPECT_EQ(central.excluded + lo_shao.excluded, 0);
  EXPECT_LT(central.off_axis, 0.05);
  EXPECT_LT(lo_shao.off_axis, 0.05);
  EXPECT_NEAR(central.torque_ratio, 1.0, 0.05);
  EXPECT_NEAR(lo_shao.torque_ratio, 5.0 / 9.0, 0.05 * 5.0 / 9.0);
}

// The sphere in 3D, a = 4 dp (~50 s): Lamb's torque within 5%. Measured on one lattice with the
// centre at the generic offset: 1.001 at 4 dp (0.975-1.001 over three generic centres, 0.96-0.99
// at 3 dp: docs/validation.md, "Where the centre falls"); with the centre at a cell corner 1.160, 1.017, 0.993 at a = 3, 4, 6 dp, the
// corner's cut being larger than the sphere (1.063 a and 1.015 a, volume-matched, at 3 and 4
// dp); on two lattices 0.735, 0.707, 0.894. Off the axis: 1.1% (the cut's asymmetry), bound 5%.
TEST(SphRotatingSphere, TurningSphereGetsLambsTorque) {
  const SpinResult r = spinSphere(3, 4, 3.0, "no_slip", "laminar_central");
  EXPECT_EQ(r.excluded, 0);
  EXPECT_LT(r.off_axis, 0.05);
  EXPECT_NEAR(r.torque_ratio, 1.0, 0.05);
}

// With the centre at a cell corner the set-up is symmetric under x -> -x and y -> -y (and the
// wall's and the body's sums with it), so the fluid can exert no force and no in-plane torque on
// the turning cylinder: zero up to rounding (a = 4 dp, 2D, ~3 s). A pair term that is not
// antisymmetric, or a body sum that drops particles, breaks it.
TEST(SphRotatingSphere, SymmetricSetUpHasNoOffAxisLoad) {
  const SpinResult r = spinSphere(2, 4, 3.0, "no_slip", "laminar_central", "shared", {0.0, 0.0, 0.0});
  EXPECT_EQ(r.excluded, 0);
  EXPECT_LT(r.off_axis, 1e-6);
  EXPECT_NEAR(r.torque_ratio, 1.0, 0.05);  // 1.009 measured (docs/validation.md, "One lattice")
}

// Diagnostic: MILLSIM_SPIN="a_over_dp[:dim[:R_over_a[:wall_velocity[:viscosity[:shell[:ox,oy,oz]]]]]] ..."
// (default "3 4 6": 3D, R = 3 a, no-slip walls, laminar_central, the shared lattice, the
// generic offset; shell "lattice" or "layered", as spinSphere; the centre's offset from a cell
// corner in dp, e.g. "0,0,0" for the corner).
TEST(SphRotatingSphere, DISABLED_Resolution) {
  for (const auto& f : testing::envRuns("MILLSIM_SPIN", "3 4 6", 7)) {
    std::array<double, 3> offset = testing::kGenericLatticeOffset;
    if (!f[6].empty()) {
      std::istringstream in(f[6]);
      char comma = 0;
      in >> offset[0] >> comma >> offset[1] >> comma >> offset[2];
      if (!in) ADD_FAILURE() << "offset \"" << f[6] << "\": ox,oy,oz in dp";
    }
    const SpinResult r = spinSphere(f[1].empty() ? 3 : std::stoi(f[1]), std::stoi(f[0]),
                                    f[2].empty() ? 3.0 : std::stod(f[2]), f[3].empty() ? "no_slip" : f[3],
                                    f[4].empty() ? "laminar_central" : f[4], f[5].empty() ? "shared" : f[5], offset);
    EXPECT_EQ(r.excluded, 0);
  }
}

}  // namespace
}  // namespace millsim
