#include "sph/geometry.hpp"

#include <algorithm>
#include <cmath>

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

void hydrostaticDensity(SphHostState& s, double surface_y, double g, double rho0, double c0, double gamma) {
  const double b = c0 * c0 * rho0 / gamma;
  for (std::size_t i = 0; i < s.size(); ++i) {
    const double depth = surface_y - s.pos[3 * i + 1];
    s.rho[i] = depth > 0 ? rho0 * std::pow(1.0 + rho0 * g * depth / b, 1.0 / gamma) : rho0;
  }
}

}  // namespace millsim::sph
