#pragma once
// CUDA execution space: owning device arrays, a generic kernel that calls the same MILLSIM_HD
// functors as the OpenMP loop, reductions and sort-by-key through Thrust. Only .cu files include
// this header.
#include <cuda_runtime.h>
#include <thrust/binary_search.h>
#include <thrust/device_ptr.h>
#include <thrust/execution_policy.h>
#include <thrust/functional.h>
#include <thrust/iterator/counting_iterator.h>
#include <thrust/scan.h>
#include <thrust/sort.h>
#include <thrust/system/cuda/execution_policy.h>
#include <thrust/transform_reduce.h>

#include <cstddef>
#include <cstdlib>
#include <cstring>
#include <map>
#include <stdexcept>
#include <string>
#include <typeinfo>
#include <utility>
#include <vector>

#include "millsim/backend/omp.hpp"

namespace millsim::backend {

struct Cuda {
  static constexpr const char* kName = "cuda";
};

inline void cudaCheck(cudaError_t err, const char* what) {
  if (err != cudaSuccess)
    throw std::runtime_error(std::string("CUDA error in ") + what + ": " + cudaGetErrorString(err));
}

template <class T>
class Array<Cuda, T> {
 public:
  Array() = default;
  explicit Array(std::size_t n, T fill = T{}) { resize(n, fill); }
  Array(const Array&) = delete;
  Array& operator=(const Array&) = delete;
  ~Array() { release(); }
  void resize(std::size_t n, T fill = T{}) {
    release();
    m_size = n;
    if (n) cudaCheck(cudaMalloc(&m_ptr, n * sizeof(T)), "cudaMalloc");
    this->fill(fill);
  }
  std::size_t size() const { return m_size; }
  std::size_t bytes() const { return m_size * sizeof(T); }
  T* data() { return m_ptr; }
  const T* data() const { return m_ptr; }
  void copyFromHost(const std::vector<T>& src) {
    if (src.size() != m_size) {
      release();
      m_size = src.size();
      if (m_size) cudaCheck(cudaMalloc(&m_ptr, m_size * sizeof(T)), "cudaMalloc");
    }
    if (m_size) cudaCheck(cudaMemcpy(m_ptr, src.data(), m_size * sizeof(T), cudaMemcpyHostToDevice), "copy to device");
  }
  void copyToHost(std::vector<T>& dst) const {
    dst.resize(m_size);
    if (m_size) cudaCheck(cudaMemcpy(dst.data(), m_ptr, m_size * sizeof(T), cudaMemcpyDeviceToHost), "copy to host");
  }
  // A value whose bytes are all zero (every T{} the solvers use) is set on the device; anything
  // else goes through a host copy (a 1e7-particle grid's offsets would be 0.5 GB of it).
  void fill(T value) {
    if (!m_size) return;
    unsigned char bytes[sizeof(T)];
    std::memcpy(bytes, &value, sizeof(T));
    bool zero = true;
    for (unsigned char b : bytes) zero = zero && b == 0;
    if (zero)
      cudaCheck(cudaMemset(m_ptr, 0, m_size * sizeof(T)), "cudaMemset");
    else
      copyFromHost(std::vector<T>(m_size, value));
  }
  void swap(Array& other) noexcept {
    std::swap(m_ptr, other.m_ptr);
    std::swap(m_size, other.m_size);
  }

 private:
  void release() {
    if (m_ptr) cudaFree(m_ptr);
    m_ptr = nullptr;
    m_size = 0;
  }
  T* m_ptr = nullptr;
  std::size_t m_size = 0;
};

template <class F>
__global__ void forEachIndexKernel(int n, F f) {
  const int i = blockIdx.x * blockDim.x + threadIdx.x;
  if (i < n) f(i);
}

// MILLSIM_CUDA_SYNC=1: every launch is waited for and checked, so a fault inside a kernel is
// reported with that kernel's functor instead of at the next copy or reduction (slower; for a
// first run on a new device or a hunt).
inline bool cudaSyncEveryLaunch() {
  static const bool on = [] {
    const char* env = std::getenv("MILLSIM_CUDA_SYNC");
    return env && std::string(env) == "1";
  }();
  return on;
}

template <class F>
void parallelFor(Cuda, int n, const F& f) {
  if (n <= 0) return;
  constexpr int kBlock = 128;
  forEachIndexKernel<<<(n + kBlock - 1) / kBlock, kBlock>>>(n, f);
  cudaCheck(cudaGetLastError(), "kernel launch");
  if (cudaSyncEveryLaunch()) cudaCheck(cudaDeviceSynchronize(), typeid(F).name());
}

// Thrust's temporary storage (the reductions' partial sums, the sort's and the scan's buffers)
// from a cache: without it every call is a cudaMalloc and a cudaFree, each synchronising the
// device, several times per step. A freed block goes back to the cache and serves the next
// request of at most its size; nothing is returned to the device until exit. One host thread
// drives the device (the solvers call thrust from the step loop only).
class ThrustTempCache {
 public:
  using value_type = char;
  ThrustTempCache() = default;
  ThrustTempCache(const ThrustTempCache&) = delete;
  ThrustTempCache& operator=(const ThrustTempCache&) = delete;
  ~ThrustTempCache() {
    for (auto& block : m_free) cudaFree(block.second);  // at exit; errors (context gone) ignored
    for (auto& block : m_used) cudaFree(block.first);
  }
  char* allocate(std::ptrdiff_t n) {
    auto it = m_free.lower_bound(n);  // the smallest free block that is large enough
    char* p = nullptr;
    if (it != m_free.end()) {
      p = it->second;
      n = it->first;
      m_free.erase(it);
    } else {
      cudaCheck(cudaMalloc(&p, static_cast<std::size_t>(n)), "thrust temporary storage");
    }
    m_used.emplace(p, n);
    return p;
  }
  void deallocate(char* p, std::size_t) {
    auto it = m_used.find(p);
    if (it == m_used.end()) return;
    m_free.emplace(it->second, p);
    m_used.erase(it);
  }

 private:
  std::multimap<std::ptrdiff_t, char*> m_free;  // size -> block
  std::map<char*, std::ptrdiff_t> m_used;       // block -> size
};

inline ThrustTempCache& thrustTempCache() {
  static ThrustTempCache cache;
  return cache;
}

// The execution policy of every thrust call: the device, temporaries from the cache.
inline auto thrustPolicy() { return thrust::cuda::par(thrustTempCache()); }

template <class R, class F>
R reduceSum(Cuda, int n, const F& f) {
  return thrust::transform_reduce(thrustPolicy(), thrust::counting_iterator<int>(0), thrust::counting_iterator<int>(n),
                                  f, R(0), thrust::plus<R>());
}

template <class R, class F>
R reduceMax(Cuda, int n, R init, const F& f) {
  return thrust::transform_reduce(thrustPolicy(), thrust::counting_iterator<int>(0), thrust::counting_iterator<int>(n),
                                  f, init, MaxKeepNan());
}

inline void sortByKey(Cuda, int* keys, int* values, int n, int /*key_count*/, std::vector<int>& /*scratch*/) {
  thrust::stable_sort_by_key(thrustPolicy(), keys, keys + n, values);
}

// Cell offsets of sorted keys (neighbors/cell_list.hpp): offsets[k] = first slot whose key is
// >= k, for k in [0, cells], one binary search per cell; the generic version writes each run of
// empty cells from one thread, which on a GPU serialises a sparse grid's margins.
inline void cellOffsets(Cuda, const int* sorted_keys, int n, int cells, int* offsets) {
  thrust::lower_bound(thrustPolicy(), sorted_keys, sorted_keys + n, thrust::counting_iterator<int>(0),
                      thrust::counting_iterator<int>(cells + 1), offsets);
  cudaCheck(cudaGetLastError(), "cell offsets");
}

// out[i] = in[0] + .. + in[i - 1] for i in [0, n]; returns the total out[n].
inline int exclusiveScan(Cuda, const int* in, int* out, int n) {
  int total = 0;
  if (n > 0) {
    thrust::exclusive_scan(thrustPolicy(), in, in + n, out);
    int last[2];
    cudaCheck(cudaMemcpy(&last[0], out + n - 1, sizeof(int), cudaMemcpyDeviceToHost), "scan total");
    cudaCheck(cudaMemcpy(&last[1], in + n - 1, sizeof(int), cudaMemcpyDeviceToHost), "scan total");
    total = last[0] + last[1];
  }
  cudaCheck(cudaMemcpy(out + n, &total, sizeof(int), cudaMemcpyHostToDevice), "scan total");
  return total;
}

inline void synchronize(Cuda) { cudaCheck(cudaDeviceSynchronize(), "synchronize"); }

// Number of CUDA devices; 0 when the driver or a device is missing (tests skip then).
inline int cudaDeviceCount() {
  int count = 0;
  if (cudaGetDeviceCount(&count) != cudaSuccess) return 0;
  return count;
}

}  // namespace millsim::backend
