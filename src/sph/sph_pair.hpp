#pragma once
// What a pair of SPH particles within 2h does to one of its sides (paper eqs. 15-45): written
// once and used by both pair loops of sph_kernels.hpp, the one that visits every pair from
// both sides (each particle gathers its own sums; the GPU's) and the one that visits each pair
// once and hands the partner its share (the host's). Both give each side the same terms: the
// pair's kernel gradient is computed once, and the other side's terms come from the same
// function with the roles swapped, r_ab -> -r_ab, grad -> -grad.
//
// Side a from neighbour b, with grad = grad_a W_ab = fac r_ab:
//   every side:       continuity rho_a V_b v_ab . grad (DBC walls: their density, eq. 42), and
//                     the viscous speed |h v_ab . r_ab| / (r^2 + eta^2) of eq. 40;
//   fluid and body:   pressure -m (P_a + P_b) / (rho_a rho_b) grad and viscosity (a body
//                     particle sums what its fluid neighbours do to it: equal and opposite);
//   fluid only:       density diffusion with fluid b, the shifting sums, the SPS strain rate.
#include "millsim/core/hd.hpp"
#include "millsim/core/vec3.hpp"
#include "sph/viscosity.hpp"

namespace millsim::sph {

using core::Vec3;

enum ParticleCode : int {
  kFluid = 0,
  kBoundFixed = 1,
  kBoundMoving = 2,
  kBoundBody = 3,
  kExcludedDensity = 4,  // first excluded code: everything >= this is out of the run
  kExcludedDomain = 5,
};

MILLSIM_HD inline bool isExcluded(int code) { return code >= kExcludedDensity; }

// One particle's state as the pair terms read it.
template <class T>
struct SphSide {
  int code;
  Vec3<T> vel;
  // Velocity it brings into the viscous terms: its own, or a wall's no-slip velocity.
  Vec3<T> visc_vel;
  T rho, press;
  Sym3<T> tau;  // SPS stress (laminar+SPS only; zero otherwise)
  MILLSIM_HD bool fluid() const { return code == kFluid; }
  // Bitwise, not ||: no branch, so the pair blocks' loop (sph_pair_batch.hpp) vectorises.
  MILLSIM_HD bool forces() const { return (code == kFluid) | (code == kBoundBody); }
};

// Sums of one particle over its pairs.
template <class T>
struct PairSums {
  T drho = T(0);                      // drho/dt
  T visc_max = T(0);                  // largest viscous speed of its pairs (eq. 40)
  Vec3<T> acc = core::zero3<T>();     // dv/dt without gravity (fluid); fluid force / mass (body)
  Vec3<T> grad_c = core::zero3<T>();  // shifting: grad C = sum_b V_b grad W
  T div_r = T(0);                     // shifting: div r = -sum_b V_b r_ab . grad W
  Sym3<T> strain = zeroSym3<T>();     // SPS strain rate
};

// r += s for the sums a loop keeps (the viscous speed is a maximum, taken by whoever owns it).
template <class T, bool kShift, bool kStrain>
MILLSIM_HD MILLSIM_FORCE_INLINE void addPairSums(PairSums<T>& r, const PairSums<T>& s) {
  r.drho += s.drho;
  r.acc += s.acc;
  if constexpr (kShift) {
    r.grad_c += s.grad_c;
    r.div_r += s.div_r;
  }
  if constexpr (kStrain) r.strain += s.strain;
}

template <class T, class Kernel, class Ddt, class Visc, bool kShift>
struct SphPairPhysics {
  static constexpr bool kShifting = kShift;
  static constexpr bool kStrain = Visc::kNeedsStrain;
  Kernel kernel;
  Ddt ddt;
  Visc visc;
  T mass;  // of every particle, rho0 dp^Dim
  T eta2;
  Vec3<T> up;  // unit vector along -g (heights for Fourtakas DDT)

  // Adds to s what neighbour b does to side a. r_ab = x_a - x_b, grad = fac r_ab.
  // kViscSpeed: also the viscous speed (a pair visited once books it on one side only: only the
  // largest over all pairs enters the time step).
  template <bool kViscSpeed = true>
  MILLSIM_HD MILLSIM_FORCE_INLINE void addSide(PairSums<T>& s, const SphSide<T>& a, const SphSide<T>& b, Vec3<T> r_ab,
                                               T r2, T fac, Vec3<T> grad) const {
    const T vol_b = mass / b.rho;
    s.drho += a.rho * vol_b * core::dot(a.vel - b.vel, grad);
    // The velocity the viscous terms see (with no-slip walls, up to twice v_ab next to a wall);
    // the step's viscous speed (eq. 40) is taken from the same.
    const Vec3<T> v_ab_visc = a.visc_vel - b.visc_vel;
    if constexpr (kViscSpeed) {
      const T vr = kernel.h * core::dot(v_ab_visc, r_ab) / (r2 + eta2);
      const T avr = vr < T(0) ? -vr : vr;
      s.visc_max = s.visc_max > avr ? s.visc_max : avr;
    }
    if (!a.forces()) return;
    s.acc -= (mass * (a.press + b.press) / (a.rho * b.rho)) * grad;
    s.acc += visc(r_ab, v_ab_visc, r2, fac, a.rho, b.rho, mass, !a.fluid() | !b.fluid(), a.tau, b.tau);
    if (!a.fluid()) return;
    if constexpr (Ddt::kActive) {
      if (b.fluid()) s.drho += ddt(a.rho, b.rho, core::dot(up, r_ab), r2, fac, vol_b);
    }
    if constexpr (kShift) {
      s.grad_c += vol_b * grad;
      s.div_r -= vol_b * fac * r2;
    }
    if constexpr (kStrain) addStrain(s.strain, -v_ab_visc, grad, vol_b);
  }
};

}  // namespace millsim::sph
