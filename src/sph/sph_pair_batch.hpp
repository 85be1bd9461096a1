#pragma once
// The host's pair-once SPH loop (SphPairInteraction, sph_kernels.hpp) in blocks of pairs, as the
// DEM's contact pass does it (dem/contact_batch.hpp). The search is the same; a pair it finds is
// not evaluated on the spot: both sides' state is copied into a small structure-of-arrays
// block, and when the block is full the pair terms run over all of it in one loop the compiler
// vectorises (SphPairPhysics::addSide, the same code the per-particle loop and CUDA call), then
// each entry's two results are booked: the evaluating particle's into its running sums, the
// partner's share through the sink. Why: per particle each pair is a chain of a square root,
// several divisions and the kernel's polynomial, evaluated one after another; in a block the
// same operations fill the vector lanes.
//
// Host only (OpenMP): the block lives on the thread's stack. Every pair gets the terms the
// per-particle loop gives it; only the order of the additions into a particle's sums differs
// (tests/unit/test_sph_pair_loop.cpp holds the two to 1e-11 of each sum's scale).
#include <cmath>
#include <type_traits>

#include "millsim/backend/simd.hpp"
#include "sph/sph_kernels.hpp"

namespace millsim::sph {

// A symmetric tensor per block entry as six arrays.
template <class T, int kN>
MILLSIM_FORCE_INLINE void putSym(T (&t)[6][kN], int k, const Sym3<T>& s) {
  t[0][k] = s.xx, t[1][k] = s.yy, t[2][k] = s.zz, t[3][k] = s.xy, t[4][k] = s.xz, t[5][k] = s.yz;
}
template <class T, int kN>
MILLSIM_FORCE_INLINE Sym3<T> getSym(const T (&t)[6][kN], int k) {
  return {t[0][k], t[1][k], t[2][k], t[3][k], t[4][k], t[5][k]};
}

// One side's terms of every entry of a block, as structure of arrays (sizes as SphPairBlock's).
template <class T, int kSize, int kVisc, int kS, int kT>
struct SphBlockSums {
  T drho[kSize], visc[kVisc], ax[kSize], ay[kSize], az[kSize];
  T gx[kS], gy[kS], gz[kS], div[kS], strain[6][kT];
  MILLSIM_FORCE_INLINE void put(int k, const PairSums<T>& s) {
    drho[k] = s.drho;
    if constexpr (kVisc > 1) visc[k] = s.visc_max;
    ax[k] = s.acc.x, ay[k] = s.acc.y, az[k] = s.acc.z;
    if constexpr (kS > 1) gx[k] = s.grad_c.x, gy[k] = s.grad_c.y, gz[k] = s.grad_c.z, div[k] = s.div_r;
    if constexpr (kT > 1) putSym(strain, k, s.strain);
  }
  MILLSIM_FORCE_INLINE PairSums<T> get(int k) const {
    PairSums<T> s;
    s.drho = drho[k];
    if constexpr (kVisc > 1) s.visc_max = visc[k];
    s.acc = {ax[k], ay[k], az[k]};
    if constexpr (kS > 1) s.grad_c = {gx[k], gy[k], gz[k]}, s.div_r = div[k];
    if constexpr (kT > 1) s.strain = getSym(strain, k);
    return s;
  }
};

// Pairs waiting for the terms, as structure of arrays. The evaluating side a is always fluid;
// entries of one a are consecutive. Arrays a loop does not use (shifting sums, SPS stresses and
// strain rates when those are off) shrink to one element.
template <class Physics, class T = decltype(Physics::mass)>
struct alignas(64) SphPairBlock {
  static constexpr int kSize = 64;
  static constexpr bool kShift = Physics::kShifting, kStrain = Physics::kStrain;
  static constexpr int kS = kShift ? kSize : 1, kT = kStrain ? kSize : 1;
  int a[kSize], b[kSize], code_b[kSize];
  // In: r_ab = x_a - x_b and its square; each side's velocity, viscous velocity, density,
  // pressure (and SPS stress).
  T rx[kSize], ry[kSize], rz[kSize], r2[kSize];
  T a_vx[kSize], a_vy[kSize], a_vz[kSize], a_wx[kSize], a_wy[kSize], a_wz[kSize], a_rho[kSize], a_p[kSize];
  T b_vx[kSize], b_vy[kSize], b_vz[kSize], b_wx[kSize], b_wy[kSize], b_wz[kSize], b_rho[kSize], b_p[kSize];
  T a_tau[6][kT], b_tau[6][kT];
  // Out: a's terms (with the viscous speed) and b's share.
  SphBlockSums<T, kSize, kSize, kS, kT> own;
  SphBlockSums<T, kSize, 1, kS, kT> share;

  MILLSIM_FORCE_INLINE void stage(int k, int ia, const SphSide<T>& sa, int ib, const SphSide<T>& sb, Vec3<T> r_ab,
                                  T dist2) {
    a[k] = ia;
    b[k] = ib;
    code_b[k] = sb.code;
    rx[k] = r_ab.x;
    ry[k] = r_ab.y;
    rz[k] = r_ab.z;
    r2[k] = dist2;
    a_vx[k] = sa.vel.x, a_vy[k] = sa.vel.y, a_vz[k] = sa.vel.z;
    a_wx[k] = sa.visc_vel.x, a_wy[k] = sa.visc_vel.y, a_wz[k] = sa.visc_vel.z;
    a_rho[k] = sa.rho, a_p[k] = sa.press;
    b_vx[k] = sb.vel.x, b_vy[k] = sb.vel.y, b_vz[k] = sb.vel.z;
    b_wx[k] = sb.visc_vel.x, b_wy[k] = sb.visc_vel.y, b_wz[k] = sb.visc_vel.z;
    b_rho[k] = sb.rho, b_p[k] = sb.press;
    if constexpr (kStrain) {
      putSym(a_tau, k, sa.tau);
      putSym(b_tau, k, sb.tau);
    }
  }
};

// The pair terms over the first `count` entries (the loop the compiler vectorises).
template <class Physics, class T = decltype(Physics::mass)>
MILLSIM_FORCE_INLINE void evaluateSphBlockLoop(SphPairBlock<Physics>& q, int count, const Physics& physics) {
  using Block = SphPairBlock<Physics>;
  // A copy on the stack: the constants are then registers, not loads through a pointer, which
  // the compiler cannot move out of the terms' branches (a load it may not speculate keeps a
  // branch in the loop, and a branch stops vectorisation).
  const Physics phys = physics;
  MILLSIM_VECTORIZE_LOOP
  for (int k = 0; k < count; ++k) {
    const Vec3<T> r_ab{q.rx[k], q.ry[k], q.rz[k]};
    const T r2 = q.r2[k];
    const T fac = phys.kernel.fac(std::sqrt(r2));
    const Vec3<T> grad = fac * r_ab;
    SphSide<T> sa{
        kFluid,       {q.a_vx[k], q.a_vy[k], q.a_vz[k]}, {q.a_wx[k], q.a_wy[k], q.a_wz[k]}, q.a_rho[k], q.a_p[k],
        zeroSym3<T>()};
    SphSide<T> sb{
        q.code_b[k],  {q.b_vx[k], q.b_vy[k], q.b_vz[k]}, {q.b_wx[k], q.b_wy[k], q.b_wz[k]}, q.b_rho[k], q.b_p[k],
        zeroSym3<T>()};
    if constexpr (Block::kStrain) {
      sa.tau = getSym(q.a_tau, k);
      sb.tau = getSym(q.b_tau, k);
    }
    PairSums<T> own, share;
    phys.addSide(own, sa, sb, r_ab, r2, fac, grad);
    phys.template addSide<false>(share, sb, sa, -r_ab, r2, fac, -grad);
    q.own.put(k, own);
    q.share.put(k, share);
  }
}

#if defined(MILLSIM_HAVE_SIMD_LEVELS)
template <class Physics>
MILLSIM_TARGET_AVX2 void evaluateSphBlockAvx2(SphPairBlock<Physics>& q, int count, const Physics& phys) {
  evaluateSphBlockLoop(q, count, phys);
}
template <class Physics>
MILLSIM_TARGET_AVX512 void evaluateSphBlockAvx512(SphPairBlock<Physics>& q, int count, const Physics& phys) {
  evaluateSphBlockLoop(q, count, phys);
}
#endif

template <class Physics>
void evaluateSphBlock(SphPairBlock<Physics>& q, int count, const Physics& phys, backend::SimdLevel level) {
#if defined(MILLSIM_HAVE_SIMD_LEVELS)
  if (level == backend::SimdLevel::kAvx512) return evaluateSphBlockAvx512(q, count, phys);
  if (level == backend::SimdLevel::kAvx2) return evaluateSphBlockAvx2(q, count, phys);
#endif
  (void)level;
  evaluateSphBlockLoop(q, count, phys);
}

// The evaluating particle whose entries are being summed; its sums go to the sink when the
// next particle's entries start (a particle's entries may span two blocks) or the range ends.
template <class T>
struct SphRunningSums {
  int a = -1;
  PairSums<T> sums;
};

// The evaluated entries to both sides' sums, in order.
template <class Physics, class Sink, class T = decltype(Physics::mass)>
void bookSphBlock(const Sink& sink, const SphPairBlock<Physics>& q, int count, SphRunningSums<T>& run) {
  constexpr bool kShift = Physics::kShifting, kStrain = Physics::kStrain;
  for (int k = 0; k < count; ++k) {
    if (q.a[k] != run.a) {
      if (run.a >= 0) sink.addOwn(run.a, run.sums);
      run.a = q.a[k];
      run.sums = PairSums<T>{};
    }
    const PairSums<T> own = q.own.get(k);
    addPairSums<T, kShift, kStrain>(run.sums, own);
    run.sums.visc_max = run.sums.visc_max > own.visc_max ? run.sums.visc_max : own.visc_max;
    sink.addPartner(q.b[k], q.share.get(k));
  }
}

// SphPairInteraction `it` over particles [lo, hi), pairs in blocks. The sums must have been
// cleared (ClearPairSums), as for the per-particle loop; a fluid particle without pairs keeps
// its cleared sums.
template <class Interaction>
void runSphPairsBatched(const Interaction& it, int lo, int hi) {
  using Physics = std::decay_t<decltype(it.phys)>;
  using T = decltype(Physics::mass);
  const backend::SimdLevel level = backend::simdLevel();
  SphPairBlock<Physics> q;
  SphRunningSums<T> run;
  int count = 0;
  const SphView<T>& p = it.p;
  for (int a = lo; a < hi; ++a) {
    if (p.code[a] != kFluid) continue;
    const SphSide<T> sa = loadSide<T, Physics::kStrain>(p, a);
    const auto stage = [&](int b, Vec3<T> r_ab, T r2) MILLSIM_LAMBDA_FORCE_INLINE {
      if (r2 <= T(0)) return;
      q.stage(count, a, sa, b, loadSide<T, Physics::kStrain>(p, b), r_ab, r2);
      if (++count == SphPairBlock<Physics>::kSize) {
        evaluateSphBlock(q, count, it.phys, level);
        bookSphBlock(it.sink, q, count, run);
        count = 0;
      }
    };
    const Vec3<T> xa = p.pos[a];
    it.fluid_cells.forEachWithinAfter(a, xa, it.support2, p.pos, stage);
    it.bound_cells.forEachWithin(xa, it.support2, p.pos, stage);
  }
  evaluateSphBlock(q, count, it.phys, level);
  bookSphBlock(it.sink, q, count, run);
  if (run.a >= 0) it.sink.addOwn(run.a, run.sums);
}

// The pair-once loop over [lo, hi) on one thread: in blocks, or one particle at a time at
// SimdLevel::kScalar (as CUDA runs it).
template <class Interaction>
void runSphPairRange(const Interaction& it, int lo, int hi) {
  if (backend::simdLevel() != backend::SimdLevel::kScalar) {
    runSphPairsBatched(it, lo, hi);
    return;
  }
  for (int a = lo; a < hi; ++a) it(a);
}

}  // namespace millsim::sph
