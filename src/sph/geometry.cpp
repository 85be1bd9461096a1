#include "sph/geometry.hpp"

#include <algorithm>
#include <cmath>
#include <utility>

#include "sph/sph_kernels.hpp"

namespace millsim::sph {
namespace {

// Lattice points c0 + (i + 1/2) dp covering [a, b) (rounded so a box of k dp holds k rows).
int rows(double a, double b, double dp) { return std::max(0, static_cast<int>(std::floor((b - a) / dp + 1e-9))); }

void add(SphHostState& s, double x, double y, double z, int code, double rho) {
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
        add(s, coord(0, i), coord(1, j), dim == 2 ? 0.0 : coord(2, k), code, rho0);
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
        if (plate || shell || insideLifter(d, x, y, 0.0)) add(s, x, y, z, kBoundMoving, rho0);
      }
}

void addSphereShell(SphHostState& s, const std::array<double, 3>& c, double r, double dp, int dim, int layers, int body,
                    double rho0) {
  // Body data for the particles already there (walls, fluid): none.
  s.body.resize(s.size(), -1);
  s.offset.resize(3 * s.size(), 0.0);
  const int n = static_cast<int>(std::ceil(r / dp)) + 1;
  const double inner = r - layers * dp;
  for (int k = dim == 2 ? 0 : -n; k <= (dim == 2 ? 0 : n); ++k)
    for (int j = -n; j <= n; ++j)
      for (int i = -n; i <= n; ++i) {
        // A lattice with a point at the centre: the shell is symmetric about it.
        const double dx = i * dp, dy = j * dp, dz = k * dp;
        const double d = std::sqrt(dx * dx + dy * dy + dz * dz);
        if (d >= r || d < inner) continue;
        add(s, c[0] + dx, c[1] + dy, dim == 2 ? 0.0 : c[2] + dz, kBoundBody, rho0);
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
