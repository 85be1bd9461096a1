#pragma once
// Pairwise hydrodynamic lubrication between near-contacting spheres and between a sphere and a
// wall: the near-field (leading singular + logarithmic) Jeffrey & Onishi (1984) resistance
// functions, as used by seed 004 (stirred media mill, eqs. 5-11, after Ness & Sun) with the
// corrections of shared/reference/lubrication.md.
//
// Sphere i, partner j; n = unit vector from j to i; h = |x_i - x_j| - r_i - r_j (surface gap);
// beta = r_j / r_i; xi = 2 h / (r_i + r_j); L = ln(1 / xi); mu = fluid viscosity [Pa s].
//   X11A = 6 pi r_i [2 beta^2 / (1+beta)^3 / xi + beta (1 + 7 beta + beta^2) / (5 (1+beta)^3) L]
//   Y11A = 6 pi r_i [4 beta (2 + beta + 2 beta^2) / (15 (1+beta)^3) L]   (seed eq. 8 misprints it)
//   Y11B = -4 pi r_i^2 [beta (4 + beta) / (5 (1+beta)^2) L],  Y21B = Y11B seen from j (seed eq. 9)
//   Y11C = 8 pi r_i^3 [2 beta / (5 (1+beta)) L],  Y21C = 8 pi r_i^3 [beta^2 / (10 (1+beta)) L]
//   F_i = mu [-(X11A nn + Y11A (I - nn)) (v_i - v_j) - Y11B (w_i x n) - Y21B (w_j x n)]
//   T_i = mu [ Y11B (v_i - v_j) x n - (I - nn) (Y11C w_i + Y21C w_j)]
// The sign of the rotation terms of F_i is the reference's reciprocity fix of seed eq. 5 (the
// resistance matrix must be symmetric); F_j = -F_i exactly (the X, Y11A brackets are symmetric in
// i, j) and T_j is T_i with i and j swapped. For equal spheres the tangential force is
// -mu Y11A times the surface slip at the gap, and the dissipation is mu pi r L (slip)^2 + ...
// >= 0 (the leading-order matrix is positive semi-definite, zero for rolling without slip).
// NB the reference sheet's "equal spheres quick values" for Y11C, Y21C are half the general
// formulas at beta = 1; the general formulas are used (with them the matrix is semi-definite,
// with the halved values it is not).
//
// Sphere-wall (beta -> infinity, gap scaled by r, reference sheet): with Lw = ln(r / h),
//   X = 6 pi r^2 / h + 6 pi r / 5 Lw (Brenner 1961 plus log term),  Y11A = 6 pi r 8/15 Lw,
//   Y11B = -8 pi r^2 / 10 Lw,  Y11C = 8 pi r^3 2/5 Lw,
// with the wall's surface velocity at the contact point in place of v_j (and no w_j terms).
//
// Range (seed 004, section 3.1): active for h < outer d_ij, d_ij = r_i + r_j (the mean diameter;
// 2 r_i for a wall); below inner d_ij (and in overlap) the coefficients are evaluated at
// h = inner d_ij (regularised inner cutoff, LAMMPS/Ness practice), so the force stays finite and
// dissipative through a contact. Seed values inner = 0.001, outer = 0.05.
//
// Energy: the lubrication power of a pair is F_i.(v_i - v_j) + T_i.w_i + T_j.w_j (<= 0); the
// functor returns its negative as the dissipation rate, so budgets close to rounding.
// Units: SI; mu >= 0 (mu = 0 is never instantiated: no lubrication stage at all).
#include <cmath>

#include "millsim/core/hd.hpp"
#include "millsim/core/vec3.hpp"

namespace millsim::dem {

template <class T>
struct LubricationParams {
  T viscosity = 0;     // mu [Pa s]
  T inner = T(0.001);  // h_in = inner d_ij
  T outer = T(0.05);   // active for h < outer d_ij
};

// Near-field resistance scalars of one side (i) of a pair at the regularised gap.
template <class T>
struct ResistanceScalars {
  T xa, ya, yb11, yb21, yc11, yc21;
};

template <class T>
struct LubricationResult {
  core::Vec3<T> force;     // on i (the partner gets -force)
  core::Vec3<T> torque_i;  // on i
  core::Vec3<T> torque_j;  // on the partner (pairs only)
  T dissipation_rate;      // [W], >= 0
};

template <class T>
struct JeffreyOnishi {
  LubricationParams<T> p;

  static constexpr T kPiT = T(3.14159265358979323846);

  MILLSIM_HD T pairRange(T ri, T rj) const { return p.outer * (ri + rj); }
  MILLSIM_HD T wallRange(T ri) const { return p.outer * T(2) * ri; }

  // Scalars of sphere i (radius ri) against j (radius rj) at gap h (already regularised).
  MILLSIM_HD static ResistanceScalars<T> pairScalars(T ri, T rj, T h) {
    const T b = rj / ri, b1 = T(1) + b;
    const T xi = T(2) * h / (ri + rj);
    const T l = std::log(T(1) / xi);
    const T b13 = b1 * b1 * b1;
    ResistanceScalars<T> s;
    s.xa = T(6) * kPiT * ri * (T(2) * b * b / b13 / xi + b * (T(1) + T(7) * b + b * b) / (T(5) * b13) * l);
    s.ya = T(6) * kPiT * ri * (T(4) * b * (T(2) + b + T(2) * b * b) / (T(15) * b13) * l);
    s.yb11 = T(-4) * kPiT * ri * ri * (b * (T(4) + b) / (T(5) * b1 * b1) * l);
    const T c = T(1) / b, c1 = T(1) + c;  // j's beta
    s.yb21 = T(-4) * kPiT * rj * rj * (c * (T(4) + c) / (T(5) * c1 * c1) * l);
    s.yc11 = T(8) * kPiT * ri * ri * ri * (T(2) * b / (T(5) * b1) * l);
    s.yc21 = T(8) * kPiT * ri * ri * ri * (b * b / (T(10) * b1) * l);
    return s;
  }

  MILLSIM_HD static ResistanceScalars<T> wallScalars(T r, T h) {
    const T l = std::log(r / h);
    ResistanceScalars<T> s;
    s.xa = T(6) * kPiT * r * r / h + T(6) * kPiT * r / T(5) * l;
    s.ya = T(6) * kPiT * r * (T(8) / T(15)) * l;
    s.yb11 = T(-8) * kPiT * r * r / T(10) * l;
    s.yb21 = T(0);
    s.yc11 = T(8) * kPiT * r * r * r * (T(2) / T(5)) * l;
    s.yc21 = T(0);
    return s;
  }

  MILLSIM_HD T regularisedGap(T h, T d) const {
    const T h_in = p.inner * d;
    return h < h_in ? h_in : h;
  }

  // Pair (i, j): n from j to i, h the gap (may be <= 0 in contact). Caller checks h < pairRange.
  MILLSIM_HD LubricationResult<T> pair(core::Vec3<T> n, T h, T ri, T rj, core::Vec3<T> vi, core::Vec3<T> vj,
                                       core::Vec3<T> wi, core::Vec3<T> wj) const {
    using core::Vec3;
    const T he = regularisedGap(h, ri + rj);
    const ResistanceScalars<T> si = pairScalars(ri, rj, he);
    const ResistanceScalars<T> sj = pairScalars(rj, ri, he);
    const T mu = p.viscosity;
    const Vec3<T> u = vi - vj;
    const T un = core::dot(u, n);
    const Vec3<T> ut = u - un * n;
    LubricationResult<T> r;
    r.force = mu * (-(si.xa * un) * n - si.ya * ut - si.yb11 * core::cross(wi, n) - si.yb21 * core::cross(wj, n));
    const Vec3<T> wi_t = wi - core::dot(wi, n) * n, wj_t = wj - core::dot(wj, n) * n;
    const Vec3<T> uxn = core::cross(u, n);
    r.torque_i = mu * (si.yb11 * uxn - si.yc11 * wi_t - si.yc21 * wj_t);
    // From j: n -> -n, u -> -u, so (v_j - v_i) x (-n) = u x n.
    r.torque_j = mu * (sj.yb11 * uxn - sj.yc11 * wj_t - sj.yc21 * wi_t);
    r.dissipation_rate = -(core::dot(r.force, u) + core::dot(r.torque_i, wi) + core::dot(r.torque_j, wj));
    return r;
  }

  // Sphere-wall: n from the wall into the sphere, h the gap, u = v_i - wall surface velocity.
  MILLSIM_HD LubricationResult<T> wall(core::Vec3<T> n, T h, T ri, core::Vec3<T> u, core::Vec3<T> wi) const {
    using core::Vec3;
    const T he = regularisedGap(h, T(2) * ri);
    const ResistanceScalars<T> s = wallScalars(ri, he);
    const T mu = p.viscosity;
    const T un = core::dot(u, n);
    const Vec3<T> ut = u - un * n;
    LubricationResult<T> r;
    r.force = mu * (-(s.xa * un) * n - s.ya * ut - s.yb11 * core::cross(wi, n));
    const Vec3<T> wi_t = wi - core::dot(wi, n) * n;
    r.torque_i = mu * (s.yb11 * core::cross(u, n) - s.yc11 * wi_t);
    r.torque_j = core::zero3<T>();
    r.dissipation_rate = -(core::dot(r.force, u) + core::dot(r.torque_i, wi));
    return r;
  }
};

}  // namespace millsim::dem
