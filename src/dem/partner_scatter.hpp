#pragma once
// Where the contact loop puts what a pair does to its partner. Each pair is evaluated once, by
// its lower-index particle i (half neighbour list); the force on i stays in registers and the
// reaction on the partner j goes to a "sink":
//   - DirectSink: straight into j's sums. Used when the loop runs on one thread.
//   - ChunkRowsSink: several OpenMP threads, each owning a contiguous chunk of particles: a
//     partner in the thread's own chunk directly, one past its end into a per-thread row array
//     summed afterwards (a variant of LAMMPS's OPENMP-package rows that only reduces the few
//     rows a chunk boundary touches). Deterministic for a given thread count.
//   - AtomicSink (CUDA, src/backend/cuda/partner_scatter_cuda.cuh): atomic adds.
// PartnerScatter<Space, T> picks the sink per execution space and runs the loop; the loop body
// (dem_kernels.hpp) is the same functor for every sink.
#include <algorithm>
#include <type_traits>
#include <vector>

#ifdef _OPENMP
#include <omp.h>
#endif

#include "dem/contact_batch.hpp"
#include "millsim/backend/omp.hpp"
#include "millsim/core/capacity.hpp"
#include "millsim/core/vec3.hpp"

namespace millsim::dem {

using core::Vec3;

// Per-particle sums the contact loop accumulates into (zeroed before the loop).
template <class T>
struct PartnerTargets {
  Vec3<T>* force;
  Vec3<T>* torque;
  double* dissipated;  // J, accumulated over the run
};

template <class T>
struct DirectSink {
  PartnerTargets<T> t;
  MILLSIM_HD void addOwn(int i, Vec3<T> f, Vec3<T> tq, T dissipated) const {
    t.force[i] += f;
    t.torque[i] += tq;
    t.dissipated[i] += double(dissipated);
  }
  MILLSIM_HD void addPartner(int j, Vec3<T> f, Vec3<T> tq, T dissipated) const { addOwn(j, f, tq, dissipated); }
};

template <class T>
struct PartnerRow {
  Vec3<T> force, torque;
  T dissipated;
};

// Several OpenMP threads: thread k owns the contiguous chunk [lo, hi) of particles and writes
// their sums directly. Particles are numbered in cell order, so a partner j > i is nearly always
// in the same chunk: that reaction goes straight to j's sums too (no other thread writes
// there). Only partners past the chunk's end (pairs across the boundary, within a few cell
// layers of it) go to the thread's row array; `touched` records the highest such index so
// the reduction afterwards visits only that window, not every particle.
template <class T>
struct ChunkRowsSink {
  PartnerTargets<T> t;
  PartnerRow<T>* row;  // this thread's window: row[j - hi] for partner j in [hi, highest partner]
  int hi;
  int* touched;  // highest partner index written, -1 for none
  void addOwn(int i, Vec3<T> f, Vec3<T> tq, T dissipated) const { DirectSink<T>{t}.addOwn(i, f, tq, dissipated); }
  void addPartner(int j, Vec3<T> f, Vec3<T> tq, T dissipated) const {
    if (j < hi) {
      DirectSink<T>{t}.addOwn(j, f, tq, dissipated);
      return;
    }
    PartnerRow<T>& r = row[j - hi];
    r.force += f;
    r.torque += tq;
    r.dissipated += dissipated;
    if (j > *touched) *touched = j;
  }
};

// A loop over [lo, hi) on one thread: the contact pass in blocks of pairs where the loop allows
// it (contact_batch.hpp), otherwise, or at SimdLevel::kScalar, one particle at a time.
template <class Loop, class = void>
struct IsBatchable : std::false_type {};
template <class Loop>
struct IsBatchable<Loop, std::void_t<decltype(Loop::kBatchable)>> : std::bool_constant<Loop::kBatchable> {};

template <class Loop>
void runRange(const Loop& loop, int lo, int hi) {
  if constexpr (IsBatchable<Loop>::value) {
    if (backend::simdLevel() != backend::SimdLevel::kScalar) {
      runContactsBatched(loop, lo, hi);
      return;
    }
  }
  for (int i = lo; i < hi; ++i) loop(i);
}

template <class Space, class T>
class PartnerScatter;

template <class T>
class PartnerScatter<backend::Omp, T> {
 public:
  // The half list the next passes run over (after each rebuild): the row windows are sized
  // from it when a pass first needs them.
  void listChanged(const int* start, const int* list) {
    m_start = start;
    m_list = list;
    m_windows_of = -1;
  }

  // make(sink) returns the loop functor for that sink type.
  template <class MakeLoop>
  void run(int n, const PartnerTargets<T>& targets, const MakeLoop& make) {
    int threads = 1;
#ifdef _OPENMP
    if (n >= backend::kOmpParallelThreshold) threads = omp_get_max_threads();
#endif
    if (threads == 1) {
      const auto loop = make(DirectSink<T>{targets});
      runRange(loop, 0, n);
      return;
    }
    const int chunk = (n + threads - 1) / threads;
    sizeWindows(n, threads, chunk);
    m_touched.assign(static_cast<std::size_t>(threads), Touched{});
    backend::forEachChunk(
        backend::Omp{}, threads,
        [&](int k) {
          const int lo = std::min(n, k * chunk), hi = std::min(n, lo + chunk);
          const auto loop = make(ChunkRowsSink<T>{targets, m_rows.data() + m_offset[static_cast<std::size_t>(k)], hi,
                                                  &m_touched[static_cast<std::size_t>(k)].index});
          runRange(loop, lo, hi);
        },
        [](int) {});
    // The rows past each chunk's end into the sums, cleared for the next pass (serial: the
    // windows are a few cell layers long).
    for (int k = 0; k < threads; ++k) {
      PartnerRow<T>* row = m_rows.data() + m_offset[static_cast<std::size_t>(k)];
      const int from = std::min(n, (k + 1) * chunk);
      for (int j = from; j <= m_touched[static_cast<std::size_t>(k)].index; ++j) {
        PartnerRow<T>& r = row[j - from];
        DirectSink<T>{targets}.addOwn(j, r.force, r.torque, r.dissipated);
        r = PartnerRow<T>{};
      }
    }
  }
  std::size_t bytes() const { return m_rows.size() * sizeof(PartnerRow<T>); }

 private:
  struct alignas(64) Touched {  // one cache line per thread: no false sharing in the loop
    int index = -1;
  };

  // Chunk k's window holds the partners past its end, hi .. the highest partner its particles
  // list: in cell order a few cell layers (28 B per particle at 2 threads when each window
  // was n rows long). Without a list (listChanged not called) every window reaches n. Sized
  // once per list and thread count; the rows only grow, so a rebuild allocates only when the
  // windows outgrow every earlier size by more than the quarter kept spare.
  void sizeWindows(int n, int threads, int chunk) {
    if (m_windows_of == threads && m_windows_n == n) return;
    m_offset.assign(static_cast<std::size_t>(threads) + 1, 0);  // same sizes: no allocation
    std::vector<int>& highest = m_highest;
    highest.assign(static_cast<std::size_t>(threads), n - 1);
    if (m_start && m_list) {
#ifdef _OPENMP
#pragma omp parallel for schedule(static) num_threads(threads)
#endif
      for (int k = 0; k < threads; ++k) {
        const int lo = std::min(n, k * chunk), hi = std::min(n, lo + chunk);
        int top = hi - 1;
        for (int e = m_start[lo]; e < m_start[hi]; ++e) top = std::max(top, m_list[e]);
        highest[static_cast<std::size_t>(k)] = top;
      }
    }
    for (int k = 0; k < threads; ++k) {
      const int hi = std::min(n, (k + 1) * chunk);
      const std::size_t rows = static_cast<std::size_t>(std::max(0, highest[static_cast<std::size_t>(k)] - hi + 1));
      m_offset[static_cast<std::size_t>(k) + 1] = m_offset[static_cast<std::size_t>(k)] + rows;
    }
    // With room to spare, as the neighbour list (core::withSpare).
    const std::size_t need = m_offset.back();
    if (m_rows.size() < need) m_rows.assign(core::withSpare(need), PartnerRow<T>{});
    m_windows_of = threads;
    m_windows_n = n;
  }

  std::vector<PartnerRow<T>> m_rows;
  std::vector<std::size_t> m_offset;  // chunk k's window starts at m_rows[m_offset[k]]
  std::vector<int> m_highest;         // per chunk: the highest partner it lists
  std::vector<Touched> m_touched;
  const int* m_start = nullptr;
  const int* m_list = nullptr;
  int m_windows_of = -1;  // thread count the windows were sized for (-1: not sized for this list)
  int m_windows_n = -1;
};

}  // namespace millsim::dem
