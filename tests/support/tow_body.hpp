#pragma once
// Towing a body through fluid at rest (the towed cylinder and towed sphere tests), or spinning
// it in place (the rotating sphere): body 0 of an SPH engine moves at a constant velocity from
// `centre` and turns at a constant rate `omega` (its particles keep their offsets: a sphere's
// lattice does not turn, its surface moves), and the fluid's force and torque on it are averaged
// over t_avg < t <= t_end (after the start-up transient).
#include <algorithm>
#include <array>
#include <string>
#include <vector>

#include "sph/sph_engine.hpp"

namespace millsim::testing {

// The set-up the body-in-viscous-fluid tests share: fluid of rho0 = 1000 kg/m3 without gravity,
// a laminar viscosity nu, c0 = 4 m/s (their flows stay below 0.02 m/s: Mach < 0.005; the step is
// the viscous term's limit, not the CFL one), Fourtakas density diffusion, shifting, Verlet,
// density bounds 900-1100. The caller sets the domain (and anything it varies).
inline sph::SphSetup viscousBodySetup(int dim, double dp, double h, double nu, const std::string& viscosity,
                                      const std::string& wall_velocity) {
  sph::SphSetup s;
  s.dimension = dim;
  s.dp = dp;
  s.h = h;
  s.c0 = 4.0;
  s.rho0 = 1000;
  s.viscosity = viscosity;
  s.nu = nu;
  s.wall_velocity = wall_velocity;
  s.ddt = "fourtakas";
  s.shifting = true;
  s.integrator = "verlet";
  s.gravity = {0, 0, 0};
  s.rho_min = 900;
  s.rho_max = 1100;
  return s;
}

struct TowAverage {
  std::array<double, 3> force{};   // mean fluid force on the body over the window
  std::array<double, 3> torque{};  // mean fluid torque about its centre
  long long steps = 0;
};

inline TowAverage towAndAverage(sph::SphEngine& e, std::array<double, 3> centre, const std::array<double, 3>& velocity,
                                double t_end, double t_avg, const std::array<double, 3>& omega = {}) {
  auto body = [&]() { return std::vector<sph::SphBody>{sph::SphBody{centre, velocity, omega}}; };
  e.setBodyKinematics(body());
  e.initialize({});
  TowAverage r;
  double t = 0;
  int samples = 0;
  while (t < t_end) {
    const double dt = std::min(e.nextDt(), t_end - t);
    for (int k = 0; k < 3; ++k) centre[k] += velocity[k] * dt;
    e.setBodyKinematics(body());
    e.step(dt, {}, {});
    t += dt;
    ++r.steps;
    if (t > t_avg) {
      const auto load = e.bodyLoads()[0];
      for (int k = 0; k < 3; ++k) {
        r.force[k] += load.force[k];
        r.torque[k] += load.torque[k];
      }
      ++samples;
    }
  }
  for (double& f : r.force) f /= samples > 0 ? samples : 1;
  for (double& q : r.torque) q /= samples > 0 ? samples : 1;
  return r;
}

}  // namespace millsim::testing
