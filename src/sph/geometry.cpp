#include "sph/geometry.hpp"

#include <algorithm>
#include <array>
#include <cmath>
#include <utility>

#include "sph/sph_kernels.hpp"

namespace millsim::sph {
namespace {

// Lattice points c0 + (i + 1/2) dp covering [a, b) (rounded so a box of k dp holds k rows).
int rows(double a, double b, double dp) { return std::max(0, static_cast<int>(std::floor((b - a) / dp + 1e-9))); }

// ghost: the particle's mDBC ghost offset (its mirror image across the wall surface, minus the
// particle); zero for fluid and for walls without one. The state's ghost array is created with
// the first non-zero offset and then kept one entry per particle.
void add(SphHostState& s, double x, double y, double z, int code, double rho,
         const std::array<double, 3>& ghost = {0.0, 0.0, 0.0}) {
  if (!s.ghost.empty() || ghost[0] != 0 || ghost[1] != 0 || ghost[2] != 0) {
    s.ghost.resize(3 * s.size(), 0.0);  // zeros for the particles before the first ghost
    s.ghost.insert(s.ghost.end(), ghost.begin(), ghost.end());
  }
  s.pos.insert(s.pos.end(), {x, y, z});
  s.vel.insert(s.vel.end(), {0.0, 0.0, 0.0});
  s.rho.push_back(rho);
  s.code.push_back(code);
  // Keep the body arrays (when a case has bodies) one entry per particle.
  if (!s.body.empty() && code != kBoundBody) {
    s.body.push_back(-1);
    s.offset.insert(s.offset.end(), {0.0, 0.0, 0.0});
  }
}

}  // namespace

void fillFluidBox(SphHostState& s, const Box& box, double dp, int dim, double rho0) {
  const int nx = rows(box.lo[0], box.hi[0], dp), ny = rows(box.lo[1], box.hi[1], dp);
  const int nz = dim == 2 ? 1 : rows(box.lo[2], box.hi[2], dp);
  for (int k = 0; k < nz; ++k)
    for (int j = 0; j < ny; ++j)
      for (int i = 0; i < nx; ++i)
        add(s, box.lo[0] + (i + 0.5) * dp, box.lo[1] + (j + 0.5) * dp, dim == 2 ? 0.0 : box.lo[2] + (k + 0.5) * dp,
            kFluid, rho0);
}

void addTankWalls(SphHostState& s, const Box& box, double dp, int dim, int layers, bool closed_top, int code,
                  double rho0) {
  const int nx = rows(box.lo[0], box.hi[0], dp), ny = rows(box.lo[1], box.hi[1], dp);
  const int nz = dim == 2 ? 1 : rows(box.lo[2], box.hi[2], dp);
  // Index ranges including the wall layers: i in [-layers, nx + layers), same for j, k.
  const int L = layers;
  auto coord = [&](int axis, int i) { return box.lo[axis] + (i + 0.5) * dp; };
  const int k0 = dim == 2 ? 0 : -L, k1 = dim == 2 ? 1 : nz + L;
  const int j1 = closed_top ? ny + L : ny;
  for (int k = k0; k < k1; ++k)
    for (int j = -L; j < j1; ++j)
      for (int i = -L; i < nx + L; ++i) {
        const bool inside_x = i >= 0 && i < nx, inside_y = j >= 0 && j < ny, inside_z = dim == 2 || (k >= 0 && k < nz);
        if (inside_x && inside_y && inside_z) continue;  // the tank's interior
        // Ghost node: the mirror image through the nearest point of the box (faces, edges, corners).
        const std::array<double, 3> p{coord(0, i), coord(1, j), dim == 2 ? 0.0 : coord(2, k)};
        std::array<double, 3> g{};
        for (int a = 0; a < dim; ++a) g[a] = 2 * (std::clamp(p[a], box.lo[a], box.hi[a]) - p[a]);
        add(s, p[0], p[1], p[2], code, rho0, g);
      }
}

bool insideLifter(const DrumGeometry& d, double x, double y, double clearance) {
  const double two_pi = 2 * std::acos(-1.0);
  for (int k = 0; k < d.lifters; ++k) {
    const double a = d.first_angle + k * two_pi / d.lifters;
    const double u = x * std::cos(a) + y * std::sin(a), v = -x * std::sin(a) + y * std::cos(a);
    if (u >= d.radius - d.lifter_height - clearance && std::abs(v) <= 0.5 * d.lifter_width + clearance) return true;
  }
  return false;
}

std::array<double, 3> drumGhost(const DrumGeometry& d, double x, double y, double z) {
  std::array<double, 3> g{};
  // End plates: mirrored across z = 0 and z = L.
  if (z < 0) g[2] = -2 * z;
  if (z > d.length) g[2] = 2 * (d.length - z);
  const double r = std::hypot(x, y);
  if (r >= d.radius) {  // mantle: radially across r = R
    g[0] = 2 * (d.radius - r) * x / r;
    g[1] = 2 * (d.radius - r) * y / r;
    return g;
  }
  if (z < 0 || z > d.length) return g;
  // Inside a lifter: across its nearest face (top u = R - h or a side v = +-w/2).
  const double two_pi = 2 * std::acos(-1.0);
  for (int k = 0; k < d.lifters; ++k) {
    const double a = d.first_angle + k * two_pi / d.lifters, ca = std::cos(a), sa = std::sin(a);
    const double u = x * ca + y * sa, v = -x * sa + y * ca, hw = 0.5 * d.lifter_width;
    if (u < d.radius - d.lifter_height || std::abs(v) > hw) continue;
    const double to_top = u - (d.radius - d.lifter_height), to_side = hw - std::abs(v);
    if (to_top <= to_side) {
      g[0] = -2 * to_top * ca;
      g[1] = -2 * to_top * sa;
    } else {
      const double sv = v >= 0 ? 1.0 : -1.0;  // out through the side v = sv hw, along sv e_t
      g[0] = 2 * to_side * sv * -sa;
      g[1] = 2 * to_side * sv * ca;
    }
    return g;
  }
  return g;
}

void addDrumWalls(SphHostState& s, const DrumGeometry& d, double dp, int layers, double rho0) {
  const double outer = d.radius + layers * dp;
  const int n = static_cast<int>(std::ceil(outer / dp));
  const int nz0 = -layers, nz1 = static_cast<int>(std::floor(d.length / dp + 1e-9)) + layers;
  for (int k = nz0; k < nz1; ++k)
    for (int j = -n; j < n; ++j)
      for (int i = -n; i < n; ++i) {
        const double x = (i + 0.5) * dp, y = (j + 0.5) * dp, z = (k + 0.5) * dp;
        const double r = std::hypot(x, y);
        if (r >= outer) continue;
        const bool plate = z < 0 || z > d.length;
        const bool shell = r >= d.radius;
        if (plate || shell || insideLifter(d, x, y, 0.0)) add(s, x, y, z, kBoundMoving, rho0, drumGhost(d, x, y, z));
      }
}

void addSphereShell(SphHostState& s, const std::array<double, 3>& c, double r, double dp, int dim, int layers, int body,
                    double rho0, const std::optional<std::array<double, 3>>& lattice_origin) {
  // Body data for the particles already there (walls, fluid): none.
  s.body.resize(s.size(), -1);
  s.offset.resize(3 * s.size(), 0.0);
  // Lattice points o + (i, j, k) dp, o = c (a point at the centre) or the given origin moved by
  // whole steps next to c, so that i, j, k in [-n, n] cover the sphere either way.
  std::array<double, 3> o = c;
  if (lattice_origin)
    for (int q = 0; q < 3; ++q) o[q] = (*lattice_origin)[q] + std::round((c[q] - (*lattice_origin)[q]) / dp) * dp;
  const int n = static_cast<int>(std::ceil(r / dp)) + 1;
  const double inner = r - layers * dp;
  for (int k = dim == 2 ? 0 : -n; k <= (dim == 2 ? 0 : n); ++k)
    for (int j = -n; j <= n; ++j)
      for (int i = -n; i <= n; ++i) {
        const double dx = o[0] + i * dp - c[0], dy = o[1] + j * dp - c[1], dz = dim == 2 ? 0.0 : o[2] + k * dp - c[2];
        const double d = std::sqrt(dx * dx + dy * dy + dz * dz);
        if (d >= r || d < inner) continue;
        // Ghost: radially across the surface r.
        const double out = d > 0 ? 2 * (r - d) / d : 0.0;
        add(s, c[0] + dx, c[1] + dy, dim == 2 ? 0.0 : c[2] + dz, kBoundBody, rho0, {out * dx, out * dy, out * dz});
        s.body.push_back(body);
        s.offset.insert(s.offset.end(), {dx, dy, dz});
      }
}

void carveFluid(SphHostState& s, const std::array<double, 3>& c, double clearance) {
  SphHostState out;
  const bool bodies = s.body.size() == s.size();
  for (std::size_t i = 0; i < s.size(); ++i) {
    const double dx = s.pos[3 * i] - c[0], dy = s.pos[3 * i + 1] - c[1], dz = s.pos[3 * i + 2] - c[2];
    if (s.code[i] == kFluid && dx * dx + dy * dy + dz * dz < clearance * clearance) continue;
    out.pos.insert(out.pos.end(), {s.pos[3 * i], s.pos[3 * i + 1], s.pos[3 * i + 2]});
    out.vel.insert(out.vel.end(), {s.vel[3 * i], s.vel[3 * i + 1], s.vel[3 * i + 2]});
    out.rho.push_back(s.rho[i]);
    out.code.push_back(s.code[i]);
    if (s.ghost.size() == 3 * s.size())
      out.ghost.insert(out.ghost.end(), {s.ghost[3 * i], s.ghost[3 * i + 1], s.ghost[3 * i + 2]});
    if (bodies) {
      out.body.push_back(s.body[i]);
      out.offset.insert(out.offset.end(), {s.offset[3 * i], s.offset[3 * i + 1], s.offset[3 * i + 2]});
    }
  }
  s = std::move(out);
}

void hydrostaticDensity(SphHostState& s, double surface_y, double g, double rho0, double c0, double gamma,
                        int up_axis) {
  const double b = c0 * c0 * rho0 / gamma;
  for (std::size_t i = 0; i < s.size(); ++i) {
    const double depth = surface_y - s.pos[3 * i + up_axis];
    s.rho[i] = depth > 0 ? rho0 * std::pow(1.0 + rho0 * g * depth / b, 1.0 / gamma) : rho0;
  }
}

}  // namespace millsim::sph
