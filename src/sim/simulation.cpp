// The time loop of a drum case and its observers (series, fields, frames for the angle of
// repose, checkpoints, progress). Physics lives in the DEM engine; this file only schedules.
#include "millsim/sim/simulation.hpp"

#include <omp.h>
#include <unistd.h>

#include <chrono>
#include <cmath>
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <iomanip>
#include <sstream>

#include "dem/dem_engine.hpp"
#include "millsim/backend/info.hpp"
#include "millsim/core/error.hpp"
#include "millsim/io/fields_writer.hpp"
#include "millsim/vision/front_view_angle.hpp"
#include "sim/charge_setup.hpp"
#include "sim/dem_checkpoint.hpp"
#include "sim/drum_motion.hpp"
#include "sim/drum_setup.hpp"
#include "sim/engine_factory.hpp"
#include "sim/run_outputs.hpp"
#include "sim/sph_run.hpp"
#include "sim/stirred_run.hpp"
#include "sim/wet_mill.hpp"

namespace millsim::sim {

namespace fs = std::filesystem;

struct Simulation::Impl {
  scene::Scene scene;
  RunOptions options;
  ChargeSetup charge;
  // DCDEM balls (dem.representation = "dcdem"): the engine's particles are their elements.
  bool dcdem = false;
  std::size_t particles = 0;
  std::unique_ptr<DrumMotion> motion;
  std::unique_ptr<dem::DemEngine> engine;
  RunSummary summary;
  double dt = 0;
  double t = 0;
  double phi = 0;
  long long step = 0;
  // Angle of repose: front-view frames summed into a heat map.
  std::unique_ptr<vision::FrontViewAngle> angle;
  // Wet mill: the slurry, poured when the drum starts (scene.effect_sph with <dem>).
  std::unique_ptr<WetMill> wet;
  double next_frame_t = 0;
  // Steady-window bookkeeping for the mean shaft power.
  double steady_t0 = -1, steady_work0 = 0;
  dem::DemSums sums0;
  dem::BallKinematics kinematics;  // the series rows' escape check reuses it

  Impl(const scene::Scene& s, const RunOptions& o) : scene(s), options(o) {
    if (!scene.effect_dem)
      throw core::InputError(scene.source, 0, "the case has no <dem> element: nothing to simulate");
    if (options.threads > 0) omp_set_num_threads(options.threads);
    charge = buildCharge(scene);
    const double rpm = drumSpeedRpm(scene, charge);
    motion = std::make_unique<DrumMotion>(scene, charge.generation_length, rpm);
    if (scene.angle.enabled)
      angle = std::make_unique<vision::FrontViewAngle>(scene.drum.diameter, drumAngleOptions(scene));
    dt = drumTimeStep(scene, charge);
    engine = makeEngine();
    dcdem = scene.dem.representation == "dcdem";
    if (dcdem) {
      const DcdemCharge dc = dcdemCharge(charge.state, scene.dem.element_spacing);
      engine->setState(dc.state);
      engine->setBodies(dc.bodies);
      particles = dc.state.size();
    } else {
      engine->setState(charge.state);
      particles = charge.state.size();
    }
    if (!options.restart.empty()) restoreCheckpoint();
    engine->initialize(motion->at(t, phi));
    sums0 = engine->sums();
    if (!options.restart.empty()) sums0 = restoredSums0;
  }

  dem::DemSums restoredSums0;

  std::unique_ptr<dem::DemEngine> makeEngine() const { return makeDemEngine(drumDemSetup(scene, charge), options); }

  // The front view sees balls: DCDEM bodies are drawn as their balls (centre, ball radius).
  void captureFrame() {
    std::vector<double> cx, cy;
    const dem::DemHostState s = dem::ballStates(*engine);
    for (std::size_t i = 0; i < s.size(); ++i) {
      cx.push_back(s.pos[3 * i]);
      cy.push_back(s.pos[3 * i + 1]);
    }
    angle->addFrame(cx, cy, s.radius);
  }

  void restoreCheckpoint();
  void writeCheckpoint(const fs::path& path) const;
  void finishAngle(const fs::path& out);
  void fillEnergy(const dem::DemSums& now) { fillDrumEnergy(summary, now, sums0); }
  void run();
};

void Simulation::Impl::finishAngle(const fs::path& out) {
  summary.angle_frames = 0;
  if (angle) finishDrumAngle(*angle, summary, out, options.write_outputs);
}

void Simulation::Impl::run() {
  const fs::path out(options.out_dir);
  const bool restart = !options.restart.empty();
  if (options.write_outputs) fs::create_directories(out);
  summary = RunSummary{};
  summary.backend = engine->backendName();
  summary.precision = engine->precisionName();
  summary.threads = summary.backend == std::string("omp") ? omp_get_max_threads() : 1;
  summary.dt = dt;
  summary.particles = particles;
  summary.charge_mass_kg = charge.total_mass;
  summary.omega_rad_s = std::abs(motion->fullOmega());

  std::unique_ptr<SeriesWriter> series;
  std::unique_ptr<io::FieldsWriter> fields;
  if (options.write_outputs) {
    series = std::make_unique<SeriesWriter>(out / "series.csv", drumSeriesColumns(), restart, t);
    if (scene.output.fields_every > 0) fields = std::make_unique<io::FieldsWriter>(out, restart);
  }
  const double t_end = scene.time.end;
  const double series_dt = scene.output.series_every, fields_dt = scene.output.fields_every;
  const double cp_dt = scene.output.checkpoint_every;
  double next_series = t, next_fields = t, next_cp = cp_dt > 0 ? t + cp_dt : 1e300;
  const double frame_dt = (t_end - scene.angle.start_time) / std::max(1, scene.angle.frames);
  next_frame_t = scene.angle.start_time + frame_dt * ((angle ? angle->frames() : 0) + 1);
  const double steady_start = scene.angle.enabled ? scene.angle.start_time : scene.drum.start_time + scene.drum.spin_up;

  ProgressLine progress(options.progress, t_end);
  const auto wall0 = std::chrono::steady_clock::now();
  auto writeFields = [&]() {
    dem::DemHostState s;
    engine->getState(s);
    fields->write(demFieldFrame(t, step, s));
  };

  try {
    while (true) {
      if (t >= next_series - 1e-12 * t_end) {
        const dem::DemSums now = engine->sums();
        engine->ballKinematics(kinematics);  // positions only: a full getState copies the contact history
        checkBallsInDrum(kinematics.pos, 0, static_cast<int>(kinematics.size()), 0.0, scene, charge, t, "");
        fillEnergy(now);
        if (series) series->row(drumSeriesRow(t, now, motion->at(t, phi), summary.energy_residual));
        if (steady_t0 < 0 && t >= steady_start) {
          steady_t0 = t;
          steady_work0 = now.work_in;
        }
        next_series += series_dt;
      }
      if (fields && t >= next_fields - 1e-12 * t_end) {
        writeFields();
        next_fields += fields_dt;
      }
      if (angle && t >= next_frame_t - 0.5 * dt && angle->frames() < scene.angle.frames) {
        captureFrame();
        if (wet) wet->captureSurface();
        next_frame_t += frame_dt;
      }
      if (options.write_outputs && t >= next_cp - 0.5 * dt) {
        writeCheckpoint(out / "checkpoint.h5");
        next_cp += cp_dt;
      }
      if (t >= t_end - 0.5 * dt) break;
      if (scene.effect_sph && !wet && t >= scene.drum.start_time - 0.5 * dt) {
        wet = std::make_unique<WetMill>(scene, options, dem::ballStates(*engine), phi, t);
      }
      if (wet) {
        wet->advance(*engine, *motion, t, phi, step, dt);
      } else {
        motion->stepDem(*engine, t, phi, dt);
        ++step;
      }
      progress.update(t, step);
    }
  } catch (const core::SimulationError& e) {
    progress.finish();
    const fs::path summary_json = out / "summary.json";
    recordFailedRun(summary, e.what(), t, step, wall0, options.write_outputs ? &summary_json : nullptr,
                    engine->memoryBytes(), scene.name, scene.source);
    throw;
  }
  progress.finish();
  markRunEnd(summary, "ok", t, step, wall0);
  summary.neighbour_rebuilds = engine->neighbourRebuilds();
  const dem::DemSums now = engine->sums();
  fillEnergy(now);
  if (steady_t0 >= 0 && t > steady_t0) {
    summary.power_W = (now.work_in - steady_work0) / (t - steady_t0);
    summary.torque_Nm = summary.omega_rad_s > 0 ? summary.power_W / summary.omega_rad_s : 0;
  }
  finishAngle(out);
  if (wet) wet->finish(out, summary, options.write_outputs);
  if (options.write_outputs) {
    writeCheckpoint(out / "checkpoint.h5");
  }
}

namespace {

// The real arrays of a checkpoint's DCDEM bodies, by dataset name (the particles': dem_checkpoint.cpp).
std::vector<std::pair<const char*, std::vector<double>*>> bodyArrays(dem::DemBodies& b) {
  return {{"body_pos", &b.pos},       {"body_vel", &b.vel},      {"body_ang_mom", &b.ang_mom},
          {"body_quat", &b.quat},     {"body_mass", &b.mass},    {"body_inertia", &b.inertia},
          {"body_offset", &b.offset}, {"body_radius", &b.radius}};
}

// Body arrays a checkpoint has only since they were added: a missing one restarts from zero.
std::vector<std::pair<const char*, std::vector<double>*>> optionalBodyArrays(dem::DemBodies& b) {
  return {{"body_work_external", &b.work_external}};
}

}  // namespace

void Simulation::Impl::writeCheckpoint(const fs::path& path) const {
  io::CheckpointData cp = demCheckpoint(*engine, t, step);
  if (dcdem) {
    dem::DemBodies b;
    engine->getBodies(b);
    cp.ints["body_start"].assign(b.start.begin(), b.start.end());
    for (const auto& [key, v] : bodyArrays(b)) cp.reals[key] = *v;
    for (const auto& [key, v] : optionalBodyArrays(b))
      if (!v->empty()) cp.reals[key] = *v;
  }
  cp.scalars["phi"] = phi;
  cp.scalars["dt"] = dt;
  cp.scalars["steady_t0"] = steady_t0;
  cp.scalars["steady_work0"] = steady_work0;
  cp.scalars["e0_kinetic"] = sums0.kinetic;
  cp.scalars["e0_potential"] = sums0.potential;
  cp.scalars["e0_elastic"] = sums0.elastic;
  if (angle && angle->frames() > 0) {
    const auto& heat = angle->accumulator();
    cp.ints["heat_counts"].assign(heat.counts().begin(), heat.counts().end());
    cp.scalars["heat_width"] = heat.width();
    cp.scalars["heat_height"] = heat.height();
    cp.scalars["heat_frames"] = heat.frames();
  }
  if (wet) wet->save(cp);
  io::writeCheckpoint(path, cp);
}

void Simulation::Impl::restoreCheckpoint() {
  const io::CheckpointData cp = io::readCheckpoint(options.restart);
  if (cp.scalars.count("stirred"))
    throw core::InputError(options.restart + ": a stirred mill's checkpoint; " + scene.source + " is a drum");
  const dem::DemHostState s = takeDemState(cp, options.restart);
  auto real = [&](const char* k) {
    auto it = cp.reals.find(k);
    if (it == cp.reals.end()) throw core::InputError(options.restart + ": checkpoint lacks '" + k + "'");
    return it->second;
  };
  if (!dcdem && cp.ints.count("body_start"))
    throw core::InputError(options.restart +
                           ": checkpoint holds DCDEM bodies, the case asks for spheres "
                           "(add dem representation=\"dcdem\")");
  engine->setState(s);
  if (dcdem) {
    if (!cp.ints.count("body_start"))
      throw core::InputError(options.restart + ": checkpoint has no DCDEM bodies, the case asks for dcdem balls");
    dem::DemBodies b;
    const auto& start = cp.ints.at("body_start");
    b.start.assign(start.begin(), start.end());
    for (const auto& [key, v] : bodyArrays(b)) *v = real(key);
    for (const auto& [key, v] : optionalBodyArrays(b))
      if (cp.reals.count(key)) *v = cp.reals.at(key);
    engine->setBodies(b);
  }
  t = cp.time;
  step = cp.step;
  auto sc = [&](const char* k) { return cp.scalars.count(k) ? cp.scalars.at(k) : 0.0; };
  phi = sc("phi");
  steady_t0 = cp.scalars.count("steady_t0") ? sc("steady_t0") : -1;
  steady_work0 = sc("steady_work0");
  restoredSums0.kinetic = sc("e0_kinetic");
  restoredSums0.potential = sc("e0_potential");
  restoredSums0.elastic = sc("e0_elastic");
  if (angle && cp.ints.count("heat_counts")) {
    const auto& h = cp.ints.at("heat_counts");
    angle->accumulator().restore(static_cast<int>(sc("heat_width")), static_cast<int>(sc("heat_height")),
                                 static_cast<int>(sc("heat_frames")), std::vector<std::uint32_t>(h.begin(), h.end()));
  }
  // A wet mill past its pour continues with the slurry of the checkpoint (one written before
  // the pour has none: the slurry is poured when the drum starts, as in a fresh run).
  if (scene.effect_sph && WetMill::inCheckpoint(cp)) {
    wet =
        std::make_unique<WetMill>(scene, options, cp, dem::ballStates(*engine), phi, motion->omega(t), options.restart);
  } else if (scene.effect_sph && t >= scene.drum.start_time - 0.5 * dt) {
    throw core::InputError(options.restart + ": checkpoint at t = " + std::to_string(t) +
                           " s, after the slurry's pour, holds no slurry (written by a balls-only case?)");
  } else if (!scene.effect_sph && WetMill::inCheckpoint(cp)) {
    throw core::InputError(options.restart + ": checkpoint holds a wet mill's slurry, the case has no <sph>");
  }
}

Simulation::Simulation(const scene::Scene& scene, const RunOptions& options) {
  // Checkpoints are written and read by the drum runs (dry and wet) and the stirred mill: a
  // fluid-only run would start over from t = 0 and overwrite the outputs it was meant to continue.
  if (!options.restart.empty() && scene.effect_sph && !scene.effect_dem)
    throw core::InputError(options.restart + ": --restart continues drum and stirred-mill runs only; " + scene.source +
                           " is a fluid-only case, which writes no checkpoint: run it from the start");
  // Only the engines the effects call for exist: a fluid-only case has no DEM arrays at all.
  if (scene.effect_sph && !scene.effect_dem)
    m_sph = std::make_unique<SphRun>(scene, options);
  else if (scene.has_stirrer)
    m_stirred = std::make_unique<StirredRun>(scene, options);
  else
    m_impl = std::make_unique<Impl>(scene, options);
}
Simulation::~Simulation() = default;

const RunSummary& Simulation::run() {
  if (m_sph) return m_sph->run();
  if (m_stirred) return m_stirred->run();
  m_impl->run();
  if (m_impl->options.write_outputs)
    writeSummaryJson(fs::path(m_impl->options.out_dir) / "summary.json", m_impl->summary, stages(), memoryReport(),
                     m_impl->scene.name, m_impl->scene.source);
  return m_impl->summary;
}

std::vector<std::string> Simulation::stages() const {
  if (m_sph) return m_sph->stages();
  if (m_stirred) return m_stirred->stages();
  std::vector<std::string> s{"neighbour_build", "dem_kick_drift", "dem_contacts_and_walls", "dem_kick"};
  if (m_impl->scene.angle.enabled) s.push_back("front_view_frames");
  if (m_impl->scene.effect_sph) {
    for (const char* stage : {"slurry_pour", "sph_neighbour_build", "sph_pressure", "sph_interaction", "sph_verlet",
                              "sph_dem_coupling", "slurry_surface_frames"})
      s.push_back(stage);
  }
  return s;
}

std::map<std::string, std::size_t> Simulation::memoryReport() const {
  if (m_stirred) return m_stirred->memoryReport();
  if (m_sph) return m_sph->memoryReport();
  auto memory = m_impl->engine->memoryBytes();
  if (m_impl->wet)
    for (const auto& [group, bytes] : m_impl->wet->memoryBytes()) memory["wet_mill." + group] += bytes;
  return memory;
}
const RunSummary& Simulation::summary() const {
  if (m_stirred) return m_stirred->summary();
  return m_sph ? m_sph->summary() : m_impl->summary;
}
double Simulation::timeStep() const {
  if (m_stirred) return m_stirred->timeStep();
  return m_sph ? m_sph->timeStep() : m_impl->dt;
}
std::size_t Simulation::particleCount() const {
  if (m_stirred) return m_stirred->particleCount();
  return m_sph ? m_sph->particleCount() : m_impl->particles;
}

}  // namespace millsim::sim
