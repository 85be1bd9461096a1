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
  T o_drho[kSize], o_visc[kSize], o_ax[kSize], o_ay[kSize], o_az[kSize];
  T o_gx[kS], o_gy[kS], o_gz[kS], o_div[kS], o_strain[6][kT];
  T s_drho[kSize], s_ax[kSize], s_ay[kSize], s_az[kSize];
  T s_gx[kS], s_gy[kS], s_gz[kS], s_div[kS], s_strain[6][kT];

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

  static MILLSIM_FORCE_INLINE void putSym(T (&t)[6][kT], int k, const Sym3<T>& s) {
    t[0][k] = s.xx, t[1][k] = s.yy, t[2][k] = s.zz, t[3][k] = s.xy, t[4][k] = s.xz, t[5][k] = s.yz;
  }
  static MILLSIM_FORCE_INLINE Sym3<T> getSym(const T (&t)[6][kT], int k) {
    return {t[0][k], t[1][k], t[2][k], t[3][k], t[4][k], t[5][k]};
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
      sa.tau = Block::getSym(q.a_tau, k);
      sb.tau = Block::getSym(q.b_tau, k);
    }
    PairSums<T> own, share;
    phys.addSide(own, sa, sb, r_ab, r2, fac, grad);
    phys.template addSide<false>(share, sb, sa, -r_ab, r2, fac, -grad);
    q.o_drho[k] = own.drho;
    q.o_visc[k] = own.visc_max;
    q.o_ax[k] = own.acc.x, q.o_ay[k] = own.acc.y, q.o_az[k] = own.acc.z;
    q.s_drho[k] = share.drho;
    q.s_ax[k] = share.acc.x, q.s_ay[k] = share.acc.y, q.s_az[k] = share.acc.z;
    if constexpr (Block::kShift) {
      q.o_gx[k] = own.grad_c.x, q.o_gy[k] = own.grad_c.y, q.o_gz[k] = own.grad_c.z, q.o_div[k] = own.div_r;
      q.s_gx[k] = share.grad_c.x, q.s_gy[k] = share.grad_c.y, q.s_gz[k] = share.grad_c.z, q.s_div[k] = share.div_r;
    }
    if constexpr (Block::kStrain) {
      Block::putSym(q.o_strain, k, own.strain);
      Block::putSym(q.s_strain, k, share.strain);
    }
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
  using Block = SphPairBlock<Physics>;
  for (int k = 0; k < count; ++k) {
    if (q.a[k] != run.a) {
      if (run.a >= 0) sink.addOwn(run.a, run.sums);
      run.a = q.a[k];
      run.sums = PairSums<T>{};
    }
    PairSums<T>& s = run.sums;
    s.drho += q.o_drho[k];
    s.visc_max = s.visc_max > q.o_visc[k] ? s.visc_max : q.o_visc[k];
    s.acc += Vec3<T>{q.o_ax[k], q.o_ay[k], q.o_az[k]};
    PairSums<T> share;
    share.drho = q.s_drho[k];
    share.acc = {q.s_ax[k], q.s_ay[k], q.s_az[k]};
    if constexpr (Block::kShift) {
      s.grad_c += Vec3<T>{q.o_gx[k], q.o_gy[k], q.o_gz[k]};
      s.div_r += q.o_div[k];
      share.grad_c = {q.s_gx[k], q.s_gy[k], q.s_gz[k]};
      share.div_r = q.s_div[k];
    }
    if constexpr (Block::kStrain) {
      s.strain += Block::getSym(q.o_strain, k);
      share.strain = Block::getSym(q.s_strain, k);
    }
    sink.addPartner(q.b[k], share);
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
    const auto stage = [&](int b, Vec3<T> r_ab, T r2) {
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
