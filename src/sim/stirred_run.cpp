// The stirred-mill time loop (see stirred_run.hpp). Physics lives in the DEM engine; this file
// places the beads, follows the speed program, and books power, energy and collision statistics.
#include "sim/stirred_run.hpp"

#include <hdf5.h>
#include <omp.h>

#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <iomanip>
#include <numeric>
#include <opencv2/imgproc.hpp>
#include <random>
#include <sstream>
#include <type_traits>

#include "dem/contact/damping.hpp"
#include "dem/contact/linear_spring.hpp"
#include "dem/contact/lubrication.hpp"
#include "dem/walls/stirrer_walls.hpp"
#include "millsim/backend/info.hpp"
#include "millsim/core/error.hpp"
#include "millsim/io/fields_writer.hpp"
#include "millsim/io/plot_png.hpp"
#include "sim/dem_checkpoint.hpp"
#include "sim/drum_setup.hpp"
#include "sim/engine_factory.hpp"
#include "sim/run_outputs.hpp"
#include "vision/cv_convert.hpp"

namespace millsim::sim {

namespace fs = std::filesystem;

namespace {

constexpr double kPi = 3.14159265358979323846;
constexpr const char* kModeNames[dem::kModeCount] = {"impact", "shearing", "rolling", "torsion"};

double beadMass(double r, double rho) { return rho * 4.0 / 3.0 * kPi * r * r * r; }

}  // namespace

std::vector<double> speedProgram(const scene::Scene& scene) {
  std::istringstream in(scene.stirrer.speeds_rpm);
  std::vector<double> rpm;
  double v = 0;
  while (in >> v) rpm.push_back(v);
  if (rpm.empty()) throw core::InputError(scene.source, 0, "stirrer.speeds_rpm: no speed given");
  return rpm;
}

dem::StirrerState stirrerStateOf(const scene::Scene& scene, double omega, double phi) {
  const auto& st = scene.stirrer;
  dem::StirrerState s;
  s.radius = 0.5 * st.chamber_diameter;
  s.length = st.chamber_length;
  s.shaft_radius = 0.5 * st.shaft_diameter;
  s.omega = omega;
  s.phi = phi;
  s.disk_count = st.disk_count;
  s.disk_radius = 0.5 * st.disk_diameter;
  s.disk_thickness = st.disk_thickness;
  for (int k = 0; k < st.disk_count; ++k) s.disk_z.push_back(st.chamber_length * (k + 0.5) / st.disk_count);
  s.hole_count = st.hole_count;
  s.hole_radius = 0.5 * st.hole_diameter;
  s.hole_ring_radius = 0.5 * st.hole_ring_diameter;
  return s;
}

dem::DemHostState placeBeads(const scene::Scene& scene) {
  const auto& b = scene.beads;
  const double d_min = b.diameter, d_max = std::max(b.diameter, b.diameter_max);
  const dem::StirrerState state = stirrerStateOf(scene, 0.0, 0.0);
  dem::StirrerWalls<double> walls{};
  walls.radius = state.radius;
  walls.length = state.length;
  walls.shaft_radius = state.shaft_radius;
  walls.disk_count = state.disk_count;
  walls.disk_radius = state.disk_radius;
  walls.disk_half_thickness = 0.5 * state.disk_thickness;
  for (int k = 0; k < state.disk_count; ++k) walls.disk_z[k] = state.disk_z[k];
  walls.hole_count = std::min(state.hole_count, dem::kMaxHoles);
  walls.hole_radius = state.hole_radius;
  walls.hole_ring_radius = state.hole_ring_radius;
  for (int m = 0; m < walls.hole_count; ++m) {
    walls.hole_cos[m] = std::cos(2 * kPi * m / walls.hole_count);
    walls.hole_sin[m] = std::sin(2 * kPi * m / walls.hole_count);
  }
  // FCC lattice with nearest-neighbour distance lattice_factor d_max; a site is kept when a bead
  // of the largest size there touches no wall (clearance 1% of the radius).
  const double nn = b.lattice_factor * d_max, a = nn * std::sqrt(2.0);
  const double r_clear = 0.5 * d_max * 1.01;
  const double R = state.radius, L = state.length;
  const int nxy = static_cast<int>(std::ceil(2 * R / a)) + 1, nz = static_cast<int>(std::ceil(L / a)) + 1;
  const double basis[4][3] = {{0, 0, 0}, {0.5, 0.5, 0}, {0.5, 0, 0.5}, {0, 0.5, 0.5}};
  std::vector<std::array<double, 3>> sites;
  for (int iz = 0; iz < nz; ++iz)
    for (int iy = 0; iy < nxy; ++iy)
      for (int ix = 0; ix < nxy; ++ix)
        for (const auto& o : basis) {
          const core::Vec3<double> p{-R + (ix + o[0]) * a, -R + (iy + o[1]) * a, r_clear + (iz + o[2]) * a};
          if (p.z > L - r_clear) continue;
          const double rho = std::sqrt(p.x * p.x + p.y * p.y);
          if (rho + r_clear > R) continue;
          bool clear = true;
          walls.forEachContact(p, r_clear, [&](const dem::WallContact<double>&) { clear = false; });
          if (clear) sites.push_back({p.x, p.y, p.z});
        }
  if (static_cast<int>(sites.size()) < b.count) {
    std::ostringstream m;
    m << "beads.count = " << b.count << " does not fit: the placement lattice (spacing " << nn * 1e3 << " mm) has only "
      << sites.size() << " free sites in the chamber; lower beads.lattice_factor or the count";
    throw core::InputError(scene.source, 0, m.str());
  }
  std::mt19937_64 rng(b.seed);
  std::shuffle(sites.begin(), sites.end(), rng);
  std::uniform_real_distribution<double> size(d_min, d_max);
  dem::DemHostState s;
  for (int i = 0; i < b.count; ++i) {
    const double r = 0.5 * (d_max > d_min ? size(rng) : d_min);
    s.pos.insert(s.pos.end(), {sites[i][0], sites[i][1], sites[i][2]});
    s.vel.insert(s.vel.end(), {0.0, 0.0, 0.0});
    s.omega.insert(s.omega.end(), {0.0, 0.0, 0.0});
    s.radius.push_back(r);
    const double m = beadMass(r, scene.dem.density);
    s.mass.push_back(m);
    s.inertia.push_back(0.4 * m * r * r);
  }
  // Spatial order (the lattice's) helps the first neighbour build; the engine renumbers anyway.
  return s;
}

struct StirredRun::Impl {
  scene::Scene scene;
  RunOptions options;
  dem::DemHostState beads;
  std::unique_ptr<dem::DemEngine> engine;
  std::vector<double> rpm;
  std::vector<StirredLevel> levels;
  StirredEnergy energy;
  double coordination_end = 0;  // bead-bead contacts per bead at the end (2 x pairs / beads)
  std::vector<RegionStats> regions;
  dem::StirredSums final_sums;
  RunSummary summary;
  double dt = 0, t = 0, phi = 0, r_min = 0, r_max = 0;
  long long step = 0;
  // Velocity field accumulators (cells x*y*z), and the last tallies for region increments.
  int gx = 0, gz = 0;
  std::vector<double> v_sum, w_sum, n_sum;
  std::vector<dem::CollisionTally> last_tally, tally_now;
  bool have_tally = false;
  // Host copies the series rows and the collision samples reuse: positions and speeds only (a
  // full getState copies the contact history too, and allocated it afresh each sample: 15% of
  // the LS1 slice's run time at a row every 72 steps).
  dem::BallKinematics kinematics;
  int field_samples = 0;
  // The loop's bookkeeping between steps: a checkpoint carries it with the beads.
  struct Ledger {
    std::size_t level = 0;  // the level whose window is open or comes next
    bool level_open = false, level_mid_taken = false;
    double level_work0 = 0, level_work_mid = 0;  // stirrer work when the window opened, at its middle
    double next_series = 0, next_sample = 0, next_fields = 0, next_checkpoint = 0;
    double stats_t0 = -1;  // first collision sample
    dem::DemSums e0;       // the energy budget's baseline (t = 0)
    double lubrication0 = 0;
  } ledger;

  Impl(const scene::Scene& s, const RunOptions& o) : scene(s), options(o) {
    if (options.threads > 0) omp_set_num_threads(options.threads);
    rpm = speedProgram(scene);
    beads = placeBeads(scene);
    r_min = *std::min_element(beads.radius.begin(), beads.radius.end());
    r_max = *std::max_element(beads.radius.begin(), beads.radius.end());
    dt = chooseTimeStep();
    engine = makeEngine();
    engine->setState(beads);
    planLevels();
    gx = scene.collisions.grid_radial;
    gz = scene.collisions.grid_axial;
    const std::size_t cells = static_cast<std::size_t>(gx) * gx * gz;
    v_sum.assign(cells, 0.0);
    w_sum.assign(cells, 0.0);
    n_sum.assign(cells, 0.0);
    const char* radial[3] = {"1", "2", "3"};
    const char* axial[3] = {"F", "C", "B"};
    for (int a = 0; a < 3; ++a)
      for (int r = 0; r < 3; ++r) {
        RegionStats rs;
        rs.name = std::string(radial[r]) + axial[a];
        regions.push_back(rs);
      }
    ledger.next_sample = scene.collisions.start;
    if (!options.restart.empty()) restoreCheckpoint();
    engine->initialize(stirrerStateOf(scene, omegaAt(t), phi));
    if (options.restart.empty()) {
      ledger.e0 = engine->sums();
      ledger.lubrication0 = engine->stirredSums().lubrication_dissipated;
      ledger.next_checkpoint = scene.output.checkpoint_every > 0 ? scene.output.checkpoint_every : 1e300;
    }
  }

  void planLevels() {
    for (std::size_t k = 0; k < rpm.size(); ++k) {
      StirredLevel lv;
      lv.rpm = rpm[k];
      lv.t_begin = k * levelLength();
      lv.t_average = lv.t_begin + scene.stirrer.ramp + scene.stirrer.average_from * scene.stirrer.hold;
      lv.t_end = lv.t_begin + levelLength();
      lv.t_mid = 0.5 * (lv.t_average + lv.t_end);
      lv.revolutions_held = lv.rpm / 60 * scene.stirrer.hold;
      levels.push_back(lv);
    }
  }

  double levelLength() const { return scene.stirrer.ramp + scene.stirrer.hold; }
  // The speed program's end, or time.end when that comes first (short benchmark runs).
  double endTime() const { return std::min(scene.time.end, levelLength() * rpm.size()); }

  double rpmAt(double time) const {
    const double len = levelLength();
    int k = static_cast<int>(std::floor(time / len));
    k = std::clamp(k, 0, static_cast<int>(rpm.size()) - 1);
    const double tau = time - k * len;
    const double prev = k > 0 ? rpm[k - 1] : 0.0;
    if (tau < scene.stirrer.ramp) return prev + (rpm[k] - prev) * tau / scene.stirrer.ramp;
    return rpm[k];
  }
  double omegaAt(double time) const { return rpmAt(time) * 2 * kPi / 60.0; }

  double chooseTimeStep() const {
    if (scene.time.dt_mode == "fixed") return scene.time.dt_fixed;
    const double m = beadMass(r_min, scene.dem.density);
    double tc = 0;
    if (scene.dem.law == "linear") {
      const double zeta = dem::linearDampingRatio(scene.dem.restitution);
      tc = kPi * std::sqrt(0.5 * m / scene.dem.linear_stiffness / (1 - zeta * zeta));
    } else {
      const double e_star = dem::effectiveModulus(scene.dem.youngs_modulus, scene.dem.poisson);
      tc = dem::hertzContactTime(0.5 * m, 0.5 * r_min, e_star, scene.dem.impact_velocity);
    }
    double step = tc / scene.time.dt_divisor;
    if (scene.lubrication.viscosity > 0) {
      // The film is a stiff dashpot: explicit steps need dt < 2 m / sum(c); the largest c is a
      // bead at a wall at the inner cutoff, c = mu (6 pi r^2 / h_in + ...). A quarter of m / c
      // leaves room for the bead's other films.
      const double h_in = scene.lubrication.inner * 2 * r_min;
      const double c = scene.lubrication.viscosity * dem::JeffreyOnishi<double>::wallScalars(r_min, h_in).xa;
      step = std::min(step, 0.25 * m / c);
    }
    return step;
  }

  std::unique_ptr<dem::DemEngine> makeEngine() const {
    dem::DemSetup setup = demContactSetup(scene);
    setup.linear_law = scene.dem.law == "linear";
    setup.linear_kn = scene.dem.linear_stiffness;
    setup.linear_zeta = dem::linearDampingRatio(scene.dem.restitution);
    setup.lubrication_viscosity = scene.lubrication.viscosity;
    setup.lubrication_inner = scene.lubrication.inner;
    setup.lubrication_outer = scene.lubrication.outer;
    setup.collision_stats = collisionStats();
    setup.gravity = scene.gravity;
    setup.skin = scene.dem.skin * r_min;
    setup.max_radius = r_max;
    const double R = 0.5 * scene.stirrer.chamber_diameter, margin = 4 * r_max;
    setup.domain_lo = {-R - margin, -R - margin, -margin};
    setup.domain_hi = {R + margin, R + margin, scene.stirrer.chamber_length + margin};
    return makeDemEngine(setup, options);
  }

  void checkEscaped() {
    engine->ballKinematics(kinematics);
    const dem::BallKinematics& s = kinematics;
    const double R = 0.5 * scene.stirrer.chamber_diameter, L = scene.stirrer.chamber_length;
    const double rs = 0.5 * scene.stirrer.shaft_diameter, tol = 0.5 * r_max;
    for (std::size_t i = 0; i < s.size(); ++i) {
      const double x = s.pos[3 * i], y = s.pos[3 * i + 1], z = s.pos[3 * i + 2];
      const double rho = std::sqrt(x * x + y * y);
      if (!(rho < R + tol && rho > rs - tol && z > -tol && z < L + tol)) {
        std::ostringstream m;
        m << "DEM: bead " << i << " escaped the chamber at t = " << t << " s, position (" << x << ", " << y << ", " << z
          << ") m: contacts too soft or the step too long for the speeds reached";
        throw core::SimulationError(m.str());
      }
    }
  }

  int regionOf(double x, double y, double z) const {
    const double R = 0.5 * scene.stirrer.chamber_diameter, L = scene.stirrer.chamber_length;
    const double rho2 = (x * x + y * y) / (R * R);
    const int radial = rho2 < 1.0 / 3.0 ? 0 : (rho2 < 2.0 / 3.0 ? 1 : 2);
    const int axial = z < L / 3 ? 0 : (z < 2 * L / 3 ? 1 : 2);
    return axial * 3 + radial;
  }

  // Collision increments since the last sample go to each bead's current region; speeds go to
  // the velocity grid.
  void sampleCollisions() {
    engine->ballKinematics(kinematics);
    const dem::BallKinematics& s = kinematics;
    std::vector<dem::CollisionTally>& tally = tally_now;
    engine->collisionTallies(tally);
    const double R = 0.5 * scene.stirrer.chamber_diameter, L = scene.stirrer.chamber_length;
    for (std::size_t i = 0; i < s.size(); ++i) {
      const double x = s.pos[3 * i], y = s.pos[3 * i + 1], z = s.pos[3 * i + 2];
      RegionStats& rg = regions[regionOf(x, y, z)];
      rg.bead_samples += 1;
      if (have_tally) {
        rg.collisions += tally[i].collisions - last_tally[i].collisions;
        for (int q = 0; q < dem::kModeCount; ++q) {
          rg.dissipated[q] += tally[i].dissipated[q] - last_tally[i].dissipated[q];
          rg.energy[q] += tally[i].energy[q] - last_tally[i].energy[q];
        }
      }
      const int cx = std::clamp(static_cast<int>((x + R) / (2 * R) * gx), 0, gx - 1);
      const int cy = std::clamp(static_cast<int>((y + R) / (2 * R) * gx), 0, gx - 1);
      const int cz = std::clamp(static_cast<int>(z / L * gz), 0, gz - 1);
      const std::size_t c = (static_cast<std::size_t>(cz) * gx + cy) * gx + cx;
      const double v2 =
          s.vel[3 * i] * s.vel[3 * i] + s.vel[3 * i + 1] * s.vel[3 * i + 1] + s.vel[3 * i + 2] * s.vel[3 * i + 2];
      const double w2 = s.omega[3 * i] * s.omega[3 * i] + s.omega[3 * i + 1] * s.omega[3 * i + 1] +
                        s.omega[3 * i + 2] * s.omega[3 * i + 2];
      v_sum[c] += std::sqrt(v2);
      w_sum[c] += std::sqrt(w2);
      n_sum[c] += 1;
    }
    std::swap(last_tally, tally);
    have_tally = true;
    ++field_samples;
  }

  void run();
  void writeCheckpoint(const fs::path& path) const;
  void restoreCheckpoint();
  void writeOutputs(const fs::path& out, double stats_time) const;
  void writeVelocityField(const fs::path& out) const;
  void writeCollisionOutputs(const fs::path& out, double stats_time) const;
  bool collisionStats() const { return scene.has_collisions && scene.collisions.enabled; }
};

void StirredRun::Impl::run() {
  const fs::path out(options.out_dir);
  if (options.write_outputs) fs::create_directories(out);
  summary = RunSummary{};
  summary.backend = engine->backendName();
  summary.precision = engine->precisionName();
  summary.threads = summary.backend == std::string("omp") ? omp_get_max_threads() : 1;
  summary.dt = dt;
  summary.particles = beads.size();
  summary.charge_mass_kg = std::accumulate(beads.mass.begin(), beads.mass.end(), 0.0);

  const bool restart = !options.restart.empty();
  std::unique_ptr<SeriesWriter> series;
  if (options.write_outputs)
    series = std::make_unique<SeriesWriter>(
        out / "series.csv",
        std::vector<std::string>{"time_s", "rpm", "stirrer_torque_Nm", "outer_torque_Nm", "power_W", "kinetic_J",
                                 "potential_J", "elastic_J", "work_in_J", "contact_dissipated_J",
                                 "lubrication_dissipated_J", "energy_residual_J", "max_speed_m_s", "contacts_per_bead",
                                 "wall_time_s"},
        restart, t + 0.5 * dt);  // a restart keeps the rows up to its checkpoint
  // Bead snapshots (ParaView); also the last good state a failed run leaves on disk.
  std::unique_ptr<io::FieldsWriter> fields;
  if (options.write_outputs && scene.output.fields_every > 0) fields = std::make_unique<io::FieldsWriter>(out, restart);
  auto writeFields = [&]() {
    dem::DemHostState s;
    engine->getState(s);
    fields->write(demFieldFrame(t, step, s));
  };
  const double t_end = endTime();
  const dem::DemSums& e0 = ledger.e0;
  Ledger& g = ledger;
  std::size_t& level = g.level;
  auto book = [&](const dem::DemSums& now, const dem::StirredSums& st) {
    energy.work_in = now.work_in - e0.work_in;
    energy.d_kinetic = now.kinetic - e0.kinetic;
    energy.d_potential = now.potential - e0.potential;
    energy.d_elastic = now.elastic - e0.elastic;
    energy.contact_dissipated = now.dissipated - e0.dissipated;
    energy.lubrication_dissipated = st.lubrication_dissipated - g.lubrication0;
    energy.residual = energy.work_in - (energy.d_kinetic + energy.d_potential + energy.d_elastic +
                                        energy.contact_dissipated + energy.lubrication_dissipated);
  };
  ProgressLine progress(options.progress, t_end);
  const auto wall0 = std::chrono::steady_clock::now();
  try {
    while (true) {
      // Level windows: open at t_average, close at t_end with the work done meanwhile.
      if (level < levels.size() && !g.level_open && t >= levels[level].t_average - 0.5 * dt) {
        const dem::DemSums open = engine->sums();
        g.level_work0 = open.work_in;
        levels[level].kinetic_open_J = open.kinetic;
        levels[level].t_average = t;
        g.level_open = true;
        g.level_mid_taken = false;
      }
      if (g.level_open && !g.level_mid_taken && t >= levels[level].t_mid - 0.5 * dt) {
        g.level_work_mid = engine->sums().work_in;
        levels[level].t_mid = t;
        g.level_mid_taken = true;
      }
      const bool closing = g.level_open && t >= levels[level].t_end - 0.5 * dt;
      if (t >= g.next_series - 1e-9 * dt || closing) {
        const dem::DemSums now = engine->sums();
        const dem::StirredSums st = engine->stirredSums();
        book(now, st);
        const double omega = omegaAt(t);
        if (g.level_open && !closing) {
          levels[level].stirrer_torque_Nm += st.stirrer_torque;
          levels[level].outer_torque_Nm += st.outer_torque;
          ++levels[level].samples;
        }
        if (series && t >= g.next_series - 1e-9 * dt) {
          checkEscaped();
          series->row({t, rpmAt(t), st.stirrer_torque, st.outer_torque, -st.stirrer_torque * omega, now.kinetic,
                       now.potential, now.elastic, energy.work_in, energy.contact_dissipated,
                       energy.lubrication_dissipated, energy.residual, now.max_speed,
                       2.0 * now.pair_contacts / double(summary.particles),
                       std::chrono::duration<double>(std::chrono::steady_clock::now() - wall0).count()});
          g.next_series += scene.output.series_every;
        } else if (!series && t >= g.next_series - 1e-9 * dt) {
          checkEscaped();
          g.next_series += scene.output.series_every;
        }
        if (closing) {
          StirredLevel& lv = levels[level];
          lv.t_end = t;
          lv.kinetic_close_J = now.kinetic;
          lv.power_W = (now.work_in - g.level_work0) / std::max(t - lv.t_average, 1e-300);
          lv.net_power_W = lv.power_W - scene.stirrer.idle_power_W;
          lv.power_first_half_W = (g.level_work_mid - g.level_work0) / std::max(lv.t_mid - lv.t_average, 1e-300);
          lv.power_second_half_W = (now.work_in - g.level_work_mid) / std::max(t - lv.t_mid, 1e-300);
          lv.steady =
              std::abs(lv.power_second_half_W - lv.power_first_half_W) <= kSteadyPowerChange * std::abs(lv.power_W);
          if (lv.samples > 0) {
            lv.stirrer_torque_Nm /= lv.samples;
            lv.outer_torque_Nm /= lv.samples;
          }
          g.level_open = false;
          ++level;
        }
      }
      if (collisionStats() && t >= g.next_sample - 0.5 * dt && t >= scene.collisions.start - 0.5 * dt) {
        if (g.stats_t0 < 0) g.stats_t0 = t;
        sampleCollisions();
        g.next_sample += scene.collisions.sample_every;
      }
      if (fields && t >= g.next_fields - 1e-9 * dt) {
        writeFields();
        g.next_fields += scene.output.fields_every;
      }
      if (options.write_outputs && t >= g.next_checkpoint - 0.5 * dt) {
        writeCheckpoint(out / "checkpoint.h5");
        g.next_checkpoint += scene.output.checkpoint_every;
      }
      if (t >= t_end - 0.5 * dt) break;
      phi += omegaAt(t + dt) * dt;
      engine->step(stirrerStateOf(scene, omegaAt(t + dt), phi), dt);
      t += dt;
      ++step;
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
  // Before the open level is dropped below: a restart from here goes on measuring it.
  if (options.write_outputs) writeCheckpoint(out / "checkpoint.h5");
  // Only the levels whose averaging window closed: a run ended by time.end inside the program
  // would otherwise report the levels it never reached (and a half-open one) as 0 W, in
  // power.csv, the plot and summary.json's power.
  levels.resize(level);
  summary.neighbour_rebuilds = engine->neighbourRebuilds();
  const dem::DemSums now = engine->sums();
  final_sums = engine->stirredSums();
  book(now, final_sums);
  fillDemEnergy(summary, now.kinetic, now.potential, now.dissipated, now.work_in, now.elastic);
  summary.energy_residual = energy.residual;
  coordination_end = summary.particles > 0 ? 2.0 * now.pair_contacts / double(summary.particles) : 0.0;
  if (!levels.empty()) {
    summary.power_W = levels.back().power_W;
    summary.omega_rad_s = levels.back().rpm * 2 * kPi / 60;
    summary.torque_Nm = summary.omega_rad_s > 0 ? summary.power_W / summary.omega_rad_s : 0;
  }
  if (options.write_outputs) writeOutputs(out, g.stats_t0 >= 0 ? t - g.stats_t0 : 0.0);
}

namespace {

// Per-bead tallies as a checkpoint's real array (CollisionTally is 11 doubles).
static_assert(sizeof(dem::CollisionTally) == 11 * sizeof(double), "CollisionTally holds 11 doubles");
constexpr std::size_t kTallyReals = 11;

std::vector<double> flatTallies(const std::vector<dem::CollisionTally>& t) {
  std::vector<double> v(t.size() * kTallyReals);
  if (!t.empty()) std::memcpy(v.data(), t.data(), v.size() * sizeof(double));
  return v;
}

std::vector<dem::CollisionTally> tallies(const std::vector<double>& v) {
  std::vector<dem::CollisionTally> t(v.size() / kTallyReals);
  if (!t.empty()) std::memcpy(t.data(), v.data(), t.size() * sizeof(dem::CollisionTally));
  return t;
}

// The measured fields of each speed level, by dataset name.
std::vector<std::pair<const char*, double StirredLevel::*>> levelFields() {
  return {{"level_t_average", &StirredLevel::t_average},
          {"level_t_mid", &StirredLevel::t_mid},
          {"level_t_end", &StirredLevel::t_end},
          {"level_power", &StirredLevel::power_W},
          {"level_net_power", &StirredLevel::net_power_W},
          {"level_stirrer_torque", &StirredLevel::stirrer_torque_Nm},
          {"level_outer_torque", &StirredLevel::outer_torque_Nm},
          {"level_power_first_half", &StirredLevel::power_first_half_W},
          {"level_power_second_half", &StirredLevel::power_second_half_W},
          {"level_kinetic_open", &StirredLevel::kinetic_open_J},
          {"level_kinetic_close", &StirredLevel::kinetic_close_J}};
}

constexpr std::size_t kRegionReals = 2 + 2 * dem::kModeCount;

// The run's ledger (StirredRun::Impl::Ledger) by checkpoint name, its reals (L const: to read).
template <class L, class D = std::conditional_t<std::is_const_v<L>, const double, double>>
std::vector<std::pair<const char*, D*>> ledgerReals(L& g) {
  return {
      {"level_work0", &g.level_work0},  {"level_work_mid", &g.level_work_mid}, {"next_series", &g.next_series},
      {"next_sample", &g.next_sample},  {"next_fields", &g.next_fields},       {"next_checkpoint", &g.next_checkpoint},
      {"stats_t0", &g.stats_t0},        {"e0_kinetic", &g.e0.kinetic},         {"e0_potential", &g.e0.potential},
      {"e0_elastic", &g.e0.elastic},    {"e0_work_in", &g.e0.work_in},         {"e0_dissipated", &g.e0.dissipated},
      {"lubrication0", &g.lubrication0}};
}

}  // namespace

void StirredRun::Impl::writeCheckpoint(const fs::path& path) const {
  io::CheckpointData cp = demCheckpoint(*engine, t, step);
  std::vector<dem::CollisionTally> tally;
  std::vector<double> lubrication;
  engine->stirredAccounts(tally, lubrication);
  if (!tally.empty()) cp.reals["stirred_tally"] = flatTallies(tally);
  if (!lubrication.empty()) cp.reals["stirred_lubrication"] = lubrication;
  if (have_tally) cp.reals["stirred_last_tally"] = flatTallies(last_tally);
  const Ledger& g = ledger;
  cp.scalars = {{"stirred", 1.0},
                {"phi", phi},
                {"dt", dt},
                {"level", double(g.level)},
                {"level_open", g.level_open ? 1.0 : 0.0},
                {"level_mid_taken", g.level_mid_taken ? 1.0 : 0.0},
                {"field_samples", double(field_samples)}};
  for (const auto& [key, v] : ledgerReals(g)) cp.scalars[key] = *v;
  for (const auto& [key, field] : levelFields()) {
    std::vector<double>& v = cp.reals[key];
    for (const StirredLevel& lv : levels) v.push_back(lv.*field);
  }
  for (const StirredLevel& lv : levels) {
    cp.reals["level_samples"].push_back(lv.samples);
    cp.reals["level_steady"].push_back(lv.steady ? 1.0 : 0.0);
  }
  std::vector<double>& rg = cp.reals["regions"];
  for (const RegionStats& r : regions) {
    rg.insert(rg.end(), {r.collisions, r.bead_samples});
    rg.insert(rg.end(), r.dissipated, r.dissipated + dem::kModeCount);
    rg.insert(rg.end(), r.energy, r.energy + dem::kModeCount);
  }
  cp.reals["velocity_sum"] = v_sum;
  cp.reals["spin_sum"] = w_sum;
  cp.reals["velocity_count"] = n_sum;
  io::writeCheckpoint(path, cp);
}

// Called from the constructor, between setState and initialize. The case may change time.end
// (to run on) but not what the checkpoint's numbers mean: beads, time step, speed program,
// sampling grid.
void StirredRun::Impl::restoreCheckpoint() {
  const std::string& path = options.restart;
  const io::CheckpointData cp = io::readCheckpoint(path);
  auto sc = [&](const char* k) {
    const auto it = cp.scalars.find(k);
    if (it == cp.scalars.end()) throw core::InputError(path + ": checkpoint lacks '" + k + "'");
    return it->second;
  };
  auto real = [&](const char* k) -> const std::vector<double>& {
    const auto it = cp.reals.find(k);
    if (it == cp.reals.end()) throw core::InputError(path + ": checkpoint lacks '" + k + "'");
    return it->second;
  };
  if (!cp.scalars.count("stirred"))
    throw core::InputError(path + ": not a stirred mill's checkpoint (written by a drum run?); " + scene.source +
                           " is a stirred mill");
  const dem::DemHostState s = takeDemState(cp, path);
  std::ostringstream bad;
  if (s.size() != beads.size())
    bad << "checkpoint holds " << s.size() << " beads, " << scene.source << " places " << beads.size();
  else if (std::abs(sc("dt") - dt) > 1e-9 * dt)
    bad << "checkpoint's time step " << sc("dt") << " s differs from the case's " << dt
        << " s (contact law, bead size or time.dt_divisor changed)";
  else if (real("level_t_end").size() > levels.size() || real("velocity_sum").size() != v_sum.size())
    bad << "checkpoint's speed program or sampling grid differs from " << scene.source << "'s";
  if (!bad.str().empty()) throw core::InputError(path + ": " + bad.str());
  engine->setState(s);
  const auto lubrication =
      cp.reals.count("stirred_lubrication") ? cp.reals.at("stirred_lubrication") : std::vector<double>{};
  engine->setStirredAccounts(
      cp.reals.count("stirred_tally") ? tallies(cp.reals.at("stirred_tally")) : std::vector<dem::CollisionTally>{},
      lubrication);
  have_tally = cp.reals.count("stirred_last_tally") > 0;
  if (have_tally) last_tally = tallies(cp.reals.at("stirred_last_tally"));
  t = cp.time;
  step = cp.step;
  phi = sc("phi");
  Ledger& g = ledger;
  g.level = static_cast<std::size_t>(sc("level"));
  g.level_open = sc("level_open") != 0;
  g.level_mid_taken = sc("level_mid_taken") != 0;
  for (const auto& [key, v] : ledgerReals(g)) *v = sc(key);
  field_samples = static_cast<int>(sc("field_samples"));
  const std::size_t saved = real("level_t_end").size();
  for (const auto& [key, field] : levelFields()) {
    const std::vector<double>& v = real(key);
    for (std::size_t k = 0; k < saved; ++k) levels[k].*field = v[k];
  }
  for (std::size_t k = 0; k < saved; ++k) {
    levels[k].samples = static_cast<int>(real("level_samples")[k]);
    levels[k].steady = real("level_steady")[k] != 0;
  }
  const std::vector<double>& rg = real("regions");
  if (rg.size() != regions.size() * kRegionReals) throw core::InputError(path + ": checkpoint's regions are malformed");
  for (std::size_t r = 0; r < regions.size(); ++r) {
    const double* x = &rg[r * kRegionReals];
    regions[r].collisions = x[0];
    regions[r].bead_samples = x[1];
    std::copy(x + 2, x + 2 + dem::kModeCount, regions[r].dissipated);
    std::copy(x + 2 + dem::kModeCount, x + kRegionReals, regions[r].energy);
  }
  v_sum = real("velocity_sum");
  w_sum = real("spin_sum");
  n_sum = real("velocity_count");
}

void StirredRun::Impl::writeOutputs(const fs::path& out, double stats_time) const {
  {
    std::ofstream f(out / "power.csv");
    f << std::setprecision(9)
      << "rpm,power_W,net_power_W,stirrer_torque_Nm,outer_torque_Nm,window_from_s,window_to_s,samples,"
         "power_first_half_W,power_second_half_W,steady,revolutions_held,kinetic_open_J,kinetic_close_J\n";
    for (const auto& lv : levels)
      f << lv.rpm << "," << lv.power_W << "," << lv.net_power_W << "," << lv.stirrer_torque_Nm << ","
        << lv.outer_torque_Nm << "," << lv.t_average << "," << lv.t_end << "," << lv.samples << ","
        << lv.power_first_half_W << "," << lv.power_second_half_W << "," << (lv.steady ? 1 : 0) << ","
        << lv.revolutions_held << "," << lv.kinetic_open_J << "," << lv.kinetic_close_J << "\n";
  }
  if (levels.size() > 1) {
    io::PlotSeries p;
    p.label = "millsim (DEM, this run)";
    p.markers = true;
    p.rgb = {200, 30, 30};
    for (const auto& lv : levels) {
      p.x.push_back(lv.rpm);
      p.y.push_back(lv.net_power_W);
    }
    io::PlotAxes ax;
    ax.title = "Net power vs stirrer speed";
    ax.x_label = "stirrer speed [rpm]";
    ax.y_label = "net power [W]";
    io::writeLinePlot((out / "power.png").string(), ax, {p});
  }
  if (collisionStats()) writeCollisionOutputs(out, stats_time);
  // summary.json: the usual head plus the stirred-mill block.
  nlohmann::ordered_json j = summaryHead(summary, scene.name, scene.source);
  nlohmann::ordered_json lv_json = nlohmann::ordered_json::array();
  for (const auto& lv : levels)
    lv_json.push_back({{"rpm", lv.rpm},
                       {"power_W", lv.power_W},
                       {"net_power_W", lv.net_power_W},
                       {"stirrer_torque_Nm", lv.stirrer_torque_Nm},
                       {"outer_torque_Nm", lv.outer_torque_Nm},
                       {"window_s", {lv.t_average, lv.t_end}},
                       {"window_mid_s", lv.t_mid},
                       {"power_halves_W", {lv.power_first_half_W, lv.power_second_half_W}},
                       {"steady", lv.steady},
                       {"revolutions_held", lv.revolutions_held},
                       {"kinetic_J", {lv.kinetic_open_J, lv.kinetic_close_J}}});
  j["stirred"] = {{"beads", summary.particles},
                  {"neighbour_rebuilds", summary.neighbour_rebuilds},
                  {"coordination_number_end", coordination_end},
                  {"bead_mass_kg", summary.charge_mass_kg},
                  {"levels", lv_json},
                  {"energy",
                   {{"work_in_J", energy.work_in},
                    {"d_kinetic_J", energy.d_kinetic},
                    {"d_potential_J", energy.d_potential},
                    {"d_elastic_J", energy.d_elastic},
                    {"contact_dissipated_J", energy.contact_dissipated},
                    {"lubrication_dissipated_J", energy.lubrication_dissipated},
                    {"residual_J", energy.residual},
                    {"residual_relative", energy.work_in != 0 ? energy.residual / energy.work_in : 0.0}}}};
  j["memory_bytes"] = memoryJson(engine->memoryBytes());
  writeJsonFile(out / "summary.json", j);
}

// Collision typology totals (collisions.csv), by region (regions.csv), and the velocity field.
void StirredRun::Impl::writeCollisionOutputs(const fs::path& out, double stats_time) const {
  double diss_total = 0, coll_total = 0;
  double diss_mode[dem::kModeCount] = {0, 0, 0, 0}, energy_mode[dem::kModeCount] = {0, 0, 0, 0};
  for (const auto& r : regions) {
    coll_total += r.collisions;
    for (int q = 0; q < dem::kModeCount; ++q) {
      diss_mode[q] += r.dissipated[q];
      energy_mode[q] += r.energy[q];
      diss_total += r.dissipated[q];
    }
  }
  {
    std::ofstream f(out / "collisions.csv");
    f << std::setprecision(9)
      << "mode,dissipated_J,dissipated_percent,dissipated_power_W,collision_energy_J,collision_energy_percent\n";
    double e_total = 0;
    for (double e : energy_mode) e_total += e;
    for (int q = 0; q < dem::kModeCount; ++q)
      f << kModeNames[q] << "," << diss_mode[q] << "," << (diss_total > 0 ? 100 * diss_mode[q] / diss_total : 0) << ","
        << (stats_time > 0 ? diss_mode[q] / stats_time : 0) << "," << energy_mode[q] << ","
        << (e_total > 0 ? 100 * energy_mode[q] / e_total : 0) << "\n";
    f << "# window_s," << stats_time << "\n# collisions," << coll_total << "\n# collision_frequency_per_s,"
      << (stats_time > 0 ? coll_total / stats_time : 0) << "\n";
    const auto& t = final_sums.totals;
    f << "# run totals (whole run): bead-bead normal damping J," << t.dissipated_normal
      << "\n# run totals: bead-bead tangential J,"
      << (t.dissipated[0] + t.dissipated[1] + t.dissipated[2] + t.dissipated[3] - t.dissipated_normal)
      << "\n# run totals: bead-wall contacts J," << t.dissipated_wall << "\n# run totals: lubrication J,"
      << energy.lubrication_dissipated << "\n";
  }
  {
    std::ofstream f(out / "regions.csv");
    f << std::setprecision(9) << "region,collisions,collision_frequency_per_s,collision_percent,mean_beads";
    for (const char* m : kModeNames) f << ",dissipated_" << m << "_J";
    for (const char* m : kModeNames) f << ",energy_" << m << "_J";
    f << "\n";
    const double samples = std::max(1, field_samples);
    for (const auto& r : regions) {
      f << r.name << "," << r.collisions << "," << (stats_time > 0 ? r.collisions / stats_time : 0) << ","
        << (coll_total > 0 ? 100 * r.collisions / coll_total : 0) << "," << r.bead_samples / samples;
      for (double d : r.dissipated) f << "," << d;
      for (double e : r.energy) f << "," << e;
      f << "\n";
    }
  }
  writeVelocityField(out);
}

void StirredRun::Impl::writeVelocityField(const fs::path& out) const {
  const std::size_t cells = n_sum.size();
  std::vector<float> v(cells, 0.f), w(cells, 0.f), n(cells, 0.f);
  for (std::size_t c = 0; c < cells; ++c) {
    n[c] = static_cast<float>(n_sum[c]);
    if (n_sum[c] > 0) {
      v[c] = static_cast<float>(v_sum[c] / n_sum[c]);
      w[c] = static_cast<float>(w_sum[c] / n_sum[c]);
    }
  }
  const std::string path = (out / "velocity_field.h5").string();
  const hid_t file = H5Fcreate(path.c_str(), H5F_ACC_TRUNC, H5P_DEFAULT, H5P_DEFAULT);
  if (file < 0) throw core::InputError(path + ": cannot create the velocity field file");
  const hsize_t dims[3] = {static_cast<hsize_t>(gz), static_cast<hsize_t>(gx), static_cast<hsize_t>(gx)};
  auto put = [&](const char* name, const std::vector<float>& data) {
    const hid_t space = H5Screate_simple(3, dims, nullptr);
    const hid_t set = H5Dcreate2(file, name, H5T_IEEE_F32LE, space, H5P_DEFAULT, H5P_DEFAULT, H5P_DEFAULT);
    H5Dwrite(set, H5T_NATIVE_FLOAT, H5S_ALL, H5S_ALL, H5P_DEFAULT, data.data());
    H5Dclose(set);
    H5Sclose(space);
  };
  put("speed_mean_m_s", v);
  put("spin_mean_rad_s", w);
  put("bead_samples", n);
  const double R = 0.5 * scene.stirrer.chamber_diameter;
  const double attrs[4] = {-R, R, 0.0, scene.stirrer.chamber_length};
  const hsize_t four = 4;
  const hid_t aspace = H5Screate_simple(1, &four, nullptr);
  const hid_t attr = H5Acreate2(file, "extent_x0_x1_z0_z1_m", H5T_IEEE_F64LE, aspace, H5P_DEFAULT, H5P_DEFAULT);
  H5Awrite(attr, H5T_NATIVE_DOUBLE, attrs);
  H5Aclose(attr);
  H5Sclose(aspace);
  H5Fclose(file);
  // Cross-section maps (x right, y up), averaged over the chamber length, bead-weighted.
  auto map = [&](const std::vector<double>& sum, const char* file_name, const char* label) {
    std::vector<double> avg(static_cast<std::size_t>(gx) * gx, 0.0), cnt(avg.size(), 0.0);
    for (int z = 0; z < gz; ++z)
      for (std::size_t c = 0; c < avg.size(); ++c) {
        avg[c] += sum[z * avg.size() + c];
        cnt[c] += n_sum[z * avg.size() + c];
      }
    double vmax = 0;
    for (std::size_t c = 0; c < avg.size(); ++c) {
      avg[c] = cnt[c] > 0 ? avg[c] / cnt[c] : 0.0;
      vmax = std::max(vmax, avg[c]);
    }
    const int px = 16, bar = 40;
    cv::Mat img(gx * px + 40, gx * px + bar + 60, CV_8UC3, cv::Scalar(255, 255, 255));
    for (int y = 0; y < gx; ++y)
      for (int x = 0; x < gx; ++x) {
        const std::size_t c = static_cast<std::size_t>(y) * gx + x;
        cv::Scalar colour(230, 230, 230);
        if (cnt[c] > 0) {
          cv::Mat one(1, 1, CV_8UC1, cv::Scalar(static_cast<int>(255 * (vmax > 0 ? avg[c] / vmax : 0))));
          cv::Mat rgb;
          cv::applyColorMap(one, rgb, cv::COLORMAP_JET);
          const cv::Vec3b p = rgb.at<cv::Vec3b>(0, 0);
          colour = cv::Scalar(p[0], p[1], p[2]);
        }
        const int row = (gx - 1 - y) * px + 30;  // y up
        cv::rectangle(img, cv::Rect(x * px, row, px, px), colour, cv::FILLED);
      }
    for (int k = 0; k < 256; ++k) {
      cv::Mat one(1, 1, CV_8UC1, cv::Scalar(k));
      cv::Mat rgb;
      cv::applyColorMap(one, rgb, cv::COLORMAP_JET);
      const cv::Vec3b p = rgb.at<cv::Vec3b>(0, 0);
      const int y = 30 + (gx * px - 1) - k * (gx * px - 1) / 255;
      cv::line(img, {gx * px + 10, y}, {gx * px + 10 + bar / 2, y}, cv::Scalar(p[0], p[1], p[2]));
    }
    std::ostringstream top;
    top << label << " (mean over length), max " << std::setprecision(3) << vmax;
    cv::putText(img, top.str(), {4, 20}, cv::FONT_HERSHEY_SIMPLEX, 0.45, cv::Scalar(0, 0, 0), 1);
    vision::detail::writePngBgr((out / file_name).string(), img);
  };
  map(v_sum, "velocity_translational.png", "|v| [m/s]");
  map(w_sum, "velocity_rotational.png", "|w| [rad/s]");
}

StirredRun::StirredRun(const scene::Scene& scene, const RunOptions& options)
    : m_impl(std::make_unique<Impl>(scene, options)) {}
StirredRun::~StirredRun() = default;
const RunSummary& StirredRun::run() {
  m_impl->run();
  return m_impl->summary;
}
std::vector<std::string> StirredRun::stages() const {
  std::vector<std::string> s{"neighbour_build", "dem_kick_drift", "dem_contacts_and_stirrer_walls"};
  if (m_impl->scene.lubrication.viscosity > 0) s.push_back("lubrication_pairs_and_walls");
  s.push_back("dem_kick");
  if (m_impl->collisionStats()) s.push_back("collision_sampling");
  return s;
}
std::map<std::string, std::size_t> StirredRun::memoryReport() const { return m_impl->engine->memoryBytes(); }
const RunSummary& StirredRun::summary() const { return m_impl->summary; }
double StirredRun::timeStep() const { return m_impl->dt; }
std::size_t StirredRun::particleCount() const { return m_impl->beads.size(); }
double StirredRun::endTime() const { return m_impl->endTime(); }
const std::vector<StirredLevel>& StirredRun::levels() const { return m_impl->levels; }
const StirredEnergy& StirredRun::energy() const { return m_impl->energy; }
const std::vector<RegionStats>& StirredRun::regions() const { return m_impl->regions; }
const dem::StirredSums& StirredRun::finalSums() const { return m_impl->final_sums; }

}  // namespace millsim::sim
