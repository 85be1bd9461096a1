#pragma once
// Modified dynamic boundary conditions (mDBC: English, Dominguez, Vacondio, Crespo, Stansby,
// Lind, Chiapponi & Gomez-Gesteira 2022, Comput. Part. Mech. 9, 911-925; DualSPHysics 5's
// alternative to DBC). With DBC a wall particle's density evolves by the continuity equation,
// and the wall holds the fluid about a spacing off its surface (docs/validation.md: the dam
// break's toe slides on a cushion 1.2 dp thick). With mDBC each wall particle b has a ghost node
// x_g = x_b + g_b, its mirror image across the wall surface (g from the geometry: sph/geometry.cpp),
// and takes its density from the fluid around the ghost node, by a first-order consistent
// interpolation (exact for a linear density field, whatever the particle layout):
//
//   [ sum V_j W_gj          sum V_j W_gj (x_j - x_g)^T       ] [ rho_g      ]   [ sum m_j W_gj     ]
//   [ sum V_j grad W_gj     sum V_j grad W_gj (x_j - x_g)^T  ] [ grad rho_g ] = [ sum m_j grad W_gj ]
//
// (V_j = m_j / rho_j, grad W_gj = grad_g W(x_g - x_j), over the fluid within 2h of x_g), then
//   rho_b = rho_g + grad rho_g . (x_b - x_g) = rho_g - grad rho_g . g_b.
// Where the matrix is nearly singular (|det| < 1e-3, DualSPHysics's limit; few fluid
// neighbours, e.g. at a free surface) the Shepard value sum m W / sum V W is taken instead;
// with no fluid near the ghost the wall stays at rho0. A wall never goes below rho0 (no
// suction: a wall below the reference density would pull the fluid onto itself).
// The ghost offsets of moving walls turn with them (rotation about z); body shells are spheres,
// their offsets fixed in the lab frame (as the shell offsets are). A zero offset: plain DBC for
// that particle (its density from continuity).
#include <cmath>

#include "millsim/core/hd.hpp"
#include "millsim/core/vec3.hpp"
#include "millsim/neighbors/cell_list.hpp"
#include "sph/sph_pair.hpp"

namespace millsim::sph {

using core::Vec3;

// Solves a x_m = b_m for a small dense N x N system and M right-hand sides by Gaussian
// elimination with partial pivoting (a and b are overwritten). Returns false, leaving x
// untouched, when |det a| < det_limit.
template <class T, int N, int M>
MILLSIM_HD bool solveSmallMulti(T (&a)[N][N], T (&b)[M][N], T (&x)[M][N], T det_limit) {
  auto mag = [](T v) { return v < T(0) ? -v : v; };
  T det = T(1);
  for (int c = 0; c < N; ++c) {
    int p = c;
    for (int r = c + 1; r < N; ++r)
      if (mag(a[r][c]) > mag(a[p][c])) p = r;
    if (p != c) {
      for (int k = 0; k < N; ++k) {
        const T t = a[c][k];
        a[c][k] = a[p][k];
        a[p][k] = t;
      }
      for (int m = 0; m < M; ++m) {
        const T t = b[m][c];
        b[m][c] = b[m][p];
        b[m][p] = t;
      }
      det = -det;
    }
    det *= a[c][c];
    if (a[c][c] == T(0)) return false;
    for (int r = c + 1; r < N; ++r) {
      const T f = a[r][c] / a[c][c];
      for (int k = c; k < N; ++k) a[r][k] -= f * a[c][k];
      for (int m = 0; m < M; ++m) b[m][r] -= f * b[m][c];
    }
  }
  if (!(mag(det) >= det_limit)) return false;
  for (int m = 0; m < M; ++m)
    for (int r = N - 1; r >= 0; --r) {
      T s = b[m][r];
      for (int k = r + 1; k < N; ++k) s -= a[r][k] * x[m][k];
      x[m][r] = s / a[r][r];
    }
  return true;
}

// One right-hand side.
template <class T, int N>
MILLSIM_HD bool solveSmall(T (&a)[N][N], T (&b)[N], T (&x)[N], T det_limit) {
  T bm[1][N], xm[1][N];
  for (int k = 0; k < N; ++k) bm[0][k] = b[k];
  if (!solveSmallMulti<T, N, 1>(a, bm, xm, det_limit)) return false;
  for (int k = 0; k < N; ++k) x[k] = xm[0][k];
  return true;
}

// DualSPHysics's determinant limit for the mDBC correction (dimensionless: the matrix rows are
// a kernel sum and kernel-gradient moments, each O(1) for a full support).
inline constexpr double kMdbcDetLimit = 1e-3;

// Density of each wall particle from the fluid around its ghost node. Run over the wall slots
// [first, first + count) after the cell sort; reads fluid densities, writes wall ones.
// kNoSlip (wall_velocity = no_slip_ghost): the same solve, with the fluid velocity as three
// more right-hand sides, gives the velocity v_g at the ghost node, and the wall particle enters
// the viscous terms with 2 v_w - v_g: the mirror of the fluid's profile through the wall
// surface, which for a linear shear profile is that profile continued into the wall, exactly,
// at every layer. (Adami's Shepard mean around the wall particle itself, WallNoSlipVelocity,
// gives every layer about the velocity of the first fluid row: the deeper layers see a weaker
// shear than the real one.)
template <class T, class Kernel, int Dim, bool kNoSlip = false>
struct MdbcDensity {
  neighbors::CellListView<T> fluid_cells;
  const Vec3<T>* pos;
  const int* code;
  const Vec3<T>* ghost;  // x_g - x_b at the start (moving walls: before their rotation)
  Kernel kernel;
  T support2, mass, rho0;
  T cos_t, sin_t;  // rotation of the moving walls since the start
  int first;
  T* rho;
  const Vec3<T>* vel = nullptr;  // kNoSlip: the particles' velocities (walls: the wall's)
  Vec3<T>* visc_vel = nullptr;   // kNoSlip: the walls' velocity in the viscous terms
  // kNoSlip: the turning of the moving walls (about z) and of the bodies, for the wall's velocity
  // at the surface point x_b + g/2 rather than at the particle (body: nullptr without bodies).
  T omega_z = T(0);
  const int* body = nullptr;
  const Vec3<T>* body_omega = nullptr;
  MILLSIM_HD void operator()(int k) const {
    const int b = first + k;
    const int c = code[b];
    if (c == kFluid || isExcluded(c)) return;
    Vec3<T> g = ghost[b];
    if (g.x == T(0) && g.y == T(0) && g.z == T(0)) return;
    if (c == kBoundMoving) g = {cos_t * g.x - sin_t * g.y, sin_t * g.x + cos_t * g.y, g.z};
    const Vec3<T> xg = pos[b] + g;
    constexpr int N = Dim + 1;
    constexpr int M = kNoSlip ? 1 + Dim : 1;  // density, then the velocity's components
    T a[N][N] = {};
    T rhs[M][N] = {};
    fluid_cells.forEachWithin(xg, support2, pos, [&](int j, Vec3<T> d, T r2) {
      // d = x_g - x_j
      const T r = std::sqrt(r2);
      const T w = kernel.w(r), fac = kernel.fac(r);
      const T vol = mass / rho[j];
      const T e[3] = {-d.x, -d.y, -d.z};  // x_j - x_g
      const T gw[3] = {fac * d.x, fac * d.y, fac * d.z};
      T f[M];
      f[0] = mass;
      if constexpr (kNoSlip) {
        const T v[3] = {vel[j].x, vel[j].y, vel[j].z};
        for (int q = 0; q < Dim; ++q) f[q + 1] = vol * v[q];
      }
      a[0][0] += vol * w;
      for (int m = 0; m < M; ++m) rhs[m][0] += f[m] * w;
      for (int q = 0; q < Dim; ++q) {
        a[0][q + 1] += vol * w * e[q];
        a[q + 1][0] += vol * gw[q];
        for (int m = 0; m < M; ++m) rhs[m][q + 1] += f[m] * gw[q];
        for (int s = 0; s < Dim; ++s) a[q + 1][s + 1] += vol * gw[q] * e[s];
      }
    });
    if (!(a[0][0] > T(0))) {
      rho[b] = rho0;
      if constexpr (kNoSlip) visc_vel[b] = vel[b];
      return;
    }
    // Shepard values, kept where the matrix is nearly singular.
    T value[M];
    for (int m = 0; m < M; ++m) value[m] = rhs[m][0] / a[0][0];
    T x[M][N];
    if (solveSmallMulti<T, N, M>(a, rhs, x, T(kMdbcDetLimit))) {
      const T gv[3] = {g.x, g.y, g.z};
      value[0] = x[0][0];
      for (int q = 0; q < Dim; ++q) value[0] -= x[0][q + 1] * gv[q];
      for (int m = 1; m < M; ++m) value[m] = x[m][0];  // the velocity at the ghost node
    }
    rho[b] = value[0] > rho0 ? value[0] : rho0;
    if constexpr (kNoSlip) {
      const Vec3<T> vg = {value[1], value[2], Dim == 3 ? value[M - 1] : T(0)};
      // The wall's velocity where the mirror plane is, x_b + g/2: with a turning wall the
      // particle's own (a layer deeper) would over-turn the mirrored profile by omega |g|; a
      // fluid turning with the wall is then held exactly (a linear field again).
      Vec3<T> w = vel[b];
      if (c == kBoundMoving) w += (T(0.5) * omega_z) * Vec3<T>{-g.y, g.x, T(0)};
      if (c == kBoundBody && body && body[b] >= 0) w += core::cross(body_omega[body[b]], T(0.5) * g);
      visc_vel[b] = T(2) * w - vg;
    }
  }
};

}  // namespace millsim::sph
