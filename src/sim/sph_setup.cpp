#include "sim/sph_setup.hpp"

#include <algorithm>
#include <cctype>
#include <cmath>
#include <sstream>

#include "millsim/core/error.hpp"
#include "sph/geometry.hpp"
#include "sph/sph_kernels.hpp"

namespace millsim::sim {

double gravityNorm(const scene::Scene& sc) {
  return std::sqrt(sc.gravity[0] * sc.gravity[0] + sc.gravity[1] * sc.gravity[1] + sc.gravity[2] * sc.gravity[2]);
}

int lineOf(const scene::Scene& sc, const std::string& element) {
  const auto it = sc.element_lines.find(element);
  return it == sc.element_lines.end() ? 0 : it->second;
}

std::vector<Probe> parseProbes(const scene::Scene& scene) {
  std::vector<Probe> out;
  std::stringstream items(scene.probes.points);
  std::string item;
  auto fail = [&](const std::string& what) {
    throw core::InputError(scene.source, lineOf(scene, "probes"),
                           "<probes points=\"" + scene.probes.points + "\">: " + what);
  };
  while (std::getline(items, item, ';')) {
    item.erase(0, item.find_first_not_of(" \t\n"));
    item.erase(item.find_last_not_of(" \t\n") + 1);
    if (item.empty()) continue;
    const auto colon = item.find(':');
    if (colon == std::string::npos || colon == 0) fail("'" + item + "': expected name:x,y[,z]");
    Probe p;
    p.name = item.substr(0, colon);
    for (char c : p.name)
      if (!(std::isalnum(static_cast<unsigned char>(c)) || c == '_'))
        fail("probe name '" + p.name + "': use letters, digits and _ only");
    std::stringstream coords(item.substr(colon + 1));
    std::string c;
    int k = 0;
    while (std::getline(coords, c, ',')) {
      if (k >= 3) fail("'" + item + "': more than 3 coordinates");
      std::size_t used = 0;
      try {
        p.x[k] = std::stod(c, &used);
      } catch (const std::exception&) {
        used = 0;
      }
      if (used == 0 || c.find_first_not_of(" \t", used) != std::string::npos || !std::isfinite(p.x[k]))
        fail("'" + item + "': '" + c + "' is not a number");
      ++k;
    }
    if (k < 2) fail("'" + item + "': expected name:x,y[,z]");
    for (const Probe& q : out)
      if (q.name == p.name) fail("probe name '" + p.name + "' given twice");
    out.push_back(p);
  }
  return out;
}

sph::SphSetup sphSolverSetup(const scene::Scene& sc, double still_water_height) {
  const scene::SphParams& p = sc.sph;
  sph::SphSetup s;
  s.dimension = p.dimension;
  s.kernel = p.kernel;
  s.ddt = p.ddt;
  s.viscosity = p.viscosity;
  s.boundary = p.boundary;
  s.integrator = p.integrator;
  s.shifting = p.shifting == "full";
  s.dp = p.dp;
  s.h = p.coefh * p.dp * std::sqrt(double(p.dimension));
  const double hswl = p.hswl > 0 ? p.hswl : still_water_height;
  s.c0 = p.coefsound * std::sqrt(gravityNorm(sc) * hswl);
  if (!(s.c0 > 0))
    throw core::InputError(sc.source, lineOf(sc, "sph"),
                           "<sph>: the speed of sound is 0 (no gravity or no fluid height): give sph.hswl > 0");
  s.rho0 = p.rho0;
  s.gamma = p.gamma;
  s.alpha = p.alpha;
  s.visco_bound_factor = p.visco_bound_factor;
  s.wall_velocity = p.wall_velocity;
  s.nu = p.nu;
  s.ddt_value = p.ddt_value;
  s.shift_coef = p.shift_coef;
  s.shift_tfs = p.shift_tfs > 0 ? p.shift_tfs : (p.dimension == 2 ? 1.5 : 2.75);
  s.verlet_steps = p.verlet_steps;
  s.cfl = p.cfl;
  s.fixed_dt = sc.time.dt_mode == "fixed";
  s.dt_fixed = sc.time.dt_fixed;
  s.rho_min = p.rhop_out_min;
  s.rho_max = p.rhop_out_max;
  s.gravity = sc.gravity;
  return s;
}

int boundaryLayers(const scene::Scene& sc, const sph::SphSetup& s) {
  return sc.sph.boundary_layers > 0 ? sc.sph.boundary_layers : static_cast<int>(std::ceil(2 * s.h / s.dp - 1e-9));
}

sph::SphSetup sphSetupOf(const scene::Scene& sc) {
  sph::SphSetup s = sphSolverSetup(sc, sc.fluid.y_max - sc.fluid.y_min);
  const scene::SphParams& p = sc.sph;
  // Domain: the tank (or the fluid) and its walls, with room above an open top for splashes;
  // a rotating tank sweeps the circle through its corners.
  const int layers = boundaryLayers(sc, s);
  std::array<double, 3> lo, hi;
  if (sc.has_tank) {
    lo = {sc.tank.x_min, sc.tank.y_min, sc.tank.z_min};
    hi = {sc.tank.x_max, sc.tank.y_max, sc.tank.z_max};
  } else {
    lo = {sc.fluid.x_min, sc.fluid.y_min, sc.fluid.z_min};
    hi = {sc.fluid.x_max, sc.fluid.y_max, sc.fluid.z_max};
  }
  const double wall = (layers + 2) * p.dp;
  s.motion_center = {0.5 * (lo[0] + hi[0]), 0.5 * (lo[1] + hi[1]), 0.5 * (lo[2] + hi[2])};
  if (sc.has_tank && sc.tank.rotation_rpm != 0) {
    const double r = 0.5 * std::hypot(hi[0] - lo[0], hi[1] - lo[1]) + wall;
    for (int a = 0; a < 2; ++a) {
      lo[a] = s.motion_center[a] - r;
      hi[a] = s.motion_center[a] + r;
    }
  } else {
    for (int a = 0; a < 3; ++a) {
      lo[a] -= wall;
      hi[a] += wall;
    }
    if (!(sc.has_tank && sc.tank.closed)) hi[1] += hi[1] - lo[1];
  }
  lo[2] = std::min(lo[2], sc.fluid.z_min - wall);
  hi[2] = std::max(hi[2], sc.fluid.z_max + wall);
  s.domain_lo = lo;
  s.domain_hi = hi;
  return s;
}

sph::SphHostState sphParticlesOf(const scene::Scene& sc, const sph::SphSetup& s) {
  sph::SphHostState st;
  const int dim = sc.sph.dimension;
  sph::fillFluidBox(st, {{sc.fluid.x_min, sc.fluid.y_min, sc.fluid.z_min}, {sc.fluid.x_max, sc.fluid.y_max, sc.fluid.z_max}},
                    s.dp, dim, s.rho0);
  if (st.size() == 0)
    throw core::InputError(sc.source, lineOf(sc, "fluid"), "<fluid>: the box holds no particle at dp = " +
                                                               std::to_string(s.dp) + " m (is it smaller than dp?)");
  if (sc.has_tank) {
    const int layers = boundaryLayers(sc, s);
    const int code = sc.tank.rotation_rpm != 0 ? sph::kBoundMoving : sph::kBoundFixed;
    sph::addTankWalls(st, {{sc.tank.x_min, sc.tank.y_min, sc.tank.z_min}, {sc.tank.x_max, sc.tank.y_max, sc.tank.z_max}},
                      s.dp, dim, layers, sc.tank.closed, code, s.rho0);
  }
  if (sc.sph.initial_density == "hydrostatic")
    sph::hydrostaticDensity(st, sc.fluid.y_max, gravityNorm(sc), s.rho0, s.c0, s.gamma);
  return st;
}

}  // namespace millsim::sim
