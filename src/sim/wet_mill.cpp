#include "sim/wet_mill.hpp"

#include <algorithm>
#include <array>
#include <cmath>
#include <cstdio>
#include <map>
#include <sstream>
#include <string>
#include <utility>
#include <vector>

#include "millsim/core/error.hpp"
#include "millsim/io/plot_png.hpp"
#include "millsim/vision/slurry_curve.hpp"
#include "sim/engine_factory.hpp"
#include "sim/sph_run.hpp"
#include "sph/eos.hpp"
#include "sph/geometry.hpp"
#include "sph/sph_kernels.hpp"

namespace millsim::sim {

namespace {

struct FillPoint {
  double x, y, z;
};

}  // namespace

WetMill::WetMill(const scene::Scene& sc, const RunOptions& options, const dem::DemHostState& balls, double phi,
                 double t)
    : m_scene(sc), m_phi0(phi), m_t0(t) {
  const scene::SphParams& p = sc.sph;
  if (p.dimension != 3)
    throw core::InputError(sc.source, lineOf(sc, "sph"), "<sph dimension=\"2\">: a wet mill is 3D (dimension=\"3\")");
  const double dp = p.dp, R = 0.5 * sc.drum.diameter, L = sc.drum.length;
  const double g = gravityNorm(sc);
  m_balls = balls.size();

  // Slurry: lattice points inside the drum, clear of walls, lifters and balls; the lowest
  // filling x V_drum / dp^3 of them (the pool a poured slurry forms).
  sph::DrumGeometry drum{R,
                         L,
                         sc.drum.lifters.count,
                         sc.drum.lifters.height,
                         sc.drum.lifters.width,
                         phi + 0.5 * std::acos(-1.0)};  // DrumMotion's phase0: a lifter on top at phi = 0
  // The lattice is indexed (i + n, j + n, k) so that each ball clears only the points of its own
  // bounding box: O(points + balls x box), not O(points x balls) (a 2 m mill has 1e7 points and
  // 3e4 balls). The points and their order are the same as a scan of every point would give.
  std::vector<FillPoint> candidates;
  const std::array<double, 3> origin = sph::cellCentredLattice(dp);  // the walls' and the shells' lattice too
  const int n = static_cast<int>(std::ceil(R / dp)), nz = sph::drumAxialLayers(L, dp);
  const std::size_t row = 2 * static_cast<std::size_t>(n);
  std::vector<int> index_of(row * row * static_cast<std::size_t>(std::max(nz, 0)), -1);
  for (int k = 0; k < nz; ++k)
    for (int j = -n; j < n; ++j)
      for (int i = -n; i < n; ++i) {
        const double x = sph::latticeCoord(origin[0], dp, i), y = sph::latticeCoord(origin[1], dp, j),
                     z = sph::latticeCoord(origin[2], dp, k);
        // The walls (addDrumWalls) are the points of this lattice with r >= R or inside a
        // lifter: the slurry takes every other point, dp from the first wall particle.
        if (std::hypot(x, y) >= R || sph::insideLifter(drum, x, y, 0.0)) continue;
        index_of[(static_cast<std::size_t>(k) * row + (j + n)) * row + (i + n)] = static_cast<int>(candidates.size());
        candidates.push_back({x, y, z});
      }
  std::vector<char> free(candidates.size(), 1);
  // Lattice indices whose point (index + 0.5) dp lies within [lo, hi], clipped to [first, last].
  auto span = [dp](double lo, double hi, int first, int last) {
    return std::make_pair(std::max(first, static_cast<int>(std::floor(lo / dp - 0.5))),
                          std::min(last, static_cast<int>(std::ceil(hi / dp - 0.5))));
  };
  // Each ball's shell is cut from this lattice too (below): the slurry starts where it ends.
  std::vector<sph::LatticeCut> cuts;
  cuts.reserve(m_balls);
  for (std::size_t b = 0; b < m_balls; ++b) {
    const double cx = balls.pos[3 * b], cy = balls.pos[3 * b + 1], cz = balls.pos[3 * b + 2];
    cuts.push_back(sph::latticeCut({cx, cy, cz}, balls.radius[b], dp, 3, origin));
    const double clear = cuts.back().radius;
    const auto [i0, i1] = span(cx - clear, cx + clear, -n, n - 1);
    const auto [j0, j1] = span(cy - clear, cy + clear, -n, n - 1);
    const auto [k0, k1] = span(cz - clear, cz + clear, 0, nz - 1);
    for (int k = k0; k <= k1; ++k)
      for (int j = j0; j <= j1; ++j)
        for (int i = i0; i <= i1; ++i) {
          const int c = index_of[(static_cast<std::size_t>(k) * row + (j + n)) * row + (i + n)];
          if (c < 0) continue;
          const double dx = candidates[c].x - cx, dy = candidates[c].y - cy, dz = candidates[c].z - cz;
          if (sph::insideRadius(dx, dy, dz, clear)) free[c] = 0;  // the shell's own test, below
        }
  }
  std::vector<FillPoint> fluid;
  for (std::size_t c = 0; c < candidates.size(); ++c)
    if (free[c]) fluid.push_back(candidates[c]);
  const double v_drum = std::acos(-1.0) * R * R * L;
  const std::size_t wanted = static_cast<std::size_t>(std::llround(sc.slurry.filling * v_drum / (dp * dp * dp)));
  if (wanted > fluid.size()) {
    std::ostringstream m;
    m << "<slurry filling=\"" << sc.slurry.filling << "\">: " << wanted << " slurry particles asked for, only "
      << fluid.size() << " fit between the balls and the walls at dp = " << dp << " m";
    throw core::InputError(sc.source, lineOf(sc, "slurry"), m.str());
  }
  std::stable_sort(fluid.begin(), fluid.end(), [](const FillPoint& a, const FillPoint& b) { return a.y < b.y; });
  fluid.resize(wanted);
  const double surface_y = fluid.empty() ? -R : fluid.back().y + 0.5 * dp;

  m_hswl = std::max(surface_y + R, dp);
  setupSolver();
  const int layers = boundaryLayers(sc, m_setup);

  sph::SphHostState st;
  for (const FillPoint& f : fluid) {
    st.pos.insert(st.pos.end(), {f.x, f.y, f.z});
    st.vel.insert(st.vel.end(), {0.0, 0.0, 0.0});
    st.rho.push_back(p.rho0);
    st.code.push_back(sph::kFluid);
  }
  m_fluid0 = static_cast<long long>(fluid.size());
  sph::addDrumWalls(st, drum, dp, layers, p.rho0);
  for (std::size_t b = 0; b < m_balls; ++b) {
    const std::array<double, 3> c{balls.pos[3 * b], balls.pos[3 * b + 1], balls.pos[3 * b + 2]};
    // The whole ball when it is at most `layers` deep (its cut can lie up to dp/2 beyond r).
    const int ball_layers = std::min(layers, static_cast<int>(std::ceil(balls.radius[b] / dp)) + 1);
    sph::addSphereShell(st, c, balls.radius[b], dp, 3, ball_layers, static_cast<int>(b), p.rho0, cuts[b]);
  }
  if (p.initial_density == "hydrostatic") sph::hydrostaticDensity(st, surface_y, g, p.rho0, m_setup.c0, p.gamma);
  m_particles = st.size();
  makeEngine(options);
  m_engine->setState(st);
  m_coupling = std::make_unique<coupling::SphDemCoupling>(m_balls);
  m_coupling->initialize(*m_engine, balls, motionAt(phi, 0.0));
}

// The solver's setup from the case and the still-water height (sets c0) of the pour.
void WetMill::setupSolver() {
  const double R = 0.5 * m_scene.drum.diameter, L = m_scene.drum.length;
  m_setup = sphSolverSetup(m_scene, m_hswl);
  const double wall = (boundaryLayers(m_scene, m_setup) + 2) * m_setup.dp;
  m_setup.domain_lo = {-R - wall, -R - wall, -wall};
  m_setup.domain_hi = {R + wall, R + wall, L + wall};
  m_setup.motion_center = {0, 0, 0};
}

void WetMill::makeEngine(const RunOptions& options) {
  // The same backend and precision as the balls' engine (engine_factory resolves --backend auto).
  m_engine = makeSphEngine(m_setup, options);
}

namespace {

// Checkpoint datasets of the wet mill (next to the DEM's): the SPH restart state and the slurry
// surface collected so far.
std::vector<double> flatten(const std::vector<sph::SphBodyLoad>& loads) {
  std::vector<double> v;
  for (const auto& l : loads)
    v.insert(v.end(), {l.force[0], l.force[1], l.force[2], l.torque[0], l.torque[1], l.torque[2]});
  return v;
}

std::vector<std::int64_t> toInts(const std::vector<int>& v) { return {v.begin(), v.end()}; }

}  // namespace

void WetMill::save(io::CheckpointData& cp) const {
  sph::SphRestartState s;
  m_engine->getRestartState(s);
  cp.reals["sph_pos"] = s.particles.pos;
  cp.reals["sph_vel"] = s.particles.vel;
  cp.reals["sph_rho"] = s.particles.rho;
  cp.ints["sph_code"] = toInts(s.particles.code);
  cp.ints["sph_body"] = toInts(s.particles.body);
  cp.reals["sph_offset"] = s.particles.offset;
  cp.reals["sph_ghost"] = s.particles.ghost;
  cp.reals["sph_pos0"] = s.pos0;
  cp.reals["sph_vel_m1"] = s.vel_m1;
  cp.reals["sph_rho_m1"] = s.rho_m1;
  cp.reals["sph_impulse"] = flatten(s.impulse);
  std::vector<double> surface;
  for (const auto& p : m_surface) surface.insert(surface.end(), {p.x_mm, p.y_mm, double(p.frame)});
  cp.reals["wet_surface"] = surface;
  cp.scalars["sph_step"] = double(s.step);
  cp.scalars["wet_steps"] = double(m_steps);
  cp.scalars["wet_frames"] = m_frames;
  cp.scalars["wet_fluid0"] = double(m_fluid0);
  cp.scalars["wet_phi0"] = m_phi0;
  cp.scalars["wet_t0"] = m_t0;
  cp.scalars["wet_hswl"] = m_hswl;
}

bool WetMill::inCheckpoint(const io::CheckpointData& cp) { return cp.reals.count("sph_pos") > 0; }

WetMill::WetMill(const scene::Scene& sc, const RunOptions& options, const io::CheckpointData& cp,
                 const dem::DemHostState& balls, double phi, double omega, const std::string& file)
    : m_scene(sc) {
  auto real = [&](const char* k) -> const std::vector<double>& {
    auto it = cp.reals.find(k);
    if (it == cp.reals.end()) throw core::InputError(file + ": checkpoint lacks the wet mill's '" + k + "'");
    return it->second;
  };
  auto ints = [&](const char* k) {
    auto it = cp.ints.find(k);
    if (it == cp.ints.end()) throw core::InputError(file + ": checkpoint lacks the wet mill's '" + k + "'");
    return std::vector<int>(it->second.begin(), it->second.end());
  };
  auto scalar = [&](const char* k) {
    auto it = cp.scalars.find(k);
    if (it == cp.scalars.end()) throw core::InputError(file + ": checkpoint lacks the wet mill's '" + k + "'");
    return it->second;
  };
  m_balls = balls.size();
  m_phi0 = scalar("wet_phi0");
  m_t0 = scalar("wet_t0");
  m_hswl = scalar("wet_hswl");
  m_fluid0 = std::llround(scalar("wet_fluid0"));
  m_steps = std::llround(scalar("wet_steps"));
  m_frames = static_cast<int>(std::lround(scalar("wet_frames")));
  const std::vector<double>& surface = real("wet_surface");
  for (std::size_t k = 0; k + 2 < surface.size(); k += 3)
    m_surface.push_back({surface[k], surface[k + 1], static_cast<int>(std::lround(surface[k + 2]))});
  setupSolver();
  sph::SphRestartState s;
  s.particles.pos = real("sph_pos");
  s.particles.vel = real("sph_vel");
  s.particles.rho = real("sph_rho");
  s.particles.code = ints("sph_code");
  s.particles.body = ints("sph_body");
  s.particles.offset = real("sph_offset");
  if (cp.reals.count("sph_ghost")) s.particles.ghost = cp.reals.at("sph_ghost");  // older checkpoints: none
  s.pos0 = real("sph_pos0");
  s.vel_m1 = real("sph_vel_m1");
  s.rho_m1 = real("sph_rho_m1");
  s.step = std::llround(scalar("sph_step"));
  const std::vector<double>& imp = real("sph_impulse");
  for (std::size_t k = 0; k + 5 < imp.size(); k += 6)
    s.impulse.push_back({{imp[k], imp[k + 1], imp[k + 2]}, {imp[k + 3], imp[k + 4], imp[k + 5]}});
  const std::size_t n = s.particles.rho.size();
  if (s.particles.pos.size() != 3 * n || s.particles.vel.size() != 3 * n || s.particles.code.size() != n)
    throw core::InputError(file + ": the wet mill's particle arrays in the checkpoint disagree in length");
  m_particles = n;
  makeEngine(options);
  m_engine->setRestartState(s);
  m_coupling = std::make_unique<coupling::SphDemCoupling>(m_balls);
  m_coupling->initialize(*m_engine, balls, motionAt(phi, omega));
}

void WetMill::advance(dem::DemEngine& dem, const DrumMotion& motion, double& t, double& phi, long long& dem_steps,
                      double dt_dem) {
  auto half = [&](double dt) {
    const double w = motion.omega(t + 0.5 * dt);
    return motionAt(phi + 0.5 * dt * w, w);
  };
  auto substeps = [&](double dt) {
    const int sub = std::max(1, static_cast<int>(std::ceil(dt / dt_dem - 1e-9)));
    const double h = dt / sub;
    for (int k = 0; k < sub; ++k) {
      motion.stepDem(dem, t, phi, h);
      ++dem_steps;
    }
    return motionAt(phi, motion.omega(t));
  };
  m_coupling->advance(*m_engine, dem, half, substeps);
  ++m_steps;
  if (double(m_engine->excludedCount()) > m_scene.sph.parts_out_max * double(m_fluid0)) {
    const sph::SphSums now = m_engine->sums();
    const long long excluded = now.excluded_density + now.excluded_domain;
    std::ostringstream m;
    m << "SPH-DEM: " << excluded << " of " << m_fluid0 << " slurry particles excluded by t = " << t << " s ("
      << now.excluded_density << " by density, " << now.excluded_domain
      << " outside the domain), more than sph.parts_out_max = " << m_scene.sph.parts_out_max
      << ": lower sph.cfl or raise sph.coefsound";
    throw core::SimulationError(m.str());
  }
}

void WetMill::captureSurface() {
  sph::SphHostState s;
  m_engine->getState(s);
  const double dp = m_setup.dp, z_mid = 0.5 * m_scene.drum.length, R = 0.5 * m_scene.drum.diameter;
  const int bins = static_cast<int>(std::ceil(2 * R / dp));
  std::vector<double> top(bins, -1e300);
  for (std::size_t i = 0; i < s.size(); ++i) {
    if (s.code[i] != sph::kFluid || std::abs(s.pos[3 * i + 2] - z_mid) > dp) continue;
    const int b = static_cast<int>(std::floor((s.pos[3 * i] + R) / dp));
    if (b >= 0 && b < bins) top[b] = std::max(top[b], s.pos[3 * i + 1]);
  }
  for (int b = 0; b < bins; ++b)
    if (top[b] > -1e299) m_surface.push_back({1000 * (-R + (b + 0.5) * dp), 1000 * top[b], m_frames});
  ++m_frames;
}

void WetMill::finish(const std::filesystem::path& out, RunSummary& summary, bool write) {
  summary.sph_particles = m_particles;
  const sph::SphSums now = m_engine->sums();
  summary.sph_excluded = now.excluded_density + now.excluded_domain;
  summary.slurry_kinetic = now.kinetic;
  summary.slurry_potential = now.potential;
  summary.sph_steps = m_steps;
  summary.slurry_frames = m_frames;
  // Per horizontal position: keep the frames' points between the median and Q3 (paper).
  std::map<long long, std::vector<double>> by_x;
  for (const auto& p : m_surface) by_x[std::llround(p.x_mm * 1000)].push_back(p.y_mm);
  std::vector<vision::SurfacePoint> kept;
  for (const auto& p : m_surface) {
    std::vector<double> ys = by_x[std::llround(p.x_mm * 1000)];
    std::sort(ys.begin(), ys.end());
    const double median = ys[ys.size() / 2], q3 = ys[(3 * ys.size()) / 4];
    if (p.y_mm >= median && p.y_mm <= q3) kept.push_back(p);
  }
  try {
    const vision::SlurryCurve curve = vision::fitSlurryCurve(kept, 3.0, 0.95);
    summary.slurry_valid = true;
    summary.slurry_coef = curve.fit.coef;
    m_curve_valid = true;
    m_curve = curve.fit.coef;
    m_x_min_mm = curve.x_min_mm;
    m_x_max_mm = curve.x_max_mm;
    if (write) {
      vision::writeSlurryCurveCsv((out / "slurry_curve.csv").string(), curve);
      vision::writeSurfacePointsCsv((out / "slurry_points.csv").string(), curve);
      // The band for the overlay, in metres.
      io::PlotCurve fit, low, high;
      fit.rgb = {200, 30, 30};
      low.rgb = high.rgb = {240, 150, 40};
      low.thickness = high.thickness = 1;
      for (double x = curve.x_min_mm; x <= curve.x_max_mm; x += 1.0) {
        const double y = curve.fit.value(x), w = curve.fit.halfWidth(x);
        fit.x.push_back(x / 1000), fit.y.push_back(y / 1000);
        low.x.push_back(x / 1000), low.y.push_back((y - w) / 1000);
        high.x.push_back(x / 1000), high.y.push_back((y + w) / 1000);
      }
      m_overlay_curves = {fit, low, high};
    }
  } catch (const std::exception& e) {
    summary.slurry_valid = false;
    summary.slurry_error = e.what();
  }
  if (write) writeOverlay(out / "slurry_overlay.png", summary);
}

void WetMill::writeOverlay(const std::filesystem::path& path, const RunSummary& summary) const {
  sph::SphHostState s;
  m_engine->getState(s);
  const double R = 0.5 * m_scene.drum.diameter, z_mid = 0.5 * m_scene.drum.length, dp = m_setup.dp;
  std::vector<double> x, y, v;
  std::vector<bool> gray;
  for (std::size_t i = 0; i < s.size(); ++i) {
    if (sph::isExcluded(s.code[i]) || std::abs(s.pos[3 * i + 2] - z_mid) > 1.5 * dp) continue;
    x.push_back(s.pos[3 * i]);
    y.push_back(s.pos[3 * i + 1]);
    v.push_back(s.code[i] == sph::kFluid ? -1.0 : 1.0);  // fluid blue
    gray.push_back(s.code[i] != sph::kFluid);
  }
  const double margin = R + 4 * dp;
  char title[200];
  std::snprintf(title, sizeof title, "%s: mid-plane slab, slurry curve %s", m_scene.name.c_str(),
                summary.slurry_valid ? "(red) with its 95% band (orange)" : "not measured");
  io::writeParticleSnapshot(path.string(), x, y, v, gray, 0.5 * dp, {-margin, margin, -margin, margin},
                            800 / (2 * margin), -1.0, 1.0, title, "", m_overlay_curves);
}

std::vector<std::string> WetMill::stages() const {
  std::vector<std::string> s{"sph_neighbour_build", "sph_pressure", "sph_interaction", "sph_" + m_setup.integrator,
                             "sph_dem_coupling"};
  if (m_setup.shifting) s.push_back("sph_shifting");
  return s;
}

}  // namespace millsim::sim
