#pragma once
// Where the pair-once SPH loop (SphPairInteraction, sph_kernels.hpp) puts a partner's share of
// a pair, on the host. The particles are numbered fluid first, then walls and bodies, each part
// in cell order; only fluid particles evaluate pairs, and a fluid partner always has a higher
// number than the evaluating particle.
//   - SphDirectSink: straight into the partner's sums (one thread).
//   - SphChunkSink: several OpenMP threads. Thread k owns a contiguous chunk [lo, hi) of the
//     fluid, which it evaluates, and the walls in the same range of cells, [own_lo, own_hi):
//     it writes their sums directly. A partner it does not own (in the next chunk's cells, a
//     few cell layers away at most: the search block) goes into the thread's rows, which
//     cover only that window: fluid [hi, fluid_hi), walls [wall_lo, own_lo) and
//     [own_hi, wall_hi). After the pass each thread adds the rows (all threads', in thread
//     order) that fall into what it owns. Each particle's sums are so written by one thread at
//     a time, and the result is the same for a given thread count.
// The same idea as the DEM's partner scatter (src/dem/partner_scatter.hpp).
#include <algorithm>
#include <cstddef>
#include <vector>

#include "millsim/core/capacity.hpp"

#ifdef _OPENMP
#include <omp.h>
#endif

#include "millsim/backend/omp.hpp"
#include "millsim/neighbors/cell_grid.hpp"
#include "sph/sph_kernels.hpp"
#include "sph/sph_pair_batch.hpp"

namespace millsim::sph {

// Adds a pair share to particle i's sums (the viscous speed is the evaluating side's alone).
template <class T, bool kShift, bool kStrain>
MILLSIM_FORCE_INLINE void addShare(const SphView<T>& p, int i, const PairSums<T>& s) {
  p.drho[i] += s.drho;
  p.ace[i] += s.acc;
  if constexpr (kShift) {
    p.shift_grad[i] += s.grad_c;
    p.shift_div[i] += s.div_r;
  }
  if constexpr (kStrain) p.strain[i] += s.strain;
}

template <class T, bool kShift, bool kStrain>
struct SphDirectSink {
  SphView<T> p;
  MILLSIM_FORCE_INLINE void addOwn(int a, const PairSums<T>& s) const {
    p.visc_dt[a] = s.visc_max;
    addShare<T, kShift, kStrain>(p, a, s);
  }
  MILLSIM_FORCE_INLINE void addPartner(int b, const PairSums<T>& s) const { addShare<T, kShift, kStrain>(p, b, s); }
};

template <class T, bool kShift, bool kStrain>
struct SphChunkSink {
  SphView<T> p;
  PairSums<T>* rows;  // fluid [hi, fluid_hi), walls [wall_lo, own_lo), walls [own_hi, wall_hi)
  int hi, fluid_end;
  int own_lo, own_hi;
  int wall_lo, fluid_rows, below_rows;
  MILLSIM_FORCE_INLINE void addOwn(int a, const PairSums<T>& s) const {
    SphDirectSink<T, kShift, kStrain>{p}.addOwn(a, s);
  }
  MILLSIM_FORCE_INLINE void addPartner(int b, const PairSums<T>& s) const {
    // Fluid partners are above a >= lo; walls are numbered after all fluid.
    if (b < hi || (b >= own_lo && b < own_hi)) {
      addShare<T, kShift, kStrain>(p, b, s);
      return;
    }
    const int row = b < fluid_end ? b - hi
                    : b < own_lo  ? fluid_rows + (b - wall_lo)
                                  : fluid_rows + below_rows + (b - own_hi);
    addPairSums<T, kShift, kStrain>(rows[row], s);
  }
};

template <class T>
class SphPairScatter {
 public:
  // Runs make(sink)(a) for every fluid particle a (in blocks of pairs: sph_pair_batch.hpp), the
  // sink chosen by the thread count. fluid, walls: the cell list's two segments, which the loop
  // searches (their blocks of cells bound the partners' numbers).
  template <bool kShift, bool kStrain, class MakeLoop>
  void run(const neighbors::CellListView<T>& fluid, const neighbors::CellListView<T>& walls, const Vec3<T>* pos,
           const SphView<T>& p, const MakeLoop& make) {
    const int fluid_end = fluid.cell_end[fluid.grid.cellCount() - 1];
    int threads = 1;
#ifdef _OPENMP
    if (fluid_end >= backend::kOmpParallelThreshold) threads = omp_get_max_threads();
#endif
    if (threads == 1) {
      runSphPairRange(make(SphDirectSink<T, kShift, kStrain>{p}), 0, fluid_end);
      return;
    }
    if (static_cast<int>(m_chunks.size()) != threads) {
      m_chunks.assign(static_cast<std::size_t>(threads), Chunk{});
      m_rows.assign(static_cast<std::size_t>(threads), {});
    }
    window(threads, fluid, walls, fluid_end, pos);
    backend::forEachChunk(
        backend::Omp{}, threads,
        [&](int k) {
          const Chunk& c = m_chunks[static_cast<std::size_t>(k)];
          const auto loop = make(SphChunkSink<T, kShift, kStrain>{p, m_rows[static_cast<std::size_t>(k)].data(), c.hi,
                                                                  fluid_end, c.own_lo, c.own_hi, c.wall_lo,
                                                                  c.fluid_hi - c.hi, c.own_lo - c.wall_lo});
          runSphPairRange(loop, c.lo, c.hi);
        },
        [&](int k) { gatherRows<kShift, kStrain>(k, p); });
  }

  std::size_t bytes() const {
    std::size_t b = 0;
    for (const auto& r : m_rows) b += r.capacity() * sizeof(PairSums<T>);
    return b;
  }

 private:
  struct Chunk {
    int lo = 0, hi = 0;            // the fluid it evaluates (and owns)
    int own_lo = 0, own_hi = 0;    // the walls it owns: those in the cells of its fluid
    int fluid_hi = 0;              // its fluid partners past hi: [hi, fluid_hi)
    int wall_lo = 0, wall_hi = 0;  // all its wall partners: [wall_lo, wall_hi)
  };

  // Fluid chunks of equal length, the walls in the same cells, and the windows their searches
  // can reach: a search block spans `reach` cells each way, i.e. keys within +-span of the
  // particle's cell.
  void window(int threads, const neighbors::CellListView<T>& fluid, const neighbors::CellListView<T>& walls,
              int fluid_end, const Vec3<T>* pos) {
    const neighbors::CellGrid<T>& g = fluid.grid;
    const int r = g.reach;
    const int span = (g.nz > 1 ? r * g.nx * g.ny : 0) + r * g.nx + r;
    const int cells = g.cellCount();
    const int chunk = (fluid_end + threads - 1) / threads;
    // First cell of chunk k's walls: the cell of its first fluid particle (0 for the first
    // chunk, the grid's end for none).
    auto first_cell = [&](int k) {
      const int lo = k * chunk;
      return k == 0 ? 0 : lo >= fluid_end ? cells : g.cellOf(pos[lo]);
    };
    for (int k = 0; k < threads; ++k) {
      Chunk& c = m_chunks[static_cast<std::size_t>(k)];
      c.lo = std::min(fluid_end, k * chunk);
      c.hi = std::min(fluid_end, c.lo + chunk);
      c.own_lo = walls.cell_start[first_cell(k)];  // cell_start[cells] is the walls' end
      c.own_hi = walls.cell_start[first_cell(k + 1)];
      c.fluid_hi = c.hi;
      c.wall_lo = c.own_lo;
      c.wall_hi = c.own_hi;
      if (c.hi > c.lo) {
        const int k_lo = std::max(0, g.cellOf(pos[c.lo]) - span);
        const int k_hi = std::min(cells - 1, g.cellOf(pos[c.hi - 1]) + span);
        c.fluid_hi = std::max(c.hi, fluid.cell_end[k_hi]);
        c.wall_lo = std::min(c.own_lo, walls.cell_start[k_lo]);
        c.wall_hi = std::max(c.own_hi, walls.cell_end[k_hi]);
      }
      std::vector<PairSums<T>>& rows = m_rows[static_cast<std::size_t>(k)];
      const std::size_t need =
          static_cast<std::size_t>((c.fluid_hi - c.hi) + (c.own_lo - c.wall_lo) + (c.wall_hi - c.own_hi));
      // Grows only, with room to spare as the neighbour lists do (core::withSpare): the windows
      // change at every pass as the fluid moves, and an exact fit would allocate each time one
      // grew by a row. Kept zero between passes.
      if (rows.size() < need) rows.resize(core::withSpare(need), PairSums<T>{});
    }
  }

  // Adds every other thread's rows that fall into what thread k owns (its fluid chunk and its
  // walls) to those particles' sums, and clears them.
  template <bool kShift, bool kStrain>
  void gatherRows(int k, const SphView<T>& p) {
    const Chunk& own = m_chunks[static_cast<std::size_t>(k)];
    for (std::size_t m = 0; m < m_chunks.size(); ++m) {
      const Chunk& c = m_chunks[m];
      PairSums<T>* rows = m_rows[m].data();
      auto take = [&](int from, int to, int lo, int hi, int offset) {
        for (int j = std::max(from, lo); j < std::min(to, hi); ++j) {
          PairSums<T>& r = rows[j - offset];
          addShare<T, kShift, kStrain>(p, j, r);
          r = PairSums<T>{};
        }
      };
      const int fluid_rows = c.fluid_hi - c.hi, below_rows = c.own_lo - c.wall_lo;
      take(c.hi, c.fluid_hi, own.lo, own.hi, c.hi);
      take(c.wall_lo, c.own_lo, own.own_lo, own.own_hi, c.wall_lo - fluid_rows);
      take(c.own_hi, c.wall_hi, own.own_lo, own.own_hi, c.own_hi - fluid_rows - below_rows);
    }
  }

  std::vector<Chunk> m_chunks;
  std::vector<std::vector<PairSums<T>>> m_rows;
};

}  // namespace millsim::sph
