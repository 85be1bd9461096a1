#pragma once
// The host's contact pass in blocks of pairs. Per particle the loop does what it always did
// (gravity, walls, the contact test on each neighbour-list slot), but a touching pair is not
// evaluated on the spot: its inputs are copied into a small structure-of-arrays block, and when
// the block is full the law runs over all of it in one loop the compiler vectorises
// (touching_pair.hpp, the same code the per-particle loop and CUDA call), then the results are
// booked to both sides in order. Why: in the per-particle loop each pair is one long chain of
// dependent square roots and divisions, so the core ran the pairs mostly one after another; in
// a block the same operations fill the vector lanes. Measured in docs/performance.md (the law
// is then ~10% of the pass; the partner loads and adds around it are the rest).
//
// Host only (OpenMP): the block lives on the thread's stack. Bookings per pair equal the
// per-particle loop's (the force, torque and half the dissipation on each side, the elastic
// energy on i); only the order of the additions differs. A pair hook that reads touching pairs
// (the stirred mill's collision statistics, CF::kPairHook) gets each pair as it is booked, with
// the normal, contact velocity and tangential force the block keeps for it; without a hook the
// loop does not store them. (Before, statistics sent the whole pass pair by pair: the LS1 slice
// ran 1.67 times slower with them than without.)
#include <algorithm>

#include "dem/dem_kernels.hpp"
#include "dem/touching_pair.hpp"
#include "millsim/backend/simd.hpp"

namespace millsim::dem {

// Touching pairs waiting for the law, as structure of arrays. 64 pairs: ~16 KB in double, so
// the block stays in L1 between staging, evaluation and booking.
template <class T>
struct alignas(64) PairBlock {
  static constexpr int kSize = 64;
  int i[kSize], j[kSize], slot[kSize];
  // In: d = x_i - x_j, |d|^2, radii, contact masses, v_i - v_j, spins, spring (in and out).
  T dx[kSize], dy[kSize], dz[kSize], dist2[kSize];
  T ri[kSize], rj[kSize], mi[kSize], mj[kSize];
  T dvx[kSize], dvy[kSize], dvz[kSize];
  T wix[kSize], wiy[kSize], wiz[kSize], wjx[kSize], wjy[kSize], wjz[kSize];
  T sx[kSize], sy[kSize], sz[kSize];
  // Out: the force on i, n x F_t and the lever arms (the torques), dissipation rate, elastic energy.
  T fx[kSize], fy[kSize], fz[kSize], tx[kSize], ty[kSize], tz[kSize];
  T ai[kSize], aj[kSize], diss[kSize], elastic[kSize];
  // For a pair hook only: in, whether the spring was empty (the contact begins); out, the
  // normal, the contact point's relative velocity and the tangential force.
  bool begins[kSize];
  T nx[kSize], ny[kSize], nz[kSize], vrx[kSize], vry[kSize], vrz[kSize], ftx[kSize], fty[kSize], ftz[kSize];
};

// The law over the first `count` pairs of the block (the loop the compiler vectorises);
// kHook: keep what a pair hook reads.
template <bool kHook, class T, class Law>
MILLSIM_FORCE_INLINE void evaluatePairBlockLoop(PairBlock<T>& b, int count, const Law& law, T dt) {
  using V = Vec3<T>;
  MILLSIM_VECTORIZE_LOOP
  for (int k = 0; k < count; ++k) {
    V s{b.sx[k], b.sy[k], b.sz[k]};
    const TouchingPair<T> t = touchingPair(law, V{b.dx[k], b.dy[k], b.dz[k]}, b.dist2[k], b.ri[k], b.rj[k], b.mi[k],
                                           b.mj[k], V{b.dvx[k], b.dvy[k], b.dvz[k]}, V{b.wix[k], b.wiy[k], b.wiz[k]},
                                           V{b.wjx[k], b.wjy[k], b.wjz[k]}, s, dt);
    b.sx[k] = s.x;
    b.sy[k] = s.y;
    b.sz[k] = s.z;
    b.fx[k] = t.c.force.x;
    b.fy[k] = t.c.force.y;
    b.fz[k] = t.c.force.z;
    b.tx[k] = t.nxft.x;
    b.ty[k] = t.nxft.y;
    b.tz[k] = t.nxft.z;
    b.ai[k] = t.ai;
    b.aj[k] = t.aj;
    b.diss[k] = t.c.dissipation_rate;
    b.elastic[k] = t.c.elastic_energy;
    if constexpr (kHook) {
      b.nx[k] = t.n.x;
      b.ny[k] = t.n.y;
      b.nz[k] = t.n.z;
      b.vrx[k] = t.v_rel.x;
      b.vry[k] = t.v_rel.y;
      b.vrz[k] = t.v_rel.z;
      b.ftx[k] = t.c.force_t.x;
      b.fty[k] = t.c.force_t.y;
      b.ftz[k] = t.c.force_t.z;
    }
  }
}

// The same loop compiled for AVX2 and for AVX-512 (simd.hpp: same bits at every level;
// tests/unit/test_contact_batch.cpp checks it).
#if defined(MILLSIM_HAVE_SIMD_LEVELS)
template <bool kHook, class T, class Law>
MILLSIM_TARGET_AVX2 void evaluatePairBlockAvx2(PairBlock<T>& b, int count, const Law& law, T dt) {
  evaluatePairBlockLoop<kHook>(b, count, law, dt);
}
template <bool kHook, class T, class Law>
MILLSIM_TARGET_AVX512 void evaluatePairBlockAvx512(PairBlock<T>& b, int count, const Law& law, T dt) {
  evaluatePairBlockLoop<kHook>(b, count, law, dt);
}
#endif

template <bool kHook = false, class T, class Law>
void evaluatePairBlock(PairBlock<T>& b, int count, const Law& law, T dt,
                       backend::SimdLevel level = backend::simdLevel()) {
#if defined(MILLSIM_HAVE_SIMD_LEVELS)
  if (level == backend::SimdLevel::kAvx512) return evaluatePairBlockAvx512<kHook>(b, count, law, dt);
  if (level == backend::SimdLevel::kAvx2) return evaluatePairBlockAvx2<kHook>(b, count, law, dt);
#endif
  (void)level;
  evaluatePairBlockLoop<kHook>(b, count, law, dt);
}

// The evaluated pairs to their springs and to both sides' sums. Entries of one i are
// consecutive, so i's share is summed in registers and booked once per run of entries.
template <class CF, class T>
void bookPairBlock(const CF& cf, const PairBlock<T>& b, int count, T dt) {
  using V = Vec3<T>;
  int cur = -1;
  V f{}, tq{};
  T diss = T(0), elastic = T(0);
  const auto bookCurrent = [&] {
    if (cur < 0) return;
    cf.sink.addOwn(cur, f, tq, diss * dt);
    cf.elastic_out[cur] += elastic;
  };
  for (int k = 0; k < count; ++k) {
    if (b.i[k] != cur) {
      bookCurrent();
      cur = b.i[k];
      f = core::zero3<T>();
      tq = core::zero3<T>();
      diss = elastic = T(0);
    }
    cf.pair_xi[b.slot[k]] = V{b.sx[k], b.sy[k], b.sz[k]};
    const V force{b.fx[k], b.fy[k], b.fz[k]}, nxft{b.tx[k], b.ty[k], b.tz[k]};
    const T half_diss = T(0.5) * b.diss[k];
    f += force;
    tq -= b.ai[k] * nxft;
    diss += half_diss;
    elastic += b.elastic[k];
    // On j: -F, and the torque -aj (n_j x F_t,j) with n_j = -n, F_t,j = -F_t.
    cf.sink.addPartner(b.j[k], -force, -(b.aj[k] * nxft), half_diss * dt);
    if constexpr (CF::kPairHook) {
      const ContactResult<T> c{force, V{b.ftx[k], b.fty[k], b.ftz[k]}, b.diss[k], b.elastic[k]};
      cf.extra.pairContact(b.i[k], V{b.nx[k], b.ny[k], b.nz[k]}, b.ri[k], b.rj[k], b.mi[k],
                           V{b.dvx[k], b.dvy[k], b.dvz[k]}, V{b.wix[k], b.wiy[k], b.wiz[k]},
                           V{b.wjx[k], b.wjy[k], b.wjz[k]}, V{b.vrx[k], b.vry[k], b.vrz[k]}, c, b.begins[k]);
    }
  }
  bookCurrent();
}

// How far ahead in the neighbour list partners are prefetched (8, 16, 32, 64 measured: 16 best).
inline constexpr int kPrefetchSlots = 16;

// ContactForces (cf, with CF::kBatchable) over particles [lo, hi), pairs in blocks.
template <class CF>
void runContactsBatched(const CF& cf, int lo, int hi) {
  using T = std::decay_t<decltype(cf.step)>;
  using V = Vec3<T>;
  const T dt = cf.step;
  const backend::SimdLevel level = backend::simdLevel();
  PairBlock<T> b;
  int count = 0;
  const auto p = cf.p;
  const int last_slot = cf.nbr_start[hi] - 1;  // the prefetch reads no further
  for (int i = lo; i < hi; ++i) {
    // Gravity, walls, external load: booked now; the pairs are added when their block is.
    auto own = cf.startSums(i);
    cf.wallContacts(i, cf.law, dt, own);
    cf.bookOwn(i, dt, own);

    const V xi_pos = p.pos[i], vi = p.vel[i], wi = p.omega[i];
    const T ri = p.radius[i], mi = p.contact_mass[i];
    const int end = cf.nbr_start[i + 1];
    for (int slot = cf.nbr_start[i]; slot < end; ++slot) {
      const int j = cf.nbr_list[slot];
      {
        // The partner a few pairs ahead, into cache while this one is staged: the partners of
        // a particle lie up to a cell layer ahead in memory, and their loads (and the adds to
        // their sums when the block is booked) were the pass's stalls (measured 10%).
        const int ahead = cf.nbr_list[std::min(slot + kPrefetchSlots, last_slot)];
        __builtin_prefetch(&p.pos[ahead]);
        __builtin_prefetch(&p.vel[ahead]);
        __builtin_prefetch(&p.omega[ahead]);
        __builtin_prefetch(&cf.sink.t.force[ahead], 1);
        __builtin_prefetch(&cf.sink.t.torque[ahead], 1);
      }
      const V d = xi_pos - p.pos[j];
      const T rj = p.radius[j];
      const T reach = ri + rj;
      const T dist2 = core::norm2(d);
      if (!pairTouches(dist2, reach)) {
        cf.pair_xi[slot] = core::zero3<T>();  // apart: the spring is released
        continue;
      }
      const V vj = p.vel[j], wj = p.omega[j], s = cf.pair_xi[slot];
      b.i[count] = i;
      b.j[count] = j;
      b.slot[count] = slot;
      b.dx[count] = d.x;
      b.dy[count] = d.y;
      b.dz[count] = d.z;
      b.dist2[count] = dist2;
      b.ri[count] = ri;
      b.rj[count] = rj;
      b.mi[count] = mi;
      b.mj[count] = p.contact_mass[j];
      b.dvx[count] = vi.x - vj.x;
      b.dvy[count] = vi.y - vj.y;
      b.dvz[count] = vi.z - vj.z;
      b.wix[count] = wi.x;
      b.wiy[count] = wi.y;
      b.wiz[count] = wi.z;
      b.wjx[count] = wj.x;
      b.wjy[count] = wj.y;
      b.wjz[count] = wj.z;
      b.sx[count] = s.x;
      b.sy[count] = s.y;
      b.sz[count] = s.z;
      if constexpr (CF::kPairHook) b.begins[count] = s.x == T(0) && s.y == T(0) && s.z == T(0);
      if (++count == PairBlock<T>::kSize) {
        evaluatePairBlock<CF::kPairHook>(b, count, cf.law, dt, level);
        bookPairBlock(cf, b, count, dt);
        count = 0;
      }
    }
  }
  evaluatePairBlock<CF::kPairHook>(b, count, cf.law, dt, level);
  bookPairBlock(cf, b, count, dt);
}

}  // namespace millsim::dem
