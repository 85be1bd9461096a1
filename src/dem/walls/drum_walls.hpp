#pragma once
// Analytic walls of a rotating drum: inner cylinder (radius R, axis z through the origin), front
// end plate at z = 0, back end plate at z = z_back (the compaction piston while it moves), and
// N box lifters of radial height h and tangential width w attached to the cylinder along its
// whole length. All walls rotate with angular velocity omega about +z (drum angle phi); the back
// plate may also translate along z (v_back). Each contact is reported in the lab frame with the
// wall's own velocity at the contact point, so friction and power see the moving wall.
//
// Wall ids (used as negative partner keys in the contact history): 0 cylinder, 1 front plate,
// 2 back plate, 3 + k lifter k.
#include <cmath>

#include "millsim/core/hd.hpp"
#include "millsim/core/vec3.hpp"

namespace millsim::dem {

template <class T>
struct WallContact {
  int wall;                 // wall id
  core::Vec3<T> n;          // unit normal from the wall into the sphere
  T delta;                  // overlap
  core::Vec3<T> point;      // contact point on the wall surface
  core::Vec3<T> velocity;   // wall velocity at the contact point
};

// Lifter directions are precomputed on the host once per step (N sincos) and carried in the
// functor, so the per-ball wall test has no trigonometry; the kernel parameter stays small.
inline constexpr int kMaxLifters = 64;

template <class T>
struct DrumWalls {
  T radius;        // R, inner cylinder radius
  T z_back;        // back plate position
  T v_back;        // back plate velocity along z
  T omega;         // rad/s about +z
  int lifter_count;
  T lifter_height;
  T lifter_width;
  T lifter_cos[kMaxLifters];  // direction of lifter k's centre line: angle phi + phase0 + k 2 pi / N
  T lifter_sin[kMaxLifters];

  MILLSIM_HD core::Vec3<T> rotationVelocity(core::Vec3<T> p) const { return {-omega * p.y, omega * p.x, T(0)}; }

  template <class F>
  MILLSIM_HD void forEachContact(core::Vec3<T> p, T r, F&& f) const {
    using core::Vec3;
    // Balls away from the mantle (most of the bed) skip the square root and the lifter tests.
    const T rho2 = p.x * p.x + p.y * p.y;
    const T inner = radius - lifter_height - r;
    const bool near_mantle = inner <= T(0) || rho2 > inner * inner;
    if (near_mantle) {
      const T rho = std::sqrt(rho2);
      const T d_cyl = rho + r - radius;
      if (d_cyl > T(0) && rho > T(0)) {
        const Vec3<T> er{p.x / rho, p.y / rho, T(0)};
        const Vec3<T> cp{er.x * radius, er.y * radius, p.z};
        f(WallContact<T>{0, -er, d_cyl, cp, rotationVelocity(cp)});
      }
    }
    if (p.z < r) {
      const Vec3<T> cp{p.x, p.y, T(0)};
      f(WallContact<T>{1, {T(0), T(0), T(1)}, r - p.z, cp, rotationVelocity(cp)});
    }
    if (p.z + r > z_back) {
      const Vec3<T> cp{p.x, p.y, z_back};
      Vec3<T> v = rotationVelocity(cp);
      v.z = v_back;
      f(WallContact<T>{2, {T(0), T(0), T(-1)}, p.z + r - z_back, cp, v});
    }
    if (lifter_count > 0 && near_mantle) lifterContacts(p, r, f);
  }

 private:
  template <class F>
  MILLSIM_HD void lifterContacts(core::Vec3<T> p, T r, F&& f) const {
    using core::Vec3;
    // Nearest lifter by angle = largest projection of the ball centre on the lifter directions.
    int nearest = 0;
    T best = -T(1e30);
    for (int k = 0; k < lifter_count; ++k) {
      const T proj = p.x * lifter_cos[k] + p.y * lifter_sin[k];
      if (proj > best) {
        best = proj;
        nearest = k;
      }
    }
    // The nearest lifter and its two neighbours: enough unless lifters are closer than a ball.
    const int first = lifter_count >= 3 ? -1 : 0, last = lifter_count >= 3 ? 1 : lifter_count - 1;
    for (int dk = first; dk <= last; ++dk) {
      int k = (nearest + dk) % lifter_count;
      if (k < 0) k += lifter_count;
      const Vec3<T> er{lifter_cos[k], lifter_sin[k], T(0)};
      const Vec3<T> et{-er.y, er.x, T(0)};
      const T u = p.x * er.x + p.y * er.y, v = p.x * et.x + p.y * et.y;
      const T u0 = radius - lifter_height, hw = T(0.5) * lifter_width;
      const T cu = u < u0 ? u0 : (u > radius ? radius : u);
      const T cv = v < -hw ? -hw : (v > hw ? hw : v);
      const T cz = p.z < T(0) ? T(0) : (p.z > z_back ? z_back : p.z);
      const T du = u - cu, dv = v - cv, dz = p.z - cz;
      const T dist2 = du * du + dv * dv + dz * dz;
      Vec3<T> nrm;
      T delta;
      if (dist2 > T(0)) {
        if (dist2 >= r * r) continue;
        const T dist = std::sqrt(dist2);
        delta = r - dist;
        nrm = (du / dist) * er + (dv / dist) * et + Vec3<T>{T(0), T(0), dz / dist};
      } else {
        // Centre inside the box (only after a violent overlap): push out through the nearest face.
        const T d_top = u - u0, d_plus = hw - v, d_minus = v + hw;
        if (d_top <= d_plus && d_top <= d_minus) {
          nrm = -er;
          delta = r + d_top;
        } else if (d_plus <= d_minus) {
          nrm = et;
          delta = r + d_plus;
        } else {
          nrm = -et;
          delta = r + d_minus;
        }
      }
      const Vec3<T> cp = cu * er + cv * et + Vec3<T>{T(0), T(0), cz};
      f(WallContact<T>{3 + k, nrm, delta, cp, rotationVelocity(cp)});
    }
  }
};

}  // namespace millsim::dem
