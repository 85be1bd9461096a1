#include "sim/sph_run.hpp"

#include <omp.h>

#include <algorithm>
#include <chrono>
#include <cstdio>
#include <cmath>
#include <filesystem>
#include <fstream>
#include <limits>
#include <nlohmann/json.hpp>
#include <sstream>

#include "millsim/backend/info.hpp"
#include "millsim/core/error.hpp"
#include "millsim/io/fields_writer.hpp"
#include "millsim/io/plot_png.hpp"
#include "sim/engine_factory.hpp"
#include "sim/run_outputs.hpp"
#include "sph/eos.hpp"
#include "sph/geometry.hpp"
#include "sph/sph_kernels.hpp"

namespace millsim::sim {

namespace fs = std::filesystem;

SphRun::SphRun(const scene::Scene& scene, const RunOptions& options) : m_scene(scene), m_options(options) {
  if (options.threads > 0) omp_set_num_threads(options.threads);
  m_setup = sphSetupOf(scene);
  m_probes = parseProbes(scene);
  m_engine = makeSphEngine(m_setup, options);
  const sph::SphHostState particles = sphParticlesOf(scene, m_setup);
  m_particles = particles.size();
  m_engine->setState(particles);
  m_omega_full = scene.has_tank ? scene.tank.rotation_rpm * 2 * std::acos(-1.0) / 60.0 : 0.0;
  m_engine->initialize(motionAt(0));
  const sph::SphSums s0 = m_engine->sums();
  m_fluid0 = s0.fluid;
  m_fluid_mass0 = s0.fluid_mass;
}

sph::SphMotion SphRun::motionAt(double t) const {
  // Linear ramp of the rate over spin_up, then constant: theta is its integral.
  const double ramp = m_scene.tank.spin_up;
  sph::SphMotion m;
  if (m_omega_full == 0) return m;
  if (ramp > 0 && t < ramp) {
    m.omega = m_omega_full * t / ramp;
    m.theta = 0.5 * m_omega_full * t * t / ramp;
  } else {
    m.omega = m_omega_full;
    m.theta = m_omega_full * (t - 0.5 * ramp);
  }
  return m;
}

std::vector<std::string> SphRun::stages() const {
  std::vector<std::string> s{"neighbour_build", "sph_pressure", "sph_interaction"};
  if (m_setup.sps()) s.push_back("sph_sps_stress");
  s.push_back(m_setup.integrator == "symplectic" ? "sph_symplectic" : "sph_verlet");
  if (m_setup.shifting) s.push_back("sph_shifting");
  return s;
}

void SphRun::writeSummary(const sph::SphSums& now, const std::vector<double>& last_probe) const {
  const RunSummary& s = m_summary;
  nlohmann::ordered_json j = summaryHead(s, m_scene.name, m_scene.source);
  j["particles"] = {{"dem_spheres", 0}, {"sph", m_particles}, {"sph_fluid", m_fluid0}, {"sph_boundary", now.boundary}};
  j["stages"] = stages();
  j["memory_bytes"] = memoryJson(m_engine->memoryBytes());
  j["sph"] = {{"dimension", m_setup.dimension}, {"dp_m", m_setup.dp},         {"h_m", m_setup.h},
              {"c0_m_s", m_setup.c0},           {"kernel", m_setup.kernel},   {"ddt", m_setup.ddt},
              {"viscosity", m_setup.viscosity}, {"integrator", m_setup.integrator}, {"shifting", m_setup.shifting}};
  // The diffusion terms' stability limits on the step (diffusion_stability.hpp), when they are on.
  if (std::isfinite(m_engine->viscousDtLimit())) j["sph"]["dt_viscous_limit_s"] = m_engine->viscousDtLimit();
  if (std::isfinite(m_engine->ddtDtLimit())) j["sph"]["dt_ddt_limit_s"] = m_engine->ddtDtLimit();
  const long long excluded = now.excluded_density + now.excluded_domain;
  j["excluded"] = {{"density", now.excluded_density},
                   {"domain", now.excluded_domain},
                   {"total", excluded},
                   {"fraction", m_fluid0 > 0 ? double(excluded) / double(m_fluid0) : 0.0}};
  j["fluid_mass_kg"] = {{"initial", m_fluid_mass0},
                        {"active", now.fluid_mass},
                        {"including_excluded", now.fluid_mass + double(excluded) * (m_fluid0 ? m_fluid_mass0 / m_fluid0 : 0.0)},
                        {"per_metre_of_depth", m_setup.dimension == 2}};
  j["energy"] = {{"kinetic_J", now.kinetic}, {"potential_J", now.potential}};
  j["max_speed_m_s"] = now.max_speed;
  j["front_x_m"] = now.max_x;
  nlohmann::ordered_json probes = nlohmann::ordered_json::object();
  for (std::size_t k = 0; k < m_probes.size(); ++k)
    probes[m_probes[k].name] = std::isfinite(last_probe[k]) ? nlohmann::ordered_json(last_probe[k]) : nullptr;
  j["probes_pressure_Pa"] = probes;
  writeJsonFile(fs::path(m_options.out_dir) / "summary.json", j);
}

const RunSummary& SphRun::run() {
  const fs::path out(m_options.out_dir);
  if (m_options.write_outputs) fs::create_directories(out);
  m_summary = RunSummary{};
  m_summary.backend = m_engine->backendName();
  m_summary.precision = m_engine->precisionName();
  m_summary.threads = m_summary.backend == std::string("omp") ? omp_get_max_threads() : 1;
  m_summary.particles = m_particles;

  std::vector<std::string> columns{"time_s",        "dt_s",    "kinetic_J",   "potential_J",      "max_speed_m_s",
                                   "front_x_m",     "rho_min", "rho_max",     "fluid_particles", "excluded_density",
                                   "excluded_domain", "tank_angle_deg"};
  for (const Probe& p : m_probes) columns.push_back("p_" + p.name + "_Pa");
  std::unique_ptr<SeriesWriter> series;
  std::unique_ptr<io::FieldsWriter> fields;
  if (m_options.write_outputs) {
    series = std::make_unique<SeriesWriter>(out / "series.csv", columns, false);
    if (m_scene.output.fields_every > 0) fields = std::make_unique<io::FieldsWriter>(out, false);
  }
  const sph::TaitEos<double> eos = sph::TaitEos<double>::make(m_setup.rho0, m_setup.c0, m_setup.gamma);
  double t = 0, dt = 0;
  long long step = 0;
  auto writeFields = [&]() {
    sph::SphHostState s;
    m_engine->getState(s);
    io::FieldFrame f = fieldFrame(t, step, s.pos, s.vel);
    f.arrays.push_back({"density", 1, std::vector<float>(s.rho.begin(), s.rho.end())});
    std::vector<float> press(s.size()), code(s.size());
    for (std::size_t i = 0; i < s.size(); ++i) {
      press[i] = float(eos.pressure(s.rho[i]));
      code[i] = float(s.code[i]);
    }
    f.arrays.push_back({"pressure", 1, press});
    f.arrays.push_back({"code", 1, code});  // 0 fluid, 1 fixed wall, 2 moving wall, 3/4 excluded
    fields->write(f);
  };

  const double t_end = m_scene.time.end;
  double next_series = 0, next_fields = 0;
  ProgressLine progress(m_options.progress, t_end);
  std::vector<double> probe_values(m_probes.size(), std::numeric_limits<double>::quiet_NaN());
  sph::SphSums now = m_engine->sums();
  const auto wall0 = std::chrono::steady_clock::now();
  // A picture of the last state (side view x-y, coloured by pressure), next to the numbers.
  auto snapshot = [&]() {
    sph::SphHostState s;
    m_engine->getState(s);
    std::vector<double> x, y, p;
    std::vector<bool> wall;
    double p_max = 1;
    for (std::size_t i = 0; i < s.size(); ++i) {
      if (sph::isExcluded(s.code[i])) continue;
      x.push_back(s.pos[3 * i]);
      y.push_back(s.pos[3 * i + 1]);
      p.push_back(eos.pressure(s.rho[i]));
      wall.push_back(s.code[i] != sph::kFluid);
      if (!wall.back()) p_max = std::max(p_max, p.back());
    }
    const auto& lo = m_setup.domain_lo;
    const auto& hi = m_setup.domain_hi;
    const double px = 900.0 / std::max(hi[0] - lo[0], hi[1] - lo[1]);
    char title[160];
    std::snprintf(title, sizeof title, "%s  t = %.3f s  (%s)", m_scene.name.c_str(), t,
                  m_setup.dimension == 2 ? "x-y" : "x-y, all depths");
    io::writeParticleSnapshot((out / "snapshot.png").string(), x, y, p, wall, 0.5 * m_setup.dp, {lo[0], hi[0], lo[1], hi[1]},
                              px, 0.0, p_max, title, "p [Pa]");
  };
  auto finish = [&](const char* status) {
    progress.finish();
    now = m_engine->sums();
    if (m_options.write_outputs) snapshot();
    markRunEnd(m_summary, status, t, step, wall0);
    m_summary.dt = dt;
    m_summary.energy_kinetic = now.kinetic;
    m_summary.energy_potential = now.potential;
    if (m_options.write_outputs) writeSummary(now, probe_values);
  };
  try {
    while (true) {
      if (double(m_engine->excludedCount()) > m_scene.sph.parts_out_max * double(m_fluid0)) {
        now = m_engine->sums();
        const long long excluded = now.excluded_density + now.excluded_domain;
        std::ostringstream m;
        m << "SPH: " << excluded << " of " << m_fluid0 << " fluid particles excluded by t = " << t << " s ("
          << now.excluded_density << " outside density [" << m_setup.rho_min << ", " << m_setup.rho_max << "] kg/m3, "
          << now.excluded_domain << " outside the domain), more than sph.parts_out_max = " << m_scene.sph.parts_out_max
          << ": the flow is unstable for this resolution and time step (lower cfl, raise coefsound or use ddt)";
        throw core::SimulationError(m.str());
      }
      if (t >= next_series - 1e-12 * t_end) {
        now = m_engine->sums();
        for (std::size_t k = 0; k < m_probes.size(); ++k) probe_values[k] = m_engine->probePressure(m_probes[k].x);
        if (series) {
          std::vector<double> row{t,
                                  dt,
                                  now.kinetic,
                                  now.potential,
                                  now.max_speed,
                                  now.max_x,
                                  now.rho_min,
                                  now.rho_max,
                                  double(now.fluid),
                                  double(now.excluded_density),
                                  double(now.excluded_domain),
                                  motionAt(t).theta * 180.0 / std::acos(-1.0)};
          row.insert(row.end(), probe_values.begin(), probe_values.end());
          series->row(row);
        }
        next_series += m_scene.output.series_every;
      }
      if (fields && t >= next_fields - 1e-12 * t_end) {
        writeFields();
        next_fields += m_scene.output.fields_every;
      }
      if (t >= t_end - 1e-12 * t_end) break;
      dt = std::min(m_engine->nextDt(), t_end - t);
      m_engine->step(dt, motionAt(t + 0.5 * dt), motionAt(t + dt));
      t += dt;
      ++step;
      progress.update(t, step);
    }
  } catch (const core::SimulationError& e) {
    m_summary.error = e.what();
    // Keep the state that failed next to the last good snapshots, for a look in ParaView.
    if (fields) writeFields();
    finish("failed");
    throw;
  }
  finish("ok");
  return m_summary;
}

}  // namespace millsim::sim
