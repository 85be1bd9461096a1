#pragma once
// One touching sphere pair through the contact law: the geometry and kinematics of the contact
// point, then the law. The one place this is written, called by the per-particle contact loop
// (ContactForces, OpenMP and CUDA) and by the host's batched pass (contact_batch.hpp), which
// runs it over a block of pairs at once so the compiler can vectorise it.
//
// Inputs as the lower-index side i sees the pair: d = x_i - x_j with |d|^2 = dist2 < (r_i + r_j)^2,
// dv = v_i - v_j, the spins, and the pair's tangential spring s (updated in place).
#include "dem/contact/hertz.hpp"
#include "millsim/core/hd.hpp"
#include "millsim/core/vec3.hpp"

namespace millsim::dem {

// Whether a listed pair touches: centres closer than r_i + r_j (and not coincident, where the
// normal is undefined). Apart, its spring is released.
template <class T>
MILLSIM_HD MILLSIM_FORCE_INLINE bool pairTouches(T dist2, T reach) {
  return dist2 < reach * reach && dist2 > T(0);
}

template <class T>
struct TouchingPair {
  ContactResult<T> c;  // the force on i (j gets -c.force)
  core::Vec3<T> n;     // unit normal from j to i
  core::Vec3<T> v_rel;
  core::Vec3<T> nxft;  // n x F_t: the torques are -a_i (n x F_t) on i and -a_j (n x F_t) on j
  T ai, aj;            // lever arms to the contact point (half the overlap off each radius)
  T delta;             // overlap
};

template <class T, class Law>
MILLSIM_HD MILLSIM_FORCE_INLINE TouchingPair<T> touchingPair(const Law& law, core::Vec3<T> d, T dist2, T ri, T rj, T mi,
                                                             T mj, core::Vec3<T> dv, core::Vec3<T> wi, core::Vec3<T> wj,
                                                             core::Vec3<T>& s, T dt) {
  TouchingPair<T> t;
  const T reach = ri + rj;
  const T dist = std::sqrt(dist2);
  t.n = (T(1) / dist) * d;
  t.delta = reach - dist;
  t.ai = ri - T(0.5) * t.delta;
  t.aj = rj - T(0.5) * t.delta;
  t.v_rel = dv + core::cross(wi, (-t.ai) * t.n) - core::cross(wj, t.aj * t.n);
  t.c = law(t.n, t.delta, ri * rj / reach, mi * mj / (mi + mj), t.v_rel, s, dt);
  t.nxft = core::cross(t.n, t.c.force_t);
  return t;
}

}  // namespace millsim::dem
