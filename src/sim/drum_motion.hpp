#pragma once
// Prescribed wall motion of a drum case: the compaction piston (back plate) moves from the
// generation length to the mill length during the first 75% of the compaction phase and then
// rests; the drum starts rotating at drum.start_time, ramping linearly over drum.spin_up.
// Rotation is clockwise seen from +z (omega < 0), so the charge is lifted on the LEFT of the
// front view, as in the paper's images (angle measured from the highest point rightwards).
#include <algorithm>
#include <cmath>

#include "dem/dem_engine.hpp"
#include "millsim/scene/scene.hpp"

namespace millsim::sim {

// Critical speed Nc = 60/(2 pi) sqrt(g / (R - r)) [rpm] (paper; r = mean ball radius).
inline double criticalSpeedRpm(double drum_radius, double ball_radius, double g) {
  return 60.0 / (2.0 * std::acos(-1.0)) * std::sqrt(g / (drum_radius - ball_radius));
}

class DrumMotion {
 public:
  DrumMotion(const scene::Scene& s, double generation_length, double speed_rpm)
      : m_scene(s), m_gen_length(generation_length), m_omega_full(-speed_rpm * 2.0 * std::acos(-1.0) / 60.0) {}

  double pistonTravelTime() const { return 0.75 * m_scene.compaction.duration; }

  dem::DrumState at(double t, double phi) const {
    dem::DrumState w;
    w.radius = 0.5 * m_scene.drum.diameter;
    const double L = m_scene.drum.length, travel = pistonTravelTime();
    if (travel > 0 && t < travel && m_gen_length > L) {
      const double v = (m_gen_length - L) / travel;
      w.z_back = m_gen_length - v * t;
      w.v_back = -v;
    } else {
      w.z_back = L;
      w.v_back = 0;
    }
    w.omega = omega(t);
    w.phi = phi;
    w.phase0 = 0.5 * std::acos(-1.0);  // a lifter at the top at t = 0
    w.lifter_count = m_scene.drum.lifters.count;
    w.lifter_height = m_scene.drum.lifters.height;
    w.lifter_width = m_scene.drum.lifters.width;
    return w;
  }

  double omega(double t) const {
    const double t0 = m_scene.drum.start_time, ramp = m_scene.drum.spin_up;
    if (t < t0) return 0.0;
    if (ramp > 0 && t < t0 + ramp) return m_omega_full * (t - t0) / ramp;
    return m_omega_full;
  }
  double fullOmega() const { return m_omega_full; }

  // One DEM step of dt with the walls where they are at its end: the drum turned by the speed at
  // t + dt, the piston moved. Advances t and phi (every drum run steps this way).
  void stepDem(dem::DemEngine& dem, double& t, double& phi, double dt) const {
    phi += omega(t + dt) * dt;
    dem.step(at(t + dt, phi), dt);
    t += dt;
  }

 private:
  const scene::Scene& m_scene;
  double m_gen_length;
  double m_omega_full;
};

}  // namespace millsim::sim
