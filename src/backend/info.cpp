#include "millsim/backend/info.hpp"

#include <omp.h>

namespace millsim::backend {

int ompMaxThreads() { return omp_get_max_threads(); }

std::string resolvedBackend(const std::string& backend) {
  if (backend != "auto") return backend;
  return cudaCompiled() && cudaDevices() > 0 ? "cuda" : "omp";
}

#if !defined(MILLSIM_HAVE_CUDA)
bool cudaCompiled() { return false; }
int cudaDevices() { return 0; }
std::string cudaDeviceName() { return ""; }
std::string cudaStatus() { return "built without CUDA"; }
bool selectCudaDevice(int) { return false; }
#endif

}  // namespace millsim::backend
