#pragma once
// CUDA side of dem/partner_scatter.hpp: one thread per particle, the partner's share (and, since
// a partner may add to it concurrently, the particle's own sums too) by atomic adds.
#include "dem/partner_scatter.hpp"
#include "millsim/backend/cuda.cuh"

namespace millsim::dem {

template <class T>
struct AtomicSink {
  PartnerTargets<T> t;
  // Host-and-device so the shared loop body compiles for both sides; only the device runs it.
  template <class U>
  MILLSIM_HD static void add(U* a, U b) {
#ifdef __CUDA_ARCH__
    atomicAdd(a, b);
#else
    *a += b;
#endif
  }
  MILLSIM_HD static void add3(Vec3<T>& a, Vec3<T> b) {
    add(&a.x, b.x);
    add(&a.y, b.y);
    add(&a.z, b.z);
  }
  MILLSIM_HD void addOwn(int i, Vec3<T> f, Vec3<T> tq, T dissipated) const {
    add3(t.force[i], f);
    add3(t.torque[i], tq);
    add(&t.dissipated[i], double(dissipated));
  }
  MILLSIM_HD void addPartner(int j, Vec3<T> f, Vec3<T> tq, T dissipated) const { addOwn(j, f, tq, dissipated); }
};

template <class T>
class PartnerScatter<backend::Cuda, T> {
 public:
  void listChanged(const int*, const int*) {}  // atomics need no rows
  template <class MakeLoop>
  void run(int n, const PartnerTargets<T>& targets, const MakeLoop& make) {
    backend::parallelFor(backend::Cuda{}, n, make(AtomicSink<T>{targets}));
  }
  std::size_t bytes() const { return 0; }
};

}  // namespace millsim::dem
