#pragma once
// Collision bookkeeping of the stirred mill and the pair hook that adds lubrication to the DEM
// contact loop (ContactForces' `Extra` parameter, dem_kernels.hpp).
//
// Beinert typology (Beinert et al. 2015; seed 004 eqs. 12-17; shared/reference/
// stirred_mill_collisions.md), per bead-bead contact, m the bead mass (seed convention: the mass
// of one bead, not the reduced mass), r = 2 r_i r_j / (r_i + r_j), n the contact normal:
//   impact   E_i = 1/2 m (v_rel . n)^2
//   torsion  E_t = 1/5 m r^2 ((w_i - w_j) . n)^2
//   shearing E_s = 1/2 m |v_slip|^2,  v_slip = (I - nn)(v_i - v_j) - (r_i w_i + r_j w_j) x n
//            (relative tangential velocity of the surfaces at the contact point: sliding)
//   rolling  E_r = 1/5 m r^2 |(I - nn)(w_i - w_j)|^2  (Luding's rolling velocity, co-directed
//            surface motion)
// The seed splits shearing and rolling further into translational and rotational parts; their
// sums are what it reports. Dissipation by mode: each step, a contact's dissipated energy
// (normal damping + tangential friction) is booked to its dominant mode (largest E) - the
// reference sheet's suggestion, since the seed does not print its split. The mechanism split
// (normal damping vs tangential work) is kept beside it.
// A collision is counted when a pair's tangential spring is empty at the start of a contact
// step (contact begins).
#include "dem/contact/hertz.hpp"
#include "dem/contact/lubrication.hpp"
#include "millsim/core/hd.hpp"
#include "millsim/core/vec3.hpp"

namespace millsim::dem {

enum CollisionMode { kModeImpact = 0, kModeShearing = 1, kModeRolling = 2, kModeTorsion = 3, kModeCount = 4 };

// Per bead, accumulated over the run; a pair's share goes to the bead that evaluates it.
struct CollisionTally {
  double dissipated[kModeCount];  // J, bead-bead contact dissipation by dominant mode
  double dissipated_normal;       // J, bead-bead normal damping part
  double dissipated_wall;         // J, bead-wall contact dissipation
  double energy[kModeCount];      // J, Beinert energies at the start of each collision
  double collisions;              // bead-bead collisions begun
};

template <class T>
struct BeinertEnergies {
  T e[kModeCount];
};

template <class T>
MILLSIM_HD BeinertEnergies<T> beinertEnergies(core::Vec3<T> n, T ri, T rj, T m, core::Vec3<T> vi, core::Vec3<T> vj,
                                              core::Vec3<T> wi, core::Vec3<T> wj) {
  using core::Vec3;
  const Vec3<T> u = vi - vj;
  const T un = core::dot(u, n);
  const Vec3<T> slip = (u - un * n) - core::cross(ri * wi + rj * wj, n);
  const Vec3<T> dw = wi - wj;
  const T wn = core::dot(dw, n);
  const Vec3<T> dwt = dw - wn * n;
  const T r = T(2) * ri * rj / (ri + rj);
  BeinertEnergies<T> b;
  b.e[kModeImpact] = T(0.5) * m * un * un;
  b.e[kModeShearing] = T(0.5) * m * core::norm2(slip);
  b.e[kModeRolling] = T(0.2) * m * r * r * core::norm2(dwt);
  b.e[kModeTorsion] = T(0.2) * m * r * r * wn * wn;
  return b;
}

MILLSIM_HD inline int dominantMode(const double* e) {
  int k = 0;
  for (int q = 1; q < kModeCount; ++q)
    if (e[q] > e[k]) k = q;
  return k;
}

// The stirred mill's pair hook: collision tallies when kTally (the case asks for collision
// statistics), lubrication when kLubricated. With neither the solver uses NoPairExtra instead.
template <class T, bool kLubricated, bool kTally = true>
struct StirredPairExtra {
  static constexpr bool kActive = true;
  static constexpr bool kLub = kLubricated;
  JeffreyOnishi<T> lub;
  CollisionTally* tally;
  double* lub_dissipated;  // J per bead (nullptr without lubrication)
  T dt;

  MILLSIM_HD T pairRange(T ri, T rj) const { return kLub ? lub.pairRange(ri, rj) : T(0); }
  MILLSIM_HD T wallRange(T ri) const { return kLub ? lub.wallRange(ri) : T(0); }

  MILLSIM_HD LubricationResult<T> pairLubrication(int i, core::Vec3<T> n, T gap, T ri, T rj, core::Vec3<T> vi,
                                                  core::Vec3<T> vj, core::Vec3<T> wi, core::Vec3<T> wj) const {
    const LubricationResult<T> r = lub.pair(n, gap, ri, rj, vi, vj, wi, wj);
    lub_dissipated[i] += double(r.dissipation_rate) * double(dt);
    return r;
  }
  MILLSIM_HD LubricationResult<T> wallLubrication(int i, core::Vec3<T> n, T gap, T ri, core::Vec3<T> u,
                                                  core::Vec3<T> wi) const {
    const LubricationResult<T> r = lub.wall(n, gap, ri, u, wi);
    lub_dissipated[i] += double(r.dissipation_rate) * double(dt);
    return r;
  }

  // A touching pair as i sees it: dv = v_i - v_j (the energies use only the difference), v_rel
  // at the contact point, and of the law's result only c.force_t and c.dissipation_rate (the
  // host's batched pass passes those two).
  MILLSIM_HD void pairContact(int i, core::Vec3<T> n, T ri, T rj, T mi, core::Vec3<T> dv, core::Vec3<T> wi,
                              core::Vec3<T> wj, core::Vec3<T> v_rel, const ContactResult<T>& c, bool begins) const {
    if constexpr (kTally) {
      const BeinertEnergies<T> b = beinertEnergies(n, ri, rj, mi, dv, core::zero3<T>(), wi, wj);
      double e[kModeCount];
      for (int q = 0; q < kModeCount; ++q) e[q] = double(b.e[q]);
      CollisionTally& t = tally[i];
      const double diss = double(c.dissipation_rate) * double(dt);
      t.dissipated[dominantMode(e)] += diss;
      const core::Vec3<T> vt = v_rel - core::dot(v_rel, n) * n;
      t.dissipated_normal += diss + double(core::dot(c.force_t, vt)) * double(dt);
      if (begins) {
        for (int q = 0; q < kModeCount; ++q) t.energy[q] += e[q];
        t.collisions += 1.0;
      }
    }
  }
  MILLSIM_HD void wallContact(int i, const ContactResult<T>& c) const {
    if constexpr (kTally) tally[i].dissipated_wall += double(c.dissipation_rate) * double(dt);
  }
};

}  // namespace millsim::dem
