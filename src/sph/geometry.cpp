#include "sph/geometry.hpp"

#include <algorithm>
#include <array>
#include <cmath>
#include <utility>
#include <vector>

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
        add(s, latticeCoord(box.lo[0] + 0.5 * dp, dp, i), latticeCoord(box.lo[1] + 0.5 * dp, dp, j),
            dim == 2 ? 0.0 : latticeCoord(box.lo[2] + 0.5 * dp, dp, k), kFluid, rho0);
}

void addTankWalls(SphHostState& s, const Box& box, double dp, int dim, int layers, bool closed_top, int code,
                  double rho0) {
  const int nx = rows(box.lo[0], box.hi[0], dp), ny = rows(box.lo[1], box.hi[1], dp);
  const int nz = dim == 2 ? 1 : rows(box.lo[2], box.hi[2], dp);
  // Index ranges including the wall layers: i in [-layers, nx + layers), same for j, k.
  const int L = layers;
  auto coord = [&](int axis, int i) { return latticeCoord(box.lo[axis] + 0.5 * dp, dp, i); };
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

int drumAxialLayers(double length, double dp) {
  // (k + 1/2) dp < L for k < L / dp - 1/2; the 1e-9 keeps a length of a whole number of dp
  // (L / dp = 30 up to rounding) at that number, its last layer dp/2 inside the plate.
  return std::max(0, static_cast<int>(std::ceil(length / dp - 0.5 - 1e-9)));
}

void addDrumWalls(SphHostState& s, const DrumGeometry& d, double dp, int layers, double rho0) {
  const double outer = d.radius + layers * dp;
  const int n = static_cast<int>(std::ceil(outer / dp));
  const int nz = drumAxialLayers(d.length, dp);
  const std::array<double, 3> o = cellCentredLattice(dp);  // the fluid's (the wet mill's fill)
  for (int k = -layers; k < nz + layers; ++k)
    for (int j = -n; j < n; ++j)
      for (int i = -n; i < n; ++i) {
        const double x = latticeCoord(o[0], dp, i), y = latticeCoord(o[1], dp, j), z = latticeCoord(o[2], dp, k);
        const double r = std::hypot(x, y);
        if (r >= outer) continue;
        const bool plate = k < 0 || k >= nz;
        const bool shell = r >= d.radius;
        if (plate || shell || insideLifter(d, x, y, 0.0)) add(s, x, y, z, kBoundMoving, rho0, drumGhost(d, x, y, z));
      }
}

double latticeCutRadius(const std::array<double, 3>& c, double r, double dp, int dim,
                        const std::array<double, 3>& lattice_origin) {
  std::array<long, 3> m0{};
  for (int q = 0; q < 3; ++q) m0[q] = std::lround((c[q] - lattice_origin[q]) / dp);
  // Squared distances of the points within r + dp: the best cut lies within dp of r (a shell of
  // points at r < d < r + dp holds ~4 pi r^2 / dp^2 points, more than any miscount of the cut at r).
  const int n = static_cast<int>(std::ceil(r / dp)) + 2;
  const double reach2 = (r + dp) * (r + dp);
  std::vector<double> d2;
  for (int k = dim == 2 ? 0 : -n; k <= (dim == 2 ? 0 : n); ++k)
    for (int j = -n; j <= n; ++j)
      for (int i = -n; i <= n; ++i) {
        const double dx = latticeCoord(lattice_origin[0], dp, m0[0] + i) - c[0];
        const double dy = latticeCoord(lattice_origin[1], dp, m0[1] + j) - c[1];
        const double dz = dim == 2 ? 0.0 : latticeCoord(lattice_origin[2], dp, m0[2] + k) - c[2];
        const double q = dx * dx + dy * dy + dz * dz;
        if (q < reach2) d2.push_back(q);
      }
  std::sort(d2.begin(), d2.end());
  const double pi = std::acos(-1.0);
  const double target = dim == 2 ? pi * r * r / (dp * dp) : 4.0 / 3.0 * pi * r * r * r / (dp * dp * dp);
  // Cut after point k - 1 (k points inside) where the distances step: points closer than 1e-9 dp
  // in squared distance are one distance (symmetric points, up to rounding).
  const double tie = 1e-9 * dp * dp;
  std::size_t best = 0;
  double best_miss = target;  // the empty cut
  for (std::size_t k = 1; k < d2.size(); ++k) {
    if (d2[k] - d2[k - 1] <= tie) continue;
    const double miss = std::abs(static_cast<double>(k) - target);
    if (miss < best_miss) best = k, best_miss = miss;
  }
  if (best == 0) return 0.5 * std::sqrt(d2.empty() ? r * r : d2.front());
  return std::sqrt(0.5 * (d2[best - 1] + d2[best]));
}

void addSphereShell(SphHostState& s, const std::array<double, 3>& c, double r, double dp, int dim, int layers, int body,
                    double rho0, const std::optional<LatticeCut>& lattice_cut) {
  // Body data for the particles already there (walls, fluid): none.
  s.body.resize(s.size(), -1);
  s.offset.resize(3 * s.size(), 0.0);
  // Lattice points latticeCoord(o, dp, m0 + i), i in [-n, n], per axis: o = c and m0 = 0 (a point
  // at the centre), or o = the given origin and m0 the index nearest c, so that the range covers
  // the sphere either way and a point has the fluid lattice's coordinates bit for bit.
  std::array<double, 3> o = c;
  std::array<long, 3> m0{0, 0, 0};
  // Own lattice: a point on the surface (r a whole number of steps, e.g. 10 dp: (6, 8) dp) is
  // outside, whichever way rounding takes its distance. The fluid's lattice: cut between points.
  double cut = r - 1e-9 * dp;
  if (lattice_cut) {
    for (int q = 0; q < 3; ++q) {
      o[q] = lattice_cut->origin[q];
      m0[q] = std::lround((c[q] - o[q]) / dp);
    }
    cut = lattice_cut->radius;
  }
  const int n = static_cast<int>(std::ceil(cut / dp)) + 1;
  const double inner = cut - layers * dp;
  for (int k = dim == 2 ? 0 : -n; k <= (dim == 2 ? 0 : n); ++k)
    for (int j = -n; j <= n; ++j)
      for (int i = -n; i <= n; ++i) {
        const double x = latticeCoord(o[0], dp, m0[0] + i), y = latticeCoord(o[1], dp, m0[1] + j);
        const double z = dim == 2 ? 0.0 : latticeCoord(o[2], dp, m0[2] + k);
        const double dx = x - c[0], dy = y - c[1], dz = dim == 2 ? 0.0 : z - c[2];
        if (!insideRadius(dx, dy, dz, cut) || (inner > 0 && insideRadius(dx, dy, dz, inner))) continue;
        const double d = std::sqrt(dx * dx + dy * dy + dz * dz);
        // Ghost: radially across the surface r.
        const double out = d > 0 ? 2 * (r - d) / d : 0.0;
        add(s, x, y, z, kBoundBody, rho0, {out * dx, out * dy, out * dz});
        s.body.push_back(body);
        s.offset.insert(s.offset.end(), {dx, dy, dz});
      }
}

void carveFluid(SphHostState& s, const std::array<double, 3>& c, double clearance) {
  SphHostState out;
  const bool bodies = s.body.size() == s.size();
  for (std::size_t i = 0; i < s.size(); ++i) {
    const double dx = s.pos[3 * i] - c[0], dy = s.pos[3 * i + 1] - c[1], dz = s.pos[3 * i + 2] - c[2];
    if (s.code[i] == kFluid && insideRadius(dx, dy, dz, clearance)) continue;
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
