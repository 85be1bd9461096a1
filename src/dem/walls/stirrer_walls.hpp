#pragma once
// Analytic walls of a horizontal stirred media mill (seed 004, LabStar LS1-like; docs/cases.md):
// a still chamber (inner cylinder of radius R about z, front plate z = 0, back plate z = L) and a
// stirrer turning about +z at omega: a shaft of radius r_s over the whole length carrying
// disk_count disks (radius R_d, thickness t, centred at disk_z[k]) pierced by hole_count axial
// cylindrical holes (radius r_h, centres on a ring of radius R_h, at angles
// phi + 2 pi m / hole_count, the same on every disk).
//
// Each wall reports the closest point of its solid to the sphere centre (exact distance
// functions), so a bead in a hole touches the hole's wall or its rim edge and a bead beyond the
// disk's rim touches the rim. Contacts come with the wall velocity at the contact point (omega x
// p for the stirrer, zero for the chamber) so friction, lubrication and the power see the moving
// stirrer. Wall ids: 0 chamber cylinder, 1 front plate, 2 back plate, 3 shaft, 4 + k disk k.
// Ids >= 3 belong to the stirrer (moving); the others are the still outer wall, whose torque is
// booked separately (kHasFixedWalls).
//
// Units: SI. Valid for hole_ring_radius + hole_radius < disk_radius and holes narrower than their
// angular spacing (only the hole nearest in angle is tested).
#include <cmath>

#include "dem/walls/drum_walls.hpp"
#include "millsim/core/hd.hpp"
#include "millsim/core/vec3.hpp"

namespace millsim::dem {

inline constexpr int kMaxDisks = 16;
inline constexpr int kMaxHoles = 32;
inline constexpr int kStirrerFirstWall = 3;

template <class T>
struct StirrerWalls {
  static constexpr bool kHasFixedWalls = true;

  T radius;        // chamber R
  T length;        // chamber L (back plate at z = L)
  T shaft_radius;  // r_s
  T omega;         // stirrer angular velocity about +z [rad/s]
  int disk_count;
  T disk_radius;
  T disk_half_thickness;
  T disk_z[kMaxDisks];
  int hole_count;
  T hole_radius;
  T hole_ring_radius;
  T hole_cos[kMaxHoles];  // hole m's direction at the current stirrer angle
  T hole_sin[kMaxHoles];

  MILLSIM_HD static bool isMoving(int wall) { return wall >= kStirrerFirstWall; }
  MILLSIM_HD core::Vec3<T> stirrerVelocity(core::Vec3<T> p) const { return {-omega * p.y, omega * p.x, T(0)}; }

  template <class F>
  MILLSIM_HD void forEachContact(core::Vec3<T> p, T r, F&& f) const {
    using core::Vec3;
    const Vec3<T> still = core::zero3<T>();
    const T rho2 = p.x * p.x + p.y * p.y;
    const T rho = std::sqrt(rho2);
    // Chamber cylinder.
    const T d_cyl = rho + r - radius;
    if (d_cyl > T(0) && rho > T(0)) {
      const Vec3<T> er{p.x / rho, p.y / rho, T(0)};
      f(WallContact<T>{0, -er, d_cyl, Vec3<T>{er.x * radius, er.y * radius, p.z}, still});
    }
    if (p.z < r) f(WallContact<T>{1, {T(0), T(0), T(1)}, r - p.z, Vec3<T>{p.x, p.y, T(0)}, still});
    if (p.z + r > length) f(WallContact<T>{2, {T(0), T(0), T(-1)}, p.z + r - length, Vec3<T>{p.x, p.y, length}, still});
    // Shaft.
    const T d_shaft = shaft_radius + r - rho;
    if (d_shaft > T(0) && rho > T(0)) {
      const Vec3<T> er{p.x / rho, p.y / rho, T(0)};
      const Vec3<T> cp{er.x * shaft_radius, er.y * shaft_radius, p.z};
      f(WallContact<T>{3, er, d_shaft, cp, stirrerVelocity(cp)});
    }
    // Disks: only those within reach along z, and only when the bead can reach the disk radius.
    if (rho - r >= disk_radius) return;
    for (int k = 0; k < disk_count; ++k) {
      const T dz = p.z - disk_z[k];
      if (dz >= disk_half_thickness + r || dz <= -(disk_half_thickness + r)) continue;
      diskContact(k, p, rho, dz, r, f);
    }
  }

 private:
  template <class F>
  MILLSIM_HD void diskContact(int k, core::Vec3<T> p, T rho, T dz, T r, F&& f) const {
    using core::Vec3;
    const T ht = disk_half_thickness;
    const T cz = dz < -ht ? -ht : (dz > ht ? ht : dz);  // clamp to the slab
    // Nearest hole by angle: largest projection of the centre on the hole directions.
    T hx = T(0), hy = T(0), dh2 = T(1e30);
    if (hole_count > 0) {
      int nearest = 0;
      T best = -T(1e30);
      for (int m = 0; m < hole_count; ++m) {
        const T proj = p.x * hole_cos[m] + p.y * hole_sin[m];
        if (proj > best) {
          best = proj;
          nearest = m;
        }
      }
      hx = hole_ring_radius * hole_cos[nearest];
      hy = hole_ring_radius * hole_sin[nearest];
      dh2 = (p.x - hx) * (p.x - hx) + (p.y - hy) * (p.y - hy);
    }
    Vec3<T> q;  // closest point of the disk solid, in lab coordinates
    if (dh2 < hole_radius * hole_radius) {
      // Above, below or inside a hole: the closest solid is the hole's wall (or its rim edge).
      const T dh = std::sqrt(dh2);
      const T ex = dh > T(0) ? (p.x - hx) / dh : T(1), ey = dh > T(0) ? (p.y - hy) / dh : T(0);
      q = {hx + hole_radius * ex, hy + hole_radius * ey, disk_z[k] + cz};
    } else if (rho > disk_radius) {
      // Beyond the rim: the rim's edge or its cylindrical face.
      q = {p.x * disk_radius / rho, p.y * disk_radius / rho, disk_z[k] + cz};
    } else if (dz > ht || dz < -ht) {
      q = {p.x, p.y, disk_z[k] + cz};  // above or below a face
    } else {
      // Centre inside the solid (after a violent overlap): out through the nearest face.
      const T to_face = ht - (dz < T(0) ? -dz : dz), to_rim = disk_radius - rho;
      Vec3<T> nrm;
      T delta;
      Vec3<T> cp;
      if (to_face <= to_rim) {
        nrm = {T(0), T(0), dz < T(0) ? T(-1) : T(1)};
        delta = r + to_face;
        cp = {p.x, p.y, disk_z[k] + (dz < T(0) ? -ht : ht)};
      } else {
        nrm = {p.x / rho, p.y / rho, T(0)};
        delta = r + to_rim;
        cp = {nrm.x * disk_radius, nrm.y * disk_radius, p.z};
      }
      f(WallContact<T>{kStirrerFirstWall + 1 + k, nrm, delta, cp, stirrerVelocity(cp)});
      return;
    }
    const Vec3<T> d = p - q;
    const T dist2 = core::norm2(d);
    if (dist2 >= r * r || dist2 <= T(0)) return;
    const T dist = std::sqrt(dist2);
    f(WallContact<T>{kStirrerFirstWall + 1 + k, (T(1) / dist) * d, r - dist, q, stirrerVelocity(q)});
  }
};

// Volumes of the geometry (host): chamber interior, stirrer solid, free (void) volume.
struct StirrerVolumes {
  double chamber, stirrer, free_volume;
};

inline StirrerVolumes stirrerVolumes(double R, double L, double r_shaft, int disks, double r_disk, double thickness,
                                     int holes, double r_hole) {
  const double pi = 3.14159265358979323846;
  StirrerVolumes v;
  v.chamber = pi * R * R * L;
  v.stirrer = pi * r_shaft * r_shaft * L + disks * (pi * (r_disk * r_disk - r_shaft * r_shaft) * thickness -
                                                    holes * pi * r_hole * r_hole * thickness);
  v.free_volume = v.chamber - v.stirrer;
  return v;
}

}  // namespace millsim::dem
