#pragma once
// Linear wall flows the mDBC ghost-node no-slip velocity (src/sph/mdbc.hpp) must hold exactly,
// on OpenMP (tests/unit/test_sph_mdbc.cpp) and CUDA (tests/gpu/test_sph_cuda_vs_omp.cpp).
#include <gtest/gtest.h>

#include <algorithm>
#include <array>
#include <cmath>
#include <string>

#include "sph/geometry.hpp"
#include "sph/sph_engine.hpp"
#include "support/momentum_box.hpp"

namespace millsim::testing {

// No-slip velocity from the ghost nodes (wall_velocity = no_slip_ghost, mdbc): a linear shear
// flow v_x = gamma y over a still floor (surface at y = 0) has no viscous force anywhere, the
// wall included, when every wall layer enters the viscous terms with the profile continued
// through the wall, v_x = gamma y_b < 0 (y_b = -(k + 1/2) dp for layer k): the wall and fluid
// lattices are then one lattice carrying one linear field, and the laminar operator sums to zero
// round it. So after one step the fluid near the floor keeps its velocity to round-off
// (asserted: 1e-9 of dt nu gamma / dp, the size of one layer's error). Adami's mean around the
// wall particle (wall_velocity = no_slip, the control) gives each layer about the first fluid row's mirror, the
// deeper layers too little shear, and the first rows change by ~dt nu gamma / dp.
// turning: the tank's walls turn at gamma about its centre and the fluid turns with them (a
// rigid rotation, linear too): every wall particle must mirror the fluid about the wall's
// velocity at the mirror plane, not its own a layer deeper (which over-turns it by gamma |g|);
// no_slip mirrors it in the wall's turning frame, which holds it too. Then the whole tank is
// checked, walls and corners included.
inline double linearWallFlowChange(const std::string& wall_velocity, bool turning = false, bool cuda = false) {
  const double dp = 0.01, rho0 = 1000, L = 0.12, gamma = 1.0, nu = 1e-3, dt = 1e-4;
  const sph::Box box{{0, 0, 0}, {L, L, 0}};
  const double cx = 0.5 * L, cy = 0.5 * L;
  sph::SphHostState st;
  sph::fillFluidBox(st, box, dp, 2, rho0);
  sph::addTankWalls(st, box, dp, 2, 3, true, turning ? sph::kBoundMoving : sph::kBoundFixed, rho0);
  auto field = [&](double x, double y) {
    return turning ? std::array<double, 2>{-gamma * (y - cy), gamma * (x - cx)} : std::array<double, 2>{gamma * y, 0};
  };
  for (std::size_t i = 0; i < st.size(); ++i)
    if (st.code[i] == sph::kFluid) {
      const auto v = field(st.pos[3 * i], st.pos[3 * i + 1]);
      st.vel[3 * i] = v[0];
      st.vel[3 * i + 1] = v[1];
    }
  sph::SphSetup s;
  s.dimension = 2;
  s.dp = dp;
  s.h = std::sqrt(2.0) * dp;
  s.c0 = 10;
  s.rho0 = rho0;
  s.viscosity = "laminar";
  s.nu = nu;
  s.ddt = "none";
  s.wall_velocity = wall_velocity;
  s.boundary = "mdbc";
  s.gravity = {0, 0, 0};
  s.rho_min = 900;
  s.rho_max = 1100;
  s.domain_lo = {-0.1, -0.1, -0.1};
  s.domain_hi = {L + 0.1, L + 0.1, 0.1};
  s.motion_center = {cx, cy, 0};
  auto e = makeSphEngine(s, cuda);
  e->setState(st);
  const double w = turning ? gamma : 0.0;
  e->initialize(sph::SphMotion{0, w});
  e->step(dt, sph::SphMotion{0.5 * w * dt, w}, sph::SphMotion{w * dt, w});
  sph::SphHostState out;
  e->getState(out);
  double worst = 0;
  int checked = 0;
  for (std::size_t i = 0; i < out.size(); ++i) {
    const double x = out.pos[3 * i], y = out.pos[3 * i + 1];
    if (out.code[i] != sph::kFluid) continue;
    // Shear: clear of the side walls' reach (2h = 2.8 dp past their first layer at -dp/2), near
    // the floor. Rotation: everywhere.
    if (!turning && (x < 3 * dp || x > L - 3 * dp || y > 3 * dp)) continue;
    ++checked;
    const auto v = field(st.pos[3 * i], st.pos[3 * i + 1]);
    worst = std::max(worst, std::hypot(out.vel[3 * i] - v[0], out.vel[3 * i + 1] - v[1]));
  }
  EXPECT_GT(checked, 10);
  return worst / (dt * nu * gamma / dp);
}

}  // namespace millsim::testing
