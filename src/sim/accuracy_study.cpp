#include "millsim/sim/accuracy_study.hpp"

#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <sstream>
#include <stdexcept>

#include "dem/contact/damping.hpp"
#include "dem/dem_engine.hpp"
#include "millsim/core/error.hpp"
#include "millsim/io/case_xml.hpp"
#include "millsim/io/plot_png.hpp"
#include "millsim/sim/martin_moyce.hpp"
#include "millsim/sim/simulation.hpp"
#include "sim/sph_setup.hpp"

namespace millsim::sim {

namespace {

const std::vector<std::string> kStudyProblems = {"dam_break_2d", "hertz_impact", "drum_300", "wet_drum_angle",
                                                 "wet_drum_slurry"};

double seconds(std::chrono::steady_clock::time_point t0) {
  return std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
}

StudyRow damBreak(const std::string& source_dir, const std::string& axis, const std::string& setting,
                  const std::vector<std::string>& sets, bool single_precision = false) {
  const double a = 0.05715, g = 9.81, t_end = 2.5 / std::sqrt(2 * g / a) + 1e-3;
  std::vector<std::string> all = sets;
  all.push_back("output.fields_every=0");
  const scene::Scene sc = io::loadCaseFile(source_dir + "/cases/dam_break_2d.xml", all);
  const sph::SphSetup setup = sphSetupOf(sc);
  auto engine = sph::makeSphEngineOmp(setup, single_precision);
  const sph::SphHostState particles = sphParticlesOf(sc, setup);
  engine->setState(particles);
  engine->initialize({});
  const auto t0 = std::chrono::steady_clock::now();
  std::vector<double> ts{0.0}, xs{engine->sums().max_x};
  double t = 0;
  long long steps = 0;
  while (t < t_end) {
    const double dt = std::min(engine->nextDt(), t_end - t);
    engine->step(dt, {}, {});
    t += dt;
    ++steps;
    ts.push_back(t);
    xs.push_back(engine->sums().max_x);
  }
  StudyRow r;
  r.problem = "dam_break_2d";
  r.axis = axis;
  r.setting = setting;
  r.wall_s = seconds(t0);
  r.simulated_s = t;
  r.particles = static_cast<long long>(particles.size());
  r.steps = steps;
  r.error = compareWithMartinMoyce(ts, xs, a, g).mean_error_raw;
  return r;
}

StudyRow hertzImpact(const std::string& axis, const std::string& setting, double divisor, double young, bool single) {
  const double r = 0.0075, v = 1.0, rho = 7800.92, e = 0.39, nu = 0.29;
  const auto model = dem::DampingModel::kExact;
  dem::DemSetup setup;
  setup.k_coef = 4.0 / 3.0 * dem::effectiveModulus(young, nu);
  setup.alpha = dem::dampingAlpha(model, e);
  setup.wall_mass_factor = dem::wallMassFactor(model);
  setup.gravity = {0, 0, 0};
  setup.skin = 0.2 * r;
  setup.max_radius = r;
  setup.domain_lo = {-0.05, -0.05, -0.05};
  setup.domain_hi = {0.05, 0.05, 0.05};
  auto engine = dem::makeDemEngineOmp(setup, single);
  const double m = rho * 4.0 / 3.0 * std::acos(-1.0) * r * r * r;
  dem::DemHostState s;
  s.pos = {0, 0, 1.05 * r};
  s.vel = {0, 0, -v};
  s.omega = {0, 0, 0};
  s.radius = {r};
  s.mass = {m};
  s.inertia = {0.4 * m * r * r};
  engine->setState(s);
  dem::DrumState walls;  // the front plate z = 0 as a flat wall, far from everything else
  walls.radius = 10;
  walls.z_back = 20;
  engine->initialize(walls);
  const double tc = dem::hertzContactTime(m, r, dem::effectiveModulus(young, nu), v);
  const double dt = tc / divisor;
  const auto t0 = std::chrono::steady_clock::now();
  double t = 0, t_in = -1, e_measured = 0, t_contact = 0;
  bool was_in = false;
  long long steps = 0;
  for (; steps < 1000000; ++steps) {
    engine->step(walls, dt);
    t += dt;
    engine->getState(s);
    const bool in = s.pos[2] < r;
    if (in && !was_in) t_in = t;
    if (!in && was_in) {
      e_measured = s.vel[2] / v;
      t_contact = t - t_in;
      break;
    }
    was_in = in;
  }
  StudyRow row;
  row.problem = "hertz_impact";
  row.axis = axis;
  row.setting = setting;
  row.wall_s = seconds(t0);
  row.simulated_s = t;
  row.particles = 1;
  row.steps = steps;
  (void)t_contact;  // with e = 0.39 the damped contact lasts longer than Hertz's elastic t_c
  row.error = std::abs(e_measured - e) / e;
  return row;
}
// One run of a mill case (one thread, no files) as a study row whose value is the angle of
// repose; `summary` gets the run's summary for what else the caller takes from it.
StudyRow angleRow(const std::string& case_path, const std::vector<std::string>& sets, const std::string& precision,
                  const std::string& problem, const std::string& axis, const std::string& setting,
                  RunSummary& summary) {
  RunOptions opt;
  opt.write_outputs = false;
  opt.backend = "omp";
  opt.precision = precision;
  opt.threads = 1;
  Simulation simulation(io::loadCaseFile(case_path, sets), opt);
  summary = simulation.run();
  StudyRow r;
  r.problem = problem;
  r.axis = axis;
  r.setting = setting;
  r.wall_s = summary.wall_time_s;
  r.simulated_s = summary.simulated_time_s;
  r.particles = static_cast<long long>(summary.particles + summary.sph_particles);
  r.steps = summary.steps;
  r.value = summary.angle_valid ? summary.angle_of_repose_deg : std::nan("");
  return r;
}

// The shipped 300 mm mill (balls only) with overrides; `value` = its dynamic angle of repose. The
// error (difference to the finest setting's angle) is filled in once every run is done.
StudyRow drumAngle(const std::string& source_dir, bool quick, const std::string& axis, const std::string& setting,
                   const std::vector<std::string>& sets, const std::string& precision = "double") {
  std::vector<std::string> all = sets;
  for (const char* s : {"output.fields_every=0", "output.checkpoint_every=0"}) all.push_back(s);
  if (quick)  // 1 s of compaction, 3 s of rotation, 30 frames over the last 1.5 s
    for (const char* s : {"time.end=4", "compaction.duration=1", "drum.start_time=1", "angle_of_repose.start_time=2.5",
                          "angle_of_repose.frames=30"})
      all.push_back(s);
  RunSummary s;
  return angleRow(source_dir + "/cases/ball_mill_300_balls.xml", all, precision, "drum_300", axis, setting, s);
}

// The small wet mill with overrides (cases/wet_drum_small.xml, 1.6 s): one run, two rows, the
// balls' angle of repose and the fitted slurry curve (errors filled in against the reference).
std::vector<StudyRow> wetDrum(const std::string& source_dir, const std::string& axis, const std::string& setting,
                              const std::vector<std::string>& sets) {
  std::vector<std::string> all = sets;
  for (const char* s : {"output.fields_every=0", "output.checkpoint_every=0"}) all.push_back(s);
  RunSummary s;
  const StudyRow angle =
      angleRow(source_dir + "/cases/wet_drum_small.xml", all, "double", "wet_drum_angle", axis, setting, s);
  StudyRow slurry = angle;
  slurry.problem = "wet_drum_slurry";
  slurry.value = s.slurry_valid ? s.slurry_coef[0] : std::nan("");
  if (s.slurry_valid) slurry.curve.assign(s.slurry_coef.begin(), s.slurry_coef.end());
  return {angle, slurry};
}

}  // namespace

std::vector<StudyRow> runAccuracyStudy(bool quick, const std::string& source_dir, const std::string& only) {
  std::vector<StudyRow> rows;
  // --only PROBLEM[:AXIS]: run just those rows (to add or redo an axis without the rest).
  const std::size_t colon = only.find(':');
  const std::string only_problem = only.substr(0, colon),
                    only_axis = colon == std::string::npos ? "" : only.substr(colon + 1);
  auto want = [&](const char* problem, const char* axis) {
    return only.empty() || (only_problem == problem && (only_axis.empty() || only_axis == axis));
  };
  const double a = 0.05715;
  // Dam break: one factor at a time around a base resolution (a/20 quick, a/40 full).
  const int base = quick ? 20 : 40;
  // Full precision: std::to_string's 6 decimals would shift dp = a/40 off the shipped case's lattice.
  auto dp = [a](int n) {
    char buf[64];
    std::snprintf(buf, sizeof buf, "sph.dp=%.17g", a / n);
    return std::string(buf);
  };
  const std::string base_dp = dp(base);
  if (want("dam_break_2d", "dp"))
    for (int n : quick ? std::vector<int>{10, 20} : std::vector<int>{20, 40, 80})
      rows.push_back(damBreak(source_dir, "dp", "a/" + std::to_string(n), {dp(n)}));
  if (want("dam_break_2d", "kernel"))
    for (const char* k : {"cubic"})
      rows.push_back(damBreak(source_dir, "kernel", k, {base_dp, std::string("sph.kernel=") + k}));
  if (want("dam_break_2d", "ddt"))
    for (const char* d : {"none", "molteni"})
      rows.push_back(damBreak(source_dir, "ddt", d, {base_dp, std::string("sph.ddt=") + d}));
  if (want("dam_break_2d", "integrator"))
    rows.push_back(damBreak(source_dir, "integrator", "symplectic", {base_dp, "sph.integrator=symplectic"}));
  if (want("dam_break_2d", "cfl"))
    for (const char* c : quick ? std::vector<const char*>{"0.3"} : std::vector<const char*>{"0.1", "0.3"})
      rows.push_back(damBreak(source_dir, "cfl", c, {base_dp, std::string("sph.cfl=") + c}));
  if (want("dam_break_2d", "precision")) rows.push_back(damBreak(source_dir, "precision", "float", {base_dp}, true));
  // Hertz impact: dt divisor, stiffness, precision.
  if (want("hertz_impact", "dt_divisor"))
    for (double n : quick ? std::vector<double>{10, 50} : std::vector<double>{10, 20, 50, 100, 400})
      rows.push_back(hertzImpact("dt_divisor", "t_c/" + std::to_string(int(n)), n, 1e8, false));
  if (want("hertz_impact", "youngs_modulus"))
    for (double young : quick ? std::vector<double>{1e7} : std::vector<double>{1e7, 1e9, 2e11}) {
      char label[32];
      std::snprintf(label, sizeof label, "E = %.0e Pa", young);
      rows.push_back(hertzImpact("youngs_modulus", label, 50, young, false));
    }
  if (want("hertz_impact", "precision")) rows.push_back(hertzImpact("precision", "float", 50, 1e8, true));

  // 300 mm drum, balls only: angle of repose against the finest setting (t_c/200; quick: t_c/100).
  // A second charge seed at the case's settings gives the run-to-run noise floor of one angle.
  const int finest = quick ? 100 : 200;
  if (want("drum_300", "reference"))
    rows.push_back(drumAngle(source_dir, quick, "reference", "t_c/" + std::to_string(finest),
                             {"time.dt_divisor=" + std::to_string(finest)}));
  if (want("drum_300", "dt_divisor"))
    for (int n : quick ? std::vector<int>{50} : std::vector<int>{20, 50, 100})
      rows.push_back(drumAngle(source_dir, quick, "dt_divisor", "t_c/" + std::to_string(n),
                               {"time.dt_divisor=" + std::to_string(n)}));
  if (!quick) {
    if (want("drum_300", "seed"))
      rows.push_back(drumAngle(source_dir, quick, "seed", "charge seed 2", {"charge.seed=2"}));
    if (want("drum_300", "youngs_modulus"))
      for (double young : {1e7, 1e9, 2e11}) {
        char label[32], set[64];
        std::snprintf(label, sizeof label, "E = %.0e Pa", young);
        std::snprintf(set, sizeof set, "dem.youngs_modulus=%.17g", young);
        rows.push_back(drumAngle(source_dir, quick, "youngs_modulus", label, {set}));
      }
    if (want("drum_300", "precision")) rows.push_back(drumAngle(source_dir, quick, "precision", "float", {}, "float"));
    // The paper's ball representation: DualSPHysics DCDEM bodies of 5 mm particles (t_c/50 of
    // their element contacts), against analytic spheres.
    if (want("drum_300", "representation"))
      rows.push_back(
          drumAngle(source_dir, quick, "representation", "DCDEM balls (dp = 5 mm)", {"dem.representation=dcdem"}));
  }

  // Small wet mill: the balls' angle and the slurry curve against the finest SPH spacing (4 mm;
  // quick: 7.5 mm, the case's 5 mm costs ~4 min). A second charge seed gives the noise floor.
  auto wet = [&](const char* axis, const std::string& setting, const std::vector<std::string>& sets) {
    if (!want("wet_drum", axis)) return;
    for (StudyRow& r : wetDrum(source_dir, axis, setting, sets)) rows.push_back(std::move(r));
  };
  const char* wet_finest = quick ? "0.0075" : "0.004";
  wet("reference", std::string("dp = ") + wet_finest + " m", {std::string("sph.dp=") + wet_finest});
  for (const char* d : quick ? std::vector<const char*>{"0.01"} : std::vector<const char*>{"0.005", "0.0075"})
    wet("dp", std::string("dp = ") + d + " m", {std::string("sph.dp=") + d});
  if (!quick) {
    wet("seed", "charge seed 2 (dp = 0.005 m)", {"charge.seed=2"});
    wet("representation", "DCDEM balls (dp = 5 mm)", {"dem.representation=dcdem"});
  }
  fillReferenceErrors(rows);
  return rows;
}

double slurryCurveDistance(const std::vector<double>& a, const std::vector<double>& b, double half_width_mm) {
  if (a.size() != 3 || b.size() != 3) return std::nan("");
  // d = p + q x + r x^2; its mean square over |x| <= L, integrated exactly (odd powers cancel).
  const double p = a[0] - b[0], q = a[1] - b[1], r = a[2] - b[2], L2 = half_width_mm * half_width_mm;
  return std::sqrt(p * p + (q * q + 2 * p * r) * L2 / 3 + r * r * L2 * L2 / 5);
}

void fillReferenceErrors(std::vector<StudyRow>& rows) {
  // The wet mill's drum is 200 mm across: its slurry curves are compared over |x| <= 50 mm.
  constexpr double kWetHalfWidthMm = 50;
  for (const char* problem : {"drum_300", "wet_drum_angle", "wet_drum_slurry"}) {
    const StudyRow* ref = nullptr;
    for (const StudyRow& r : rows)
      if (r.problem == problem && r.axis == "reference") ref = &r;
    const bool curve = std::string(problem) == "wet_drum_slurry";
    for (StudyRow& r : rows) {
      if (r.problem != problem) continue;
      if (!ref)
        r.error = std::nan("");
      else
        r.error = curve ? slurryCurveDistance(r.curve, ref->curve, kWetHalfWidthMm) : std::abs(r.value - ref->value);
    }
  }
}

std::vector<StudyRow> mergeStudyRows(std::vector<StudyRow> base, const std::vector<StudyRow>& fresh) {
  for (const StudyRow& f : fresh) {
    auto same = std::find_if(base.begin(), base.end(), [&](const StudyRow& b) {
      return b.problem == f.problem && b.axis == f.axis && b.setting == f.setting;
    });
    if (same != base.end()) {
      *same = f;
      continue;
    }
    // After the problem's last row, so each problem's rows stay together.
    auto last = std::find_if(base.rbegin(), base.rend(), [&](const StudyRow& b) { return b.problem == f.problem; });
    base.insert(last == base.rend() ? base.end() : last.base(), f);
  }
  fillReferenceErrors(base);
  return base;
}

std::vector<std::size_t> paretoFront(const std::vector<StudyRow>& rows, const std::string& problem) {
  std::vector<std::size_t> idx;
  // The "seed" rows measure run-to-run noise, not a setting a user picks: not on the front.
  for (std::size_t i = 0; i < rows.size(); ++i)
    if (rows[i].problem == problem && rows[i].axis != "seed") idx.push_back(i);
  std::sort(idx.begin(), idx.end(), [&](std::size_t a, std::size_t b) { return rows[a].wall_s < rows[b].wall_s; });
  std::vector<std::size_t> front;
  double best = 1e300;
  for (std::size_t i : idx)
    if (rows[i].error < best) {
      best = rows[i].error;
      front.push_back(i);
    }
  return front;
}

std::vector<StudyRow> readAccuracyStudy(const std::string& csv) {
  std::ifstream in(csv);
  if (!in) throw core::InputError(csv + ": cannot read");
  std::string line;
  std::getline(in, line);
  if (line.rfind("problem,axis,setting,error,value,wall_s", 0) != 0)
    throw core::InputError(csv, 1, "not an accuracy_cost.csv header");
  std::vector<StudyRow> rows;
  for (int n = 2; std::getline(in, line); ++n) {
    std::vector<std::string> c;
    std::stringstream ss(line);
    for (std::string cell; std::getline(ss, cell, ',');) c.push_back(cell);
    // getline drops an empty last cell: rows without a slurry curve (and studies written before
    // the column existed) come out with 11.
    if (c.size() == 11) c.emplace_back();
    if (c.size() != 12) throw core::InputError(csv, n, "expected 12 columns");
    try {
      StudyRow r;
      r.problem = c[0];
      r.axis = c[1];
      r.setting = c[2];
      r.error = std::stod(c[3]);
      r.value = std::stod(c[4]);
      r.wall_s = std::stod(c[5]);
      const double per_s = std::stod(c[6]);
      r.simulated_s = per_s > 0 ? r.wall_s / per_s : 0.0;
      r.particles = std::stoll(c[7]);
      r.steps = std::stoll(c[8]);
      r.backend = c[9];
      std::stringstream curve(c[11]);
      for (std::string v; std::getline(curve, v, ';');) r.curve.push_back(std::stod(v));
      rows.push_back(r);
    } catch (const std::logic_error&) {
      throw core::InputError(csv, n, "not a number where one is expected");
    }
  }
  return rows;
}

void writeAccuracyStudy(const std::vector<StudyRow>& rows, const std::string& out_dir) {
  std::filesystem::create_directories(out_dir);
  const std::string csv = out_dir + "/accuracy_cost.csv";
  std::ofstream out(csv);
  if (!out) throw std::runtime_error(csv + ": cannot write");
  out << "problem,axis,setting,error,value,wall_s,wall_s_per_simulated_s,particles,steps,backend,pareto,"
         "slurry_curve_mm\n";
  std::vector<bool> on_front(rows.size(), false);
  for (const std::string& problem : kStudyProblems)
    for (std::size_t i : paretoFront(rows, problem)) on_front[i] = true;
  // Plain CSV without quoting: a comma inside a label would shift the columns, so it becomes ';'.
  auto cell = [](std::string v) {
    std::replace(v.begin(), v.end(), ',', ';');
    return v;
  };
  for (std::size_t i = 0; i < rows.size(); ++i) {
    const StudyRow& r = rows[i];
    out << cell(r.problem) << "," << cell(r.axis) << "," << cell(r.setting) << "," << r.error << "," << r.value << ","
        << r.wall_s << "," << (r.simulated_s > 0 ? r.wall_s / r.simulated_s : 0.0) << "," << r.particles << ","
        << r.steps << "," << r.backend << "," << (on_front[i] ? 1 : 0) << ",";
    // The curve's coefficients in full precision (the errors are recomputed from them on --merge).
    for (std::size_t k = 0; k < r.curve.size(); ++k) {
      char buf[32];
      std::snprintf(buf, sizeof buf, "%.17g", r.curve[k]);
      out << (k ? ";" : "") << buf;
    }
    out << "\n";
  }
  for (const std::string& problem : kStudyProblems) {
    // Relative errors are plotted in %, angle differences in degrees, curve distances in mm.
    const bool degrees = problem == "drum_300" || problem == "wet_drum_angle";
    const bool mm = problem == "wet_drum_slurry";
    const double scale = degrees || mm ? 1.0 : 100.0;
    io::PlotSeries all, front;
    all.label = "runs (" + problem + ")";
    all.line = false;
    all.markers = true;
    all.rgb = {31, 119, 180};
    front.label = "Pareto front";
    front.rgb = {214, 39, 40};
    for (std::size_t i = 0; i < rows.size(); ++i)
      if (rows[i].problem == problem) {
        all.x.push_back(std::log10(std::max(rows[i].wall_s, 1e-6)));
        all.y.push_back(scale * rows[i].error);
      }
    for (std::size_t i : paretoFront(rows, problem)) {
      front.x.push_back(std::log10(std::max(rows[i].wall_s, 1e-6)));
      front.y.push_back(scale * rows[i].error);
    }
    if (all.x.empty()) continue;  // a partial study (--only) or one from before the problem existed
    io::PlotAxes axes;
    // Room above the highest point for the legend (top left), and a margin left and right.
    {
      axes.x_min = *std::min_element(all.x.begin(), all.x.end()) - 0.1;
      axes.x_max = *std::max_element(all.x.begin(), all.x.end()) + 0.1;
      axes.y_min = 0;
      axes.y_max = 1.35 * std::max(*std::max_element(all.y.begin(), all.y.end()), 1e-12);
    }
    axes.title = "What accuracy costs: " + problem;
    axes.x_label = "log10(wall time [s])";
    axes.y_label = problem == "drum_300"         ? "angle difference to the finest dt [deg]"
                   : problem == "wet_drum_angle" ? "angle difference to the finest dp [deg]"
                   : mm                          ? "slurry curve RMS distance to the finest dp [mm]"
                                                 : "error [%]";
    io::writeLinePlot(out_dir + "/pareto_" + problem + ".png", axes, {all, front});
  }
}

}  // namespace millsim::sim
