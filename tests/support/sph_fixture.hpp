#pragma once
// Small SPH scenes for tests, built straight on the engine (the same code `millsim run` uses).
#include <cmath>
#include <memory>

#include "sph/geometry.hpp"
#include "sph/sph_engine.hpp"
#include "sph/sph_kernels.hpp"

namespace millsim::testing {

// A 2D tank of width w and height h_tank holding a column of fluid of width a and height
// h_fluid against its left wall; the setup follows the DualSPHysics rules (h = coefh dp sqrt(2),
// c0 = coefsound sqrt(g h_fluid)).
struct TankScene {
  double w = 0.2, h_tank = 0.3, a = 0.2, h_fluid = 0.2, dp = 0.005;
  double coefh = 1.0, coefsound = 20, rho0 = 1000;
  int layers = 3;
  sph::SphSetup setup() const {
    sph::SphSetup s;
    s.dimension = 2;
    s.dp = dp;
    s.h = coefh * dp * std::sqrt(2.0);
    s.c0 = coefsound * std::sqrt(9.81 * h_fluid);
    s.rho0 = rho0;
    s.rho_min = 700;
    s.rho_max = 1300;
    const double m = 0.5 * std::max(w, h_tank);
    s.domain_lo = {-m, -m, -1};
    s.domain_hi = {w + m, h_tank + m, 1};
    return s;
  }
  sph::SphHostState state(const sph::SphSetup& s) const {
    sph::SphHostState st;
    sph::fillFluidBox(st, {{0, 0, 0}, {a, h_fluid, 0}}, dp, 2, rho0);
    sph::addTankWalls(st, {{0, 0, 0}, {w, h_tank, 0}}, dp, 2, layers, false, sph::kBoundFixed, rho0);
    sph::hydrostaticDensity(st, h_fluid, 9.81, rho0, s.c0, s.gamma);
    return st;
  }
};

inline double runTo(sph::SphEngine& e, double t_end, double t = 0) {
  while (t < t_end) {
    const double dt = std::min(e.nextDt(), t_end - t);
    e.step(dt, {}, {});
    t += dt;
  }
  return t;
}

}  // namespace millsim::testing
