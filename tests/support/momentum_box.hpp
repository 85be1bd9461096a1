#pragma once
// The momentum-bookkeeping scene of issue 5 (tests/validation/test_wet_coupling_momentum.cpp has
// the why and the tolerances): two balls coast through fluid at rest in a closed box, no gravity,
// for 1 s, coupled by coupling::SphDemCoupling; the box's walls are a held body. On OpenMP or
// (tests/gpu) on CUDA, both engines on the same backend.
#include <gtest/gtest.h>

#include <algorithm>
#include <array>
#include <cmath>
#include <memory>
#include <stdexcept>
#include <string>
#include <vector>

#include "coupling/sph_dem_coupling.hpp"
#include "sph/geometry.hpp"
#include "support/dem_fixture.hpp"
#include "support/sph_fixture.hpp"

namespace millsim::testing {

inline std::unique_ptr<sph::SphEngine> makeSphEngine(const sph::SphSetup& s, bool cuda) {
#if defined(MILLSIM_HAVE_CUDA)
  if (cuda) return sph::makeSphEngineCuda(s);
#endif
  if (cuda) throw std::runtime_error("makeSphEngine: this build has no CUDA backend");
  return sph::makeSphEngineOmp(s);
}

struct MomentumRun {
  double p0 = 0;           // |P(0)|, kg m/s
  double worst = 0;        // max_t |P(t) - P(0)| / |P(0)|
  double fluid_share = 0;  // |fluid momentum| / |P(0)| at the end: the fluid did take some
  double wall_share = 0;   // |wall impulse| / |P(0)| at the end: and the walls too
  long long steps = 0;
};

// The scene, set up and initialised: both engines and their coupling.
struct MomentumBox {
  std::unique_ptr<dem::DemEngine> dem;
  std::unique_ptr<sph::SphEngine> sph;
  std::unique_ptr<coupling::SphDemCoupling> coupling;
  double dt_dem = 2e-4;
  double fluid_mass = 0;  // of one fluid particle, kg
  // One coupled step (the DEM sub-stepped at dt_dem or finer); returns dt.
  double advance() {
    auto half = [](double) { return sph::SphMotion{}; };
    auto dem_steps = [this](double dt) {
      const int sub = std::max(1, static_cast<int>(std::ceil(dt / dt_dem - 1e-9)));
      for (int k = 0; k < sub; ++k) dem->step(stillDrum(), dt / sub);
      return sph::SphMotion{};
    };
    return coupling->advance(*sph, *dem, half, dem_steps);
  }
};

// dcdem: the balls are DCDEM bodies (lattice particles at the fluid's dp, dem_fixture), loaded
// per body; else analytic spheres.
inline MomentumBox makeMomentumBox(const std::string& integrator, bool dcdem = false, bool cuda = false) {
  const double dp = 0.01, L = 0.16, rho0 = 1000, z0 = 1.0;  // z0: clear of the DEM drum's front plate
  sph::SphSetup s;
  s.dimension = 3;
  s.dp = dp;
  s.h = 0.8 * std::sqrt(3.0) * dp;
  s.c0 = 1.0;
  s.rho0 = rho0;
  s.gravity = {0, 0, 0};
  s.integrator = integrator;
  s.visco_bound_factor = 0.1;
  s.shifting = true;
  s.domain_lo = {-0.1, -0.1, z0 - 0.1};
  s.domain_hi = {L + 0.1, L + 0.1, z0 + L + 0.1};

  const std::vector<Ball> balls{{0.05, 0.05, z0 + 0.08, 0.04, 0.01, 0.0, 0.03},
                                         {0.11, 0.11, z0 + 0.07, -0.01, 0.0, 0.03, 0.03}};
  const double ball_density = 2500;
  sph::SphHostState st;
  const sph::Box box{{0, 0, z0}, {L, L, z0 + L}};
  sph::fillFluidBox(st, box, dp, 3, rho0);
  sph::addTankWalls(st, box, dp, 3, 3, true, sph::kBoundFixed, rho0);
  for (std::size_t b = 0; b < balls.size(); ++b) {
    const std::array<double, 3> c{balls[b].x, balls[b].y, balls[b].z};
    // The shell cut from the fluid's lattice, the fluid carved where it ends (as the wet mill).
    const sph::LatticeCut cut = sph::latticeCut(c, balls[b].r, dp, 3, sph::cellCentredLattice(dp, box.lo));
    sph::carveFluidForShell(st, c, cut);
    sph::addSphereShell(st, c, balls[b].r, dp, 3, 3, static_cast<int>(b), rho0, cut);
  }
  // The walls become body particles of body 2, held at the box's centre.
  const std::array<double, 3> centre{0.5 * L, 0.5 * L, z0 + 0.5 * L};
  for (std::size_t i = 0; i < st.size(); ++i) {
    if (st.code[i] != sph::kBoundFixed) continue;
    st.code[i] = sph::kBoundBody;
    st.body[i] = static_cast<int>(balls.size());
    for (int a = 0; a < 3; ++a) st.offset[3 * i + a] = st.pos[3 * i + a] - centre[a];
  }

  DemScene dsc;
  dsc.density = ball_density;
  dsc.cuda = cuda;
  std::unique_ptr<dem::DemEngine> dem;
  if (dcdem) {
    dem::BodyAssembler a;
    for (const auto& b : balls) {
      std::vector<core::Vec3<double>> pts = dem::latticeBallPoints(b.r, dp);
      for (auto& p : pts) p += core::Vec3<double>{b.x, b.y, b.z};
      a.addBody(pts, 0.5 * dp, ballMass(b.r, ball_density), {b.vx, b.vy, b.vz}, {0, 0, 0}, b.r);
    }
    dem = makeBodyEngine(dsc, a, 0.5 * dp, s.domain_lo, s.domain_hi);
  } else {
    dem = makeEngine(dsc, balls);
  }
  MomentumBox run;
  run.fluid_mass = rho0 * dp * dp * dp;
  run.dem = std::move(dem);
  run.sph = makeSphEngine(s, cuda);
  run.sph->setState(st);
  run.coupling = std::make_unique<coupling::SphDemCoupling>(balls.size(),
                                                             std::vector<sph::SphBody>{sph::SphBody{centre, {}, {}}});
  run.coupling->initialize(*run.sph, dem::ballStates(*run.dem), {});
  return run;
}

inline MomentumRun runBox(const std::string& integrator, bool dcdem = false, bool cuda = false) {
  MomentumBox box = makeMomentumBox(integrator, dcdem, cuda);
  sph::SphEngine* sph = box.sph.get();
  dem::DemEngine* dem = box.dem.get();
  const coupling::SphDemCoupling& coupling = *box.coupling;
  const double fluid_mass = box.fluid_mass;
  auto total = [&](double* fluid_abs, double* wall_abs) {
    std::array<double, 3> p{0, 0, 0}, pf{0, 0, 0};
    sph::SphHostState now;
    sph->getState(now);
    for (std::size_t i = 0; i < now.size(); ++i)
      if (now.code[i] == sph::kFluid)
        for (int a = 0; a < 3; ++a) pf[a] += fluid_mass * now.vel[3 * i + a];
    const dem::DemHostState d = dem::ballStates(*dem);
    const auto& wall = coupling.heldImpulse()[0];
    for (int a = 0; a < 3; ++a) {
      p[a] = pf[a] + wall[a];
      for (std::size_t b = 0; b < d.size(); ++b) p[a] += d.mass[b] * d.vel[3 * b + a];
    }
    if (fluid_abs) *fluid_abs = std::sqrt(pf[0] * pf[0] + pf[1] * pf[1] + pf[2] * pf[2]);
    if (wall_abs) *wall_abs = std::sqrt(wall[0] * wall[0] + wall[1] * wall[1] + wall[2] * wall[2]);
    return p;
  };

  MomentumRun r;
  const std::array<double, 3> p0 = total(nullptr, nullptr);
  r.p0 = std::sqrt(p0[0] * p0[0] + p0[1] * p0[1] + p0[2] * p0[2]);
  double t = 0;
  while (t < 1.0) {
    t += box.advance();
    ++r.steps;
    const std::array<double, 3> p = total(nullptr, nullptr);
    const double d =
        std::sqrt((p[0] - p0[0]) * (p[0] - p0[0]) + (p[1] - p0[1]) * (p[1] - p0[1]) + (p[2] - p0[2]) * (p[2] - p0[2]));
    r.worst = std::max(r.worst, d / r.p0);
  }
  double fluid_abs = 0, wall_abs = 0;
  total(&fluid_abs, &wall_abs);
  r.fluid_share = fluid_abs / r.p0;
  r.wall_share = wall_abs / r.p0;
  const sph::SphSums sums = sph->sums();
  EXPECT_EQ(sums.excluded_density + sums.excluded_domain, 0);
  return r;
}

}  // namespace millsim::testing
