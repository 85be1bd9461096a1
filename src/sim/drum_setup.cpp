// A drum case's DEM settings from its scene and charge (see header).
#include "sim/drum_setup.hpp"

#include <algorithm>
#include <cmath>
#include <sstream>
#include <stdexcept>

#include "dem/contact/damping.hpp"
#include "millsim/core/error.hpp"
#include "sim/drum_motion.hpp"
#include "sim/run_outputs.hpp"

namespace millsim::sim {

double drumTimeStep(const scene::Scene& scene, const ChargeSetup& charge) {
  if (scene.time.dt_mode == "fixed") return scene.time.dt_fixed;
  // Shortest Hertz contact: the smallest balls at the reference impact speed, ball-ball
  // (R* = r/2, m* = m/2) and ball-wall (R* = r, m* = factor * m). dt = t_c / N.
  const double e_star = dem::effectiveModulus(scene.dem.youngs_modulus, scene.dem.poisson);
  // DCDEM balls touch element on element: R* = dp/4 (pairs), dp/2 (walls), with the balls' masses.
  const double r = charge.min_radius, m = scene.dem.density * 4.0 / 3.0 * std::acos(-1.0) * r * r * r;
  const double r_contact = scene.dem.representation == "dcdem" ? 0.5 * scene.dem.element_spacing : r;
  const double v = scene.dem.impact_velocity;
  const double factor = dem::wallMassFactor(dem::dampingModelFromName(scene.dem.damping));
  const double tc = std::min(dem::hertzContactTime(0.5 * m, 0.5 * r_contact, e_star, v),
                             dem::hertzContactTime(factor * m, r_contact, e_star, v));
  return tc / scene.time.dt_divisor;
}

dem::DemSetup demContactSetup(const scene::Scene& scene) {
  dem::DemSetup setup;
  const auto model = dem::dampingModelFromName(scene.dem.damping);
  setup.k_coef = 4.0 / 3.0 * dem::effectiveModulus(scene.dem.youngs_modulus, scene.dem.poisson);
  setup.alpha = dem::dampingAlpha(model, scene.dem.restitution);
  setup.wall_mass_factor = dem::wallMassFactor(model);
  setup.friction = scene.dem.friction;
  return setup;
}

dem::DemSetup drumDemSetup(const scene::Scene& scene, const ChargeSetup& charge) {
  dem::DemSetup setup = demContactSetup(scene);
  setup.tanh_smoothing = scene.dem.friction_smoothing == "tanh";
  setup.dualsphysics_tangential = scene.dem.tangential == "dualsphysics";
  setup.gravity = scene.gravity;
  setup.skin = scene.dem.skin * charge.min_radius;
  setup.max_radius = charge.max_radius;
  if (scene.dem.representation == "dcdem") {
    setup.skin = scene.dem.skin * scene.dem.element_spacing;
    setup.max_radius = 0.5 * scene.dem.element_spacing;
  }
  const double R = 0.5 * scene.drum.diameter, margin = 2 * charge.max_radius;
  setup.domain_lo = {-R - margin, -R - margin, -margin};
  setup.domain_hi = {R + margin, R + margin, charge.generation_length + margin};
  return setup;
}

double drumSpeedRpm(const scene::Scene& scene, const ChargeSetup& charge) {
  if (scene.drum.critical_fraction <= 0) return scene.drum.speed_rpm;
  const auto& g = scene.gravity;
  const double gn = std::sqrt(g[0] * g[0] + g[1] * g[1] + g[2] * g[2]);
  return scene.drum.critical_fraction * criticalSpeedRpm(0.5 * scene.drum.diameter, charge.mean_radius, gn);
}

vision::AngleOptions drumAngleOptions(const scene::Scene& scene) {
  vision::AngleOptions opt;
  opt.pixels_per_mm = scene.angle.pixels_per_mm;
  opt.threshold = scene.angle.threshold;
  opt.smoothing_px = scene.angle.smoothing_px;
  opt.fit_offset_mm = scene.angle.fit_offset_mm;
  opt.fit_length_mm = scene.angle.fit_length_mm;
  return opt;
}

std::vector<std::string> drumSeriesColumns() {
  return {"time_s",  "kinetic_J", "potential_J", "dissipated_J",  "work_in_J",         "elastic_J", "drum_torque_Nm",
          "power_W", "omega_rpm", "piston_z_m",  "max_speed_m_s", "energy_residual_J", "com_x_m",   "com_y_m"};
}

std::vector<double> drumSeriesRow(double t, const dem::DemSums& now, const dem::DrumState& drum, double residual) {
  return {t,
          now.kinetic,
          now.potential,
          now.dissipated,
          now.work_in,
          now.elastic,
          now.drum_torque,
          -now.drum_torque * drum.omega,
          std::abs(drum.omega) * 60.0 / (2 * std::acos(-1.0)),
          drum.z_back,
          now.max_speed,
          residual,
          now.com_x,
          now.com_y};
}

void fillDrumEnergy(RunSummary& s, const dem::DemSums& now, const dem::DemSums& start) {
  fillDemEnergy(s, now.kinetic, now.potential, now.dissipated, now.work_in, now.elastic);
  s.energy_residual = (now.work_in - start.work_in) + (now.work_external - start.work_external) -
                      ((now.kinetic - start.kinetic) + (now.potential - start.potential) +
                       (now.elastic - start.elastic) + (now.dissipated - start.dissipated));
}

void finishDrumAngle(const vision::FrontViewAngle& angle, RunSummary& s, const std::filesystem::path& out, bool write) {
  s.angle_frames = angle.frames();
  vision::AngleResult r;
  try {
    r = angle.measure();
    s.angle_valid = true;
    s.angle_of_repose_deg = r.angle_deg;
    s.angle_stderr_deg = r.stderr_deg;
    s.angle_points = r.points_used;
  } catch (const std::runtime_error& e) {
    s.angle_valid = false;
    s.angle_error = e.what();
  }
  if (write) angle.writeImages(out, s.angle_valid ? &r : nullptr);
}

void checkBallsInDrum(const std::vector<double>& pos, int lo, int hi, double z0, const scene::Scene& scene,
                      const ChargeSetup& charge, double t, const std::string& label) {
  const double R = 0.5 * scene.drum.diameter, tol = 0.5 * charge.max_radius, zmax = charge.generation_length;
  for (int h = lo; h < hi; ++h) {
    const std::size_t i = 3 * static_cast<std::size_t>(h);
    const double x = pos[i], y = pos[i + 1], z = pos[i + 2] - z0;
    if (std::sqrt(x * x + y * y) > R + tol || z < -tol || z > zmax + tol) {
      std::ostringstream m;
      m << label << "DEM: ball " << h - lo << " escaped the drum at t = " << t << " s, position (" << x << ", " << y
        << ", " << z << ") m: contacts too soft for the speeds reached (raise E or lower dt)";
      throw core::SimulationError(m.str());
    }
  }
}

}  // namespace millsim::sim
