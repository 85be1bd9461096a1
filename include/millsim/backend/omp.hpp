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
#ifdef _OPENMP
    const int first = omp_get_thread_num(), stride = omp_get_num_threads();
#else
    const int first = 0, stride = 1;
#endif
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
// so this is O(n + key_count) and needs no comparison sort.
inline void sortByKey(Omp, int* keys, int* values, int n, int key_count, std::vector<int>& scratch) {
  scratch.assign(static_cast<std::size_t>(key_count) + 1 + 2 * static_cast<std::size_t>(n), 0);
  int* count = scratch.data();
  int* out_keys = count + key_count + 1;
  int* out_values = out_keys + n;
  for (int i = 0; i < n; ++i) ++count[keys[i] + 1];
  for (int k = 0; k < key_count; ++k) count[k + 1] += count[k];
  for (int i = 0; i < n; ++i) {
    const int slot = count[keys[i]]++;
    out_keys[slot] = keys[i];
    out_values[slot] = values[i];
  }
  std::copy(out_keys, out_keys + n, keys);
  std::copy(out_values, out_values + n, values);
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
