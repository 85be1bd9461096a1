#pragma once
// OpenMP execution space. Together with cuda.cuh this is the only place that knows how loop
// indices are handed out; the loop bodies are MILLSIM_HD functors shared with the CUDA kernels.
#include <algorithm>
#include <cstddef>
#include <numeric>
#include <utility>
#include <vector>

#ifdef _OPENMP
#include <omp.h>
#endif

#include "millsim/backend/reduce_ops.hpp"

namespace millsim::backend {

struct Omp {
  static constexpr const char* kName = "omp";
};

// Below this many indices a loop runs on one thread: a lab drum has ~200-400 balls, where the
// fork/join of a parallel region costs more than the loop (and oversubscribed spinning threads
// cost far more).
inline constexpr int kOmpParallelThreshold = 2048;

// Owning array in the execution space's memory (host memory for OpenMP).
template <class Space, class T>
class Array;

template <class T>
class Array<Omp, T> {
 public:
  Array() = default;
  explicit Array(std::size_t n, T fill = T{}) : m_data(n, fill) {}
  void resize(std::size_t n, T fill = T{}) { m_data.assign(n, fill); }
  std::size_t size() const { return m_data.size(); }
  std::size_t bytes() const { return m_data.size() * sizeof(T); }
  T* data() { return m_data.data(); }
  const T* data() const { return m_data.data(); }
  void copyFromHost(const std::vector<T>& src) { m_data = src; }
  void copyToHost(std::vector<T>& dst) const { dst = m_data; }
  void fill(T value) { std::fill(m_data.begin(), m_data.end(), value); }
  void swap(Array& other) noexcept { m_data.swap(other.m_data); }

 private:
  std::vector<T> m_data;
};

// The calling thread's number in its team and the team's size (0 and 1 outside a parallel
// region or without OpenMP).
struct TeamSeat {
  int thread, team;
};
inline TeamSeat teamSeat() {
#ifdef _OPENMP
  return {omp_get_thread_num(), omp_get_num_threads()};
#else
  return {0, 1};
#endif
}

// Runs chunk(k) for every k in [0, chunks) on a team of `chunks` threads, chunk k by team member
// k (and k + team size, ... should OpenMP give fewer threads than asked, e.g. with OMP_DYNAMIC):
// every chunk is done once, whatever the team. Then, after a barrier, after(k) for every k the
// same way (a pass that reads what all chunks wrote).
template <class Chunk, class After>
void forEachChunk(Omp, int chunks, const Chunk& chunk, const After& after) {
#ifdef _OPENMP
#pragma omp parallel num_threads(chunks)
#endif
  {
    const TeamSeat seat = teamSeat();
    const int first = seat.thread, stride = seat.team;
    for (int k = first; k < chunks; k += stride) chunk(k);
#ifdef _OPENMP
#pragma omp barrier
#endif
    for (int k = first; k < chunks; k += stride) after(k);
  }
}

template <class F>
void parallelFor(Omp, int n, const F& f) {
#pragma omp parallel for schedule(static) if (n >= kOmpParallelThreshold)
  for (int i = 0; i < n; ++i) f(i);
}

// parallelFor over n items that hold `work` inner iterations between them (bodies, each summing
// its particles): the threshold applies to the work, so a few hundred balls with a hundred shell
// particles each are shared out. Other spaces: their parallelFor (found by ADL).
template <class F>
void parallelForWork(Omp, int n, long long work, const F& f) {
#pragma omp parallel for schedule(static) if (work >= kOmpParallelThreshold && n > 1)
  for (int i = 0; i < n; ++i) f(i);
}
template <class Space, class F>
void parallelForWork(Space space, int n, long long /*work*/, const F& f) {
  parallelFor(space, n, f);
}

// Sum of f(i) over [0, n). Accumulated in the result type (double for energies).
template <class R, class F>
R reduceSum(Omp, int n, const F& f) {
  R total = R(0);
#pragma omp parallel for schedule(static) reduction(+ : total) if (n >= kOmpParallelThreshold)
  for (int i = 0; i < n; ++i) total += f(i);
  return total;
}

// Largest f(i) and init; NaN if any f(i) is NaN (MaxKeepNan, as on CUDA).
template <class R, class F>
R reduceMax(Omp, int n, R init, const F& f) {
  constexpr MaxKeepNan op{};
  R best = init;
  if (n < kOmpParallelThreshold) {
    for (int i = 0; i < n; ++i) best = op(best, f(i));
    return best;
  }
#pragma omp parallel
  {
    R local = init;
#pragma omp for schedule(static) nowait
    for (int i = 0; i < n; ++i) local = op(local, f(i));
#pragma omp critical(millsim_reduce_max)
    best = op(best, local);
  }
  return best;
}

// Stable sort of (key, value) pairs by key. Counting sort: keys are cell indices in [0, key_count),
// so this is O(n + key_count) and needs no comparison sort. On T threads thread t counts its
// contiguous part of the input in its own row, each thread turns a range of keys into offsets
// (key by key, thread rows in order), and thread t scatters its part from its row: equal keys
// keep their input order, so the result is the serial sort's, whatever T. Each thread still
// walks all key_count entries of its row (clear, offsets), so the threads only pay off where
// the keys are no more than the pairs: an SPH grid (several particles per cell), not a DEM grid
// of a drum's bounding box (~0.1 balls per cell), which sorts on one thread.
// scratch: the sorted keys and values (n each), T rows of key_count counts, T range totals.
inline void sortByKey(Omp, int* keys, int* values, int n, int key_count, std::vector<int>& scratch) {
  int threads = 1;
#ifdef _OPENMP
  if (n >= kOmpParallelThreshold && key_count <= n) threads = omp_get_max_threads();
#endif
  const std::size_t row_ints = static_cast<std::size_t>(threads) * static_cast<std::size_t>(key_count);
  const std::size_t need = 2 * static_cast<std::size_t>(n) + row_ints + static_cast<std::size_t>(threads);
  if (scratch.size() < need) scratch.resize(need);  // grows only: no allocation once sized
  int* out_keys = scratch.data();
  int* out_values = out_keys + n;
  int* rows = out_values + n;
  int* range_total = rows + row_ints;
#ifdef _OPENMP
#pragma omp parallel num_threads(threads) if (threads > 1)
#endif
  {
    const TeamSeat seat = teamSeat();
    const int t = seat.thread, team = seat.team;
    // Input part and key range of team member t (team may be smaller than threads: OMP_DYNAMIC).
    const auto part = [](int total, int parts, int k) {
      return static_cast<int>(static_cast<long long>(total) * k / parts);
    };
    const int i0 = part(n, team, t), i1 = part(n, team, t + 1);
    const int k0 = part(key_count, team, t), k1 = part(key_count, team, t + 1);
    int* own = rows + static_cast<std::size_t>(t) * key_count;
    std::fill(own, own + key_count, 0);
    for (int i = i0; i < i1; ++i) ++own[keys[i]];
#ifdef _OPENMP
#pragma omp barrier
#endif
    int running = 0;
    for (int k = k0; k < k1; ++k) {
      for (int r = 0; r < team; ++r) {
        int& c = rows[static_cast<std::size_t>(r) * key_count + k];
        const int count = c;
        c = running;
        running += count;
      }
    }
    range_total[t] = running;
#ifdef _OPENMP
#pragma omp barrier
#endif
    int base = 0;
    for (int r = 0; r < t; ++r) base += range_total[r];
    for (int r = 0; r < team && base != 0; ++r) {
      int* row = rows + static_cast<std::size_t>(r) * key_count;
      for (int k = k0; k < k1; ++k) row[k] += base;
    }
#ifdef _OPENMP
#pragma omp barrier
#endif
    for (int i = i0; i < i1; ++i) {
      const int slot = own[keys[i]]++;
      out_keys[slot] = keys[i];
      out_values[slot] = values[i];
    }
#ifdef _OPENMP
#pragma omp barrier
#endif
    std::copy(out_keys + i0, out_keys + i1, keys + i0);
    std::copy(out_values + i0, out_values + i1, values + i0);
  }
}

// out[i] = in[0] + .. + in[i - 1] for i in [0, n]; returns the total out[n]. Serial: it runs at
// neighbour rebuilds only, on one int per particle.
inline int exclusiveScan(Omp, const int* in, int* out, int n) {
  int total = 0;
  for (int i = 0; i < n; ++i) {
    const int v = in[i];
    out[i] = total;
    total += v;
  }
  out[n] = total;
  return total;
}

inline void synchronize(Omp) {}

}  // namespace millsim::backend
