// Several drum cases in one DEM solver (see header): the cases' charges side by side in slabs
// along z, one engine, one time loop, and each case's observers on its own balls.
#include "millsim/sim/ensemble_run.hpp"

#include <omp.h>

#include <algorithm>
#include <chrono>
#include <cmath>
#include <filesystem>
#include <memory>
#include <sstream>

#include "dem/dem_engine.hpp"
#include "millsim/core/error.hpp"
#include "millsim/vision/front_view_angle.hpp"
#include "sim/charge_setup.hpp"
#include "sim/drum_motion.hpp"
#include "sim/drum_setup.hpp"
#include "sim/engine_factory.hpp"
#include "sim/run_outputs.hpp"

namespace millsim::sim {

namespace fs = std::filesystem;

namespace {

// One case of the ensemble: its charge, drum motion, front view and bookkeeping.
struct Member {
  const scene::Scene* scene = nullptr;
  ChargeSetup charge;
  std::unique_ptr<DrumMotion> motion;
  std::unique_ptr<vision::FrontViewAngle> angle;
  fs::path out;
  int lo = 0, hi = 0;  // host numbers of its balls in the engine
  double z0 = 0;       // z of its local origin (front plate) in the ensemble
  double phi = 0;
  dem::DemSums sums0;
  RunSummary summary;
  std::unique_ptr<SeriesWriter> series;
  double next_series = 0, next_frame = 0, frame_dt = 0, steady_start = 0;
  double steady_t0 = -1, steady_work0 = 0;
  std::string label;     // "case k (its folder or file)": names it in messages
  double dt = 0, t = 0;  // its own time step and time
  long long steps = 0;
  bool done = false;  // reached time.end: its summary is final, its balls rest
};

// The case and line of a field that differs from the first case's, as an input error.
core::InputError mismatch(const scene::Scene& s, const char* element, const std::string& what) {
  const auto line = s.element_lines.count(element) ? s.element_lines.at(element) : 0;
  return core::InputError(s.source, line,
                          "ensemble: " + what +
                              " differs from the first case's; the cases of an ensemble share one "
                              "DEM solver (docs/performance.md, Ensembles)");
}

}  // namespace

void checkEnsembleCases(const std::vector<scene::Scene>& scenes, const RunOptions& run) {
  if (scenes.empty()) throw core::InputError("ensemble: no cases");
  if (run.precision != "double")
    throw core::InputError("ensemble: --precision " + run.precision +
                           ": an ensemble runs in double (its balls lie up to half the ensemble's length from "
                           "the origin, where a float resolves ~1e-7 m)");
  const scene::Scene& a = scenes.front();
  for (const scene::Scene& s : scenes) {
    if (!s.effect_dem || s.effect_sph || s.has_stirrer)
      throw core::InputError(s.source, 0, "ensemble: only balls-only drum cases (a <dem> without <sph> or <stirrer>)");
    if (s.dem.representation != "sphere")
      throw core::InputError(s.source, s.element_lines.count("dem") ? s.element_lines.at("dem") : 0,
                             "ensemble: dem.representation must be \"sphere\" (DCDEM bodies run one case at a time)");
    if (s.dem.youngs_modulus != a.dem.youngs_modulus || s.dem.poisson != a.dem.poisson)
      throw mismatch(s, "dem", "dem.youngs_modulus / dem.poisson");
    if (s.dem.damping != a.dem.damping) throw mismatch(s, "dem", "dem.damping");
    if (s.dem.tangential != a.dem.tangential || s.dem.friction_smoothing != a.dem.friction_smoothing)
      throw mismatch(s, "dem", "dem.tangential / dem.friction_smoothing");
    if (s.dem.law != a.dem.law) throw mismatch(s, "dem", "dem.law");
    if (s.gravity != a.gravity) throw mismatch(s, "gravity", "gravity");
    if (s.gravity[2] != 0)
      throw core::InputError(s.source, s.element_lines.count("gravity") ? s.element_lines.at("gravity") : 0,
                             "ensemble: gravity along the drum axis (z) is not supported: the cases lie along z");
    if (s.time.end != a.time.end) throw mismatch(s, "time", "time.end");
  }
}

std::vector<RunSummary> runEnsemble(const EnsembleSpec& spec) {
  const std::size_t k_count = spec.scenes.size();
  if (k_count == 0) throw core::InputError("ensemble: no cases");
  if (spec.out_dirs.size() != k_count) throw core::InputError("ensemble: one output folder per case is needed");
  checkEnsembleCases(spec.scenes, spec.run);
  if (!spec.run.restart.empty()) throw core::InputError("ensemble: --restart is for single runs");
  if (spec.run.threads > 0) omp_set_num_threads(spec.run.threads);

  // Charges, motions, each case's own time step and skin, and the solver's shared setup: the
  // largest skin and ball (the cells), the widest drum, the longest generation drum.
  std::vector<Member> members(k_count);
  double skin = 0, max_radius = 0, max_drum = 0, max_length = 0;
  for (std::size_t k = 0; k < k_count; ++k) {
    Member& m = members[k];
    m.scene = &spec.scenes[k];
    m.charge = buildCharge(*m.scene);
    m.motion = std::make_unique<DrumMotion>(*m.scene, m.charge.generation_length, drumSpeedRpm(*m.scene, m.charge));
    if (m.scene->angle.enabled)
      m.angle = std::make_unique<vision::FrontViewAngle>(m.scene->drum.diameter, drumAngleOptions(*m.scene));
    m.out = spec.out_dirs[k];
    m.label = "case " + std::to_string(k) + " (" + (m.out.empty() ? m.scene->source : m.out.string()) + ")";
    const dem::DemSetup own = drumDemSetup(*m.scene, m.charge);
    m.dt = drumTimeStep(*m.scene, m.charge);
    skin = std::max(skin, own.skin);
    max_radius = std::max(max_radius, own.max_radius);
    max_drum = std::max(max_drum, 0.5 * m.scene->drum.diameter);
    max_length = std::max(max_length, m.charge.generation_length);
  }
  dem::DemSetup setup = drumDemSetup(*members[0].scene, members[0].charge);
  setup.skin = skin;
  setup.max_radius = max_radius;
  // Slabs: each case's local z in [0, generation length] sits `lead` into its slab, and the next
  // slab starts more than a neighbour cell after the longest drum, so no pair spans two cases.
  const double cell = 2 * max_radius + skin, margin = 2 * max_radius;
  dem::DemEnsemble& ens = setup.ensemble;
  ens.lead = cell;
  ens.pitch = max_length + 3 * cell;
  ens.origin = -0.5 * static_cast<double>(k_count) * ens.pitch;  // centred: smaller |z| in float
  setup.domain_lo = {-max_drum - margin, -max_drum - margin, ens.origin - margin};
  setup.domain_hi = {max_drum + margin, max_drum + margin, ens.origin + k_count * ens.pitch + margin};

  // One state: case k's balls shifted to its slab, their history keys by its first host number.
  dem::DemHostState state;
  ens.start.push_back(0);
  for (std::size_t k = 0; k < k_count; ++k) {
    Member& m = members[k];
    const dem::DemSetup own = drumDemSetup(*m.scene, m.charge);
    ens.alpha.push_back(own.alpha);
    ens.skin.push_back(own.skin);
    ens.friction.push_back(own.friction);
    m.z0 = ens.origin + static_cast<double>(k) * ens.pitch + ens.lead;
    m.lo = ens.start.back();
    const dem::DemHostState& c = m.charge.state;
    auto append = [](std::vector<double>& to, const std::vector<double>& from) {
      to.insert(to.end(), from.begin(), from.end());
    };
    for (std::size_t i = 0; i < c.size(); ++i) {
      state.pos.insert(state.pos.end(), {c.pos[3 * i], c.pos[3 * i + 1], c.pos[3 * i + 2] + m.z0});
    }
    append(state.vel, c.vel);
    append(state.omega, c.omega);
    append(state.radius, c.radius);
    append(state.mass, c.mass);
    append(state.inertia, c.inertia);
    append(state.hist_xi, c.hist_xi);
    for (const std::int64_t key : c.hist_id) state.hist_id.push_back(key >= 0 ? key + m.lo : key);
    m.hi = m.lo + static_cast<int>(c.size());
    ens.start.push_back(m.hi);
  }
  const std::unique_ptr<dem::DemEngine> engine = makeDemEngine(setup, spec.run);
  engine->setState(state);

  std::vector<dem::DrumState> drums(k_count);
  std::vector<double> steps(k_count, 0.0);
  for (std::size_t k = 0; k < k_count; ++k) drums[k] = members[k].motion->at(0.0, 0.0);
  engine->initialize(drums);
  {
    const std::vector<dem::DemSums> s0 = engine->sceneSums();
    for (std::size_t k = 0; k < k_count; ++k) members[k].sums0 = s0[k];
  }

  const bool write = spec.run.write_outputs;
  const double t_end = spec.scenes.front().time.end;
  for (Member& m : members) {
    RunSummary& s = m.summary;
    s.backend = engine->backendName();
    s.precision = engine->precisionName();
    s.threads = s.backend == std::string("omp") ? omp_get_max_threads() : 1;
    s.dt = m.dt;
    s.particles = static_cast<std::size_t>(m.hi - m.lo);
    s.charge_mass_kg = m.charge.total_mass;
    s.omega_rad_s = std::abs(m.motion->fullOmega());
    const scene::Scene& sc = *m.scene;
    m.frame_dt = (t_end - sc.angle.start_time) / std::max(1, sc.angle.frames);
    m.next_frame = sc.angle.start_time + m.frame_dt;
    m.steady_start = sc.angle.enabled ? sc.angle.start_time : sc.drum.start_time + sc.drum.spin_up;
    if (write) {
      fs::create_directories(m.out);
      m.series = std::make_unique<SeriesWriter>(m.out / "series.csv", drumSeriesColumns(), false);
    }
  }

  const std::vector<std::string> stages{"ensemble", "neighbour_build",  "dem_kick_drift", "dem_contacts_and_walls",
                                        "dem_kick", "front_view_frames"};
  // The balls' positions for the escape checks and the front views (host order).
  dem::BallKinematics balls;
  auto captureFrame = [&](Member& m) {
    std::vector<double> cx, cy, r;
    for (int h = m.lo; h < m.hi; ++h) {
      cx.push_back(balls.pos[3 * h]);
      cy.push_back(balls.pos[3 * h + 1]);
      r.push_back(state.radius[static_cast<std::size_t>(h)]);
    }
    m.angle->addFrame(cx, cy, r);
  };
  const auto wall0 = std::chrono::steady_clock::now();
  // A case at its end: its summary from its sums now (power over its steady window, angle from
  // its frames), its summary.json written; from now on it rests (dt 0).
  auto finish = [&](Member& m, const dem::DemSums& now) {
    RunSummary& s = m.summary;
    markRunEnd(s, "ok", m.t, m.steps, wall0);
    s.neighbour_rebuilds = engine->neighbourRebuilds();
    fillDrumEnergy(s, now, m.sums0);
    if (m.steady_t0 >= 0 && m.t > m.steady_t0) {
      s.power_W = (now.work_in - m.steady_work0) / (m.t - m.steady_t0);
      s.torque_Nm = s.omega_rad_s > 0 ? s.power_W / s.omega_rad_s : 0;
    }
    if (m.angle) finishDrumAngle(*m.angle, s, m.out, write);
    if (write)
      writeSummaryJson(m.out / "summary.json", s, stages, engine->memoryBytes(), m.scene->name, m.scene->source);
    m.done = true;
  };

  ProgressLine progress(spec.run.progress, t_end);
  long long ticks = 0;
  std::vector<bool> sums_wanted(k_count, false);
  try {
    while (true) {
      // What the cases that are still running want at their own time now.
      bool want_sums = false, want_frame = false;
      for (std::size_t k = 0; k < k_count; ++k) {
        const Member& m = members[k];
        sums_wanted[k] = !m.done && (m.t >= t_end - 0.5 * m.dt || m.t >= m.next_series - 1e-12 * t_end);
        want_sums = want_sums || sums_wanted[k];
        if (m.done) continue;
        want_frame =
            want_frame || (m.angle && m.t >= m.next_frame - 0.5 * m.dt && m.angle->frames() < m.scene->angle.frames);
      }
      if (want_sums || want_frame) engine->ballKinematics(balls);
      std::vector<dem::DemSums> now;
      if (want_sums) now = engine->sceneSums(sums_wanted);
      for (std::size_t k = 0; k < k_count; ++k) {
        Member& m = members[k];
        if (m.done) continue;
        if (m.t >= m.next_series - 1e-12 * t_end) {
          try {
            checkBallsInDrum(balls.pos, m.lo, m.hi, m.z0, *m.scene, m.charge, m.t, m.label + ": ");
          } catch (const core::SimulationError& e) {
            // This case fails and rests; the others go on. (Its escaped ball rests with it while
            // it stays in its slab; one that flew along z past the gap of 2 cells to the next
            // case in the series interval would join that case: an unstable run's rare worst.)
            const fs::path summary_json = m.out / "summary.json";
            recordFailedRun(m.summary, e.what(), m.t, m.steps, wall0, write ? &summary_json : nullptr,
                            engine->memoryBytes(), m.scene->name, m.scene->source);
            m.done = true;
            continue;
          }
          fillDrumEnergy(m.summary, now[k], m.sums0);
          if (m.series) m.series->row(drumSeriesRow(m.t, now[k], m.motion->at(m.t, m.phi), m.summary.energy_residual));
          if (m.steady_t0 < 0 && m.t >= m.steady_start) {
            m.steady_t0 = m.t;
            m.steady_work0 = now[k].work_in;
          }
          m.next_series += m.scene->output.series_every;
        }
        if (m.angle && m.t >= m.next_frame - 0.5 * m.dt && m.angle->frames() < m.scene->angle.frames) {
          captureFrame(m);
          m.next_frame += m.frame_dt;
        }
        if (m.t >= t_end - 0.5 * m.dt) finish(m, now[k]);
      }
      // One step of every running case, each by its own dt; ended cases rest.
      double slowest = t_end;
      bool running = false;
      for (std::size_t k = 0; k < k_count; ++k) {
        Member& m = members[k];
        if (m.done) {
          steps[k] = 0;
          drums[k] = m.motion->at(m.t, m.phi);
          continue;
        }
        running = true;
        m.phi += m.motion->omega(m.t + m.dt) * m.dt;
        drums[k] = m.motion->at(m.t + m.dt, m.phi);
        steps[k] = m.dt;
      }
      if (!running) break;
      engine->step(drums, steps);
      for (Member& m : members) {
        if (m.done) continue;
        m.t += m.dt;
        ++m.steps;
        slowest = std::min(slowest, m.t);
      }
      progress.update(slowest, ++ticks);
    }
  } catch (const core::SimulationError& e) {
    progress.finish();
    for (Member& m : members) {
      if (m.done) continue;
      const fs::path summary_json = m.out / "summary.json";
      recordFailedRun(m.summary, e.what(), m.t, m.steps, wall0, write ? &summary_json : nullptr, engine->memoryBytes(),
                      m.scene->name, m.scene->source);
    }
    throw;
  }
  progress.finish();
  std::vector<RunSummary> out;
  for (const Member& m : members) out.push_back(m.summary);
  return out;
}

}  // namespace millsim::sim
