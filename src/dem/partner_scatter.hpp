#pragma once
// Where the contact loop puts what a pair does to its partner. Each pair is evaluated once, by
// its lower-index particle i (half neighbour list); the force on i stays in registers and the
// reaction on the partner j goes to a "sink":
//   - DirectSink: straight into j's sums. Used when the loop runs on one thread.
//   - ThreadRowsSink: into a per-thread row array, summed into the particles afterwards (the
//     scheme of LAMMPS's OPENMP package). Deterministic for a given thread count.
//   - AtomicSink (CUDA, src/backend/cuda/partner_scatter_cuda.cuh): atomic adds.
// PartnerScatter<Space, T> picks the sink per execution space and runs the loop; the loop body
// (dem_kernels.hpp) is the same functor for every sink.
#include <vector>

#ifdef _OPENMP
#include <omp.h>
#endif

#include "millsim/backend/omp.hpp"
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

// The loop hands out particles to threads; a thread writes its own particles' sums directly (no
// other thread owns them) and partners' shares into its own row array.
template <class T>
struct ThreadRowsSink {
  PartnerTargets<T> t;
  PartnerRow<T>* rows;  // threads x n
  int n;
  void addOwn(int i, Vec3<T> f, Vec3<T> tq, T dissipated) const { DirectSink<T>{t}.addOwn(i, f, tq, dissipated); }
  void addPartner(int j, Vec3<T> f, Vec3<T> tq, T dissipated) const {
#ifdef _OPENMP
    PartnerRow<T>& r = rows[static_cast<std::size_t>(omp_get_thread_num()) * n + j];
#else
    PartnerRow<T>& r = rows[j];
#endif
    r.force += f;
    r.torque += tq;
    r.dissipated += dissipated;
  }
};

// Adds every thread's row for particle i into its sums and clears the rows for the next step.
template <class T>
struct ReduceThreadRows {
  PartnerTargets<T> t;
  PartnerRow<T>* rows;
  int n, threads;
  void operator()(int i) const {
    for (int k = 0; k < threads; ++k) {
      PartnerRow<T>& r = rows[static_cast<std::size_t>(k) * n + i];
      DirectSink<T>{t}.addOwn(i, r.force, r.torque, r.dissipated);
      r = PartnerRow<T>{};
    }
  }
};

template <class Space, class T>
class PartnerScatter;

template <class T>
class PartnerScatter<backend::Omp, T> {
 public:
  // make(sink) returns the loop functor for that sink type.
  template <class MakeLoop>
  void run(int n, const PartnerTargets<T>& targets, const MakeLoop& make) {
    int threads = 1;
#ifdef _OPENMP
    if (n >= backend::kOmpParallelThreshold) threads = omp_get_max_threads();
#endif
    if (threads == 1) {
      const auto loop = make(DirectSink<T>{targets});
      for (int i = 0; i < n; ++i) loop(i);
      return;
    }
    const std::size_t rows = static_cast<std::size_t>(threads) * n;
    if (m_rows.size() != rows) m_rows.assign(rows, PartnerRow<T>{});  // only when n or threads change
    backend::parallelFor(backend::Omp{}, n, make(ThreadRowsSink<T>{targets, m_rows.data(), n}));
    backend::parallelFor(backend::Omp{}, n, ReduceThreadRows<T>{targets, m_rows.data(), n, threads});
  }
  std::size_t bytes() const { return m_rows.size() * sizeof(PartnerRow<T>); }

 private:
  std::vector<PartnerRow<T>> m_rows;
};

}  // namespace millsim::dem
