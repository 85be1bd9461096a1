#pragma once
// Small DEM scenes for tests: a few balls in a huge, still drum whose front plate (z = 0) serves
// as a flat wall. Everything goes through the real engine (the same code as `millsim run`).
#include <algorithm>
#include <array>
#include <cmath>
#include <memory>
#include <random>
#include <stdexcept>
#include <vector>

#include "dem/contact/damping.hpp"
#include "dem/dcdem_bodies.hpp"
#include "dem/dem_engine.hpp"
#include "dem/dem_kernels.hpp"

namespace millsim::testing {

struct Ball {
  double x, y, z, vx, vy, vz, r;
  double wx = 0, wy = 0, wz = 0;
};

struct DemScene {
  double young = 1e8, poisson = 0.29, density = 7800.0;
  double restitution = 0.5, friction = 0.0;
  dem::DampingModel damping = dem::DampingModel::kExact;
  std::array<double, 3> gravity{0, 0, 0};
  bool single_precision = false;
  bool tanh = false;
  bool cuda = false;  // the CUDA engine (tests/gpu); needs a CUDA build
};

// The scene's engine on its backend.
inline std::unique_ptr<dem::DemEngine> makeDemEngine(const dem::DemSetup& setup, const DemScene& sc) {
#if defined(MILLSIM_HAVE_CUDA)
  if (sc.cuda) return dem::makeDemEngineCuda(setup, sc.single_precision);
#endif
  if (sc.cuda) throw std::runtime_error("DemScene::cuda: this build has no CUDA backend");
  return dem::makeDemEngineOmp(setup, sc.single_precision);
}

inline double ballMass(double r, double rho) { return rho * 4.0 / 3.0 * std::acos(-1.0) * r * r * r; }

inline dem::DrumState stillDrum() {
  dem::DrumState w;
  w.radius = 10.0;
  w.z_back = 20.0;
  return w;
}

// Solid spheres of the given density (I = 2/5 m r^2).
inline dem::DemHostState hostState(const std::vector<Ball>& balls, double density) {
  dem::DemHostState s;
  for (const auto& b : balls) {
    s.pos.insert(s.pos.end(), {b.x, b.y, b.z});
    s.vel.insert(s.vel.end(), {b.vx, b.vy, b.vz});
    s.omega.insert(s.omega.end(), {b.wx, b.wy, b.wz});
    s.radius.push_back(b.r);
    const double m = ballMass(b.r, density);
    s.mass.push_back(m);
    s.inertia.push_back(0.4 * m * b.r * b.r);
  }
  return s;
}

// The scene's material, contact law and gravity (no cells yet).
inline dem::DemSetup materialSetup(const DemScene& sc) {
  dem::DemSetup setup;
  setup.k_coef = 4.0 / 3.0 * dem::effectiveModulus(sc.young, sc.poisson);
  setup.alpha = dem::dampingAlpha(sc.damping, sc.restitution);
  setup.wall_mass_factor = dem::wallMassFactor(sc.damping);
  setup.friction = sc.friction;
  setup.tanh_smoothing = sc.tanh;
  setup.gravity = sc.gravity;
  return setup;
}

inline std::unique_ptr<dem::DemEngine> makeEngine(const DemScene& sc, const std::vector<Ball>& balls) {
  dem::DemSetup setup = materialSetup(sc);
  double rmax = 0, rmin = 1e9;
  for (const auto& b : balls) {
    rmax = std::max(rmax, b.r);
    rmin = std::min(rmin, b.r);
  }
  setup.skin = 0.2 * rmin;
  setup.max_radius = rmax;
  // Grid over the balls' box plus a margin: balls that leave it are clamped into border cells,
  // which keeps the search exact, and a small grid keeps rebuilds cheap.
  std::array<double, 3> lo{1e9, 1e9, 1e9}, hi{-1e9, -1e9, -1e9};
  for (const auto& b : balls) {
    const double p[3] = {b.x, b.y, b.z};
    for (int a = 0; a < 3; ++a) {
      lo[a] = std::min(lo[a], p[a] - 0.05);
      hi[a] = std::max(hi[a], p[a] + 0.05);
    }
  }
  setup.domain_lo = lo;
  setup.domain_hi = hi;
  auto engine = makeDemEngine(setup, sc);
  engine->setState(hostState(balls, sc.density));
  engine->initialize(stillDrum());
  return engine;
}

// A tumbling-drum set-up: E = 1e8 Pa steel balls, exact damping for restitution e, friction mu,
// gravity -y, skin 0.2 r_min, cells over [lo, hi].
inline dem::DemSetup drumSetup(double e, double mu, double r_min, double r_max, std::array<double, 3> lo,
                               std::array<double, 3> hi) {
  DemScene sc;
  sc.restitution = e;
  sc.friction = mu;
  sc.gravity = {0, -9.81, 0};
  dem::DemSetup setup = materialSetup(sc);
  setup.skin = 0.2 * r_min;
  setup.max_radius = r_max;
  setup.domain_lo = lo;
  setup.domain_hi = hi;
  return setup;
}

// DCDEM bodies (an assembled set of element particles) with the scene's material, skin 0.2 of
// the element radius, cells over [lo, hi].
inline std::unique_ptr<dem::DemEngine> makeBodyEngine(const DemScene& sc, const dem::BodyAssembler& a,
                                                      double element_radius, std::array<double, 3> lo,
                                                      std::array<double, 3> hi) {
  dem::DemSetup setup = materialSetup(sc);
  setup.skin = 0.2 * element_radius;
  setup.max_radius = element_radius;
  setup.domain_lo = lo;
  setup.domain_hi = hi;
  auto engine = makeDemEngine(setup, sc);
  engine->setState(a.state());
  engine->setBodies(a.bodies());
  engine->initialize(stillDrum());
  return engine;
}

inline dem::DemHostState state(const dem::DemEngine& e) {
  dem::DemHostState s;
  e.getState(s);
  return s;
}

// ~4 000 balls of 4-5 mm dropped as a jittered lattice onto the bottom of a turning drum with
// lifters (turningDrum): more than the OpenMP threshold (2 048), and after 400 steps of 5 us
// many lasting contacts. Engine set-up: drumSetup(0.4, 0.5, 0.004, 0.005, {-0.17, -0.17, -0.01},
// {0.17, 0.17, 0.095}).
inline dem::DemHostState denseDrumBed() {
  std::vector<Ball> balls;
  std::mt19937 rng(3);
  std::uniform_real_distribution<double> radius(0.004, 0.005), jitter(-5e-4, 5e-4), v(-0.2, 0.2);
  for (int iz = 0; iz < 8; ++iz)
    for (int iy = 0; iy < 22; ++iy)
      for (int ix = 0; ix < 23; ++ix)
        balls.push_back({-0.105 + 0.0095 * ix + jitter(rng), -0.105 + 0.0095 * iy + jitter(rng),
                         0.006 + 0.0095 * iz + jitter(rng), v(rng), v(rng) - 1.0, v(rng), radius(rng)});
  return hostState(balls, 7800.0);
}

inline dem::DrumState turningDrum(double t) {
  dem::DrumState w;
  w.radius = 0.16;
  w.z_back = 0.085;
  w.omega = 2.0;
  w.phi = w.omega * t;
  w.lifter_count = 8;
  w.lifter_height = 0.01;
  w.lifter_width = 0.01;
  return w;
}

// denseDrumBed in its drum for `steps` steps of 5 us on the OpenMP engine.
inline dem::DemHostState runDenseDrumBed(int steps) {
  auto e = dem::makeDemEngineOmp(drumSetup(0.4, 0.5, 0.004, 0.005, {-0.17, -0.17, -0.01}, {0.17, 0.17, 0.095}), false);
  e->setState(denseDrumBed());
  const double dt = 5e-6;
  e->initialize(turningDrum(0));
  for (int k = 1; k <= steps; ++k) e->step(turningDrum(k * dt), dt);
  return state(*e);
}

}  // namespace millsim::testing
