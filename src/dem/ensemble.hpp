#pragma once
// Ensembles: K independent drum scenes advanced by one DEM solver in the same kernels, so that a
// calibration's batch (3 diameters x several (e, mu) candidates, a few hundred balls each) is one
// launch per stage on a GPU instead of K launch-bound runs (issue 10).
//
// Scene k's particles live in the slab z in [origin + k pitch, origin + (k + 1) pitch) of one
// domain, its local origin `lead` into the slab; its walls (its own drum, turned by its own motion) and its contact law
// (its own e and mu) are looked up from a particle's z. The slabs are further apart than any contact or neighbour
// reach, so no pair crosses scenes and each scene moves as it would alone. The scene of a pair is its lower particle's:
// both lie in one slab.
//
// Walls see a scene-local position (z - z0), so the drum code is the single-scene code. The
// slab origin is centred on z = 0: in float the largest |z| is K/2 pitch, not K pitch.
#include <cmath>

#include "dem/walls/drum_walls.hpp"
#include "millsim/core/hd.hpp"
#include "millsim/core/vec3.hpp"

namespace millsim::dem {

// The scene whose slab holds z (clamped to the first and last: a particle that left its slab
// has escaped its drum, which the run detects and stops on).
template <class T>
MILLSIM_HD int sceneOf(T z, T origin, T inv_pitch, int count) {
  // Clamped as a real number first: a diverged (huge or NaN) z must not reach the int cast.
  const T u = (z - origin) * inv_pitch;
  if (!(u >= T(0))) return 0;
  if (u >= T(count)) return count - 1;
  return static_cast<int>(u);
}

template <class T>
struct SlabLayout {
  T origin;     // z of scene 0's slab start
  T pitch;      // slab length along z
  T inv_pitch;  // 1 / pitch
  T lead;       // from a slab's start to its scene's local origin (its drum's front plate)
  int count;    // scenes
  MILLSIM_HD int scene(T z) const { return sceneOf(z, origin, inv_pitch, count); }
  MILLSIM_HD T zero(int k) const { return origin + T(k) * pitch + lead; }
};

// Per-scene contact parameters: the law of scene k is Law{params[k]} (every law of the drum is
// an aggregate over its HertzParams). The single-scene law passes through lawAt unchanged.
template <class Law, class Params, class T>
struct EnsembleLaw {
  const Params* params;  // one per scene, in the execution space's memory
  SlabLayout<T> slabs;
};

template <class Law, class T>
MILLSIM_HD Law lawAt(const Law& law, const core::Vec3<T>&) {
  return law;
}

template <class Law, class Params, class T>
MILLSIM_HD Law lawAt(const EnsembleLaw<Law, Params, T>& e, const core::Vec3<T>& x) {
  return Law{e.params[e.slabs.scene(x.z)]};
}

// A value per scene, looked up by a particle's slab: the time step (each case advances by its
// own dt, its own contact time, so a batch costs the steps its runs would take alone; a case
// that has ended has dt = 0 and rests) and the neighbour skin (each case's own, so a case of
// large balls is not rebuilt at the small balls' rate). A plain value passes through valueAt
// unchanged.
template <class T>
struct SceneTable {
  const T* value;  // one per scene, in the execution space's memory
  SlabLayout<T> slabs;
};

template <class T>
MILLSIM_HD T valueAt(T v, const core::Vec3<T>&) {
  return v;
}

template <class T>
MILLSIM_HD T valueAt(const SceneTable<T>& s, const core::Vec3<T>& x) {
  return s.value[s.slabs.scene(x.z)];
}

// The drum walls of every scene: a particle meets its own scene's drum, in scene-local
// coordinates; the contact point goes back to the ensemble's frame (its x, y give the torque
// about the drum axis, which every scene shares).
template <class T>
struct EnsembleDrumWalls {
  const DrumWalls<T>* drums;  // one per scene, in the execution space's memory
  SlabLayout<T> slabs;

  template <class F>
  MILLSIM_HD void forEachContact(core::Vec3<T> p, T r, F&& f) const {
    const int k = slabs.scene(p.z);
    const T z0 = slabs.zero(k);
    drums[k].forEachContact(core::Vec3<T>{p.x, p.y, p.z - z0}, r, [&](const WallContact<T>& w) {
      WallContact<T> v = w;
      v.point.z += z0;
      f(v);
    });
  }
};

// A per-particle quantity counted only for the particles of host numbers [lo, hi) (one scene's):
// the per-scene sums are the ensemble's reductions through this mask.
template <class F>
struct HostRange {
  F f;
  const int* id;
  int lo, hi;
  MILLSIM_HD auto operator()(int i) const -> decltype(f(i)) {
    const int h = id[i];
    return h >= lo && h < hi ? f(i) : decltype(f(i))(0);
  }
};

}  // namespace millsim::dem
