#include <cuda_runtime.h>

#include "millsim/backend/info.hpp"

namespace millsim::backend {

bool cudaCompiled() { return true; }

int cudaDevices() {
  int count = 0;
  if (cudaGetDeviceCount(&count) != cudaSuccess) return 0;
  return count;
}

std::string cudaDeviceName() {
  if (cudaDevices() == 0) return "";
  cudaDeviceProp prop{};
  if (cudaGetDeviceProperties(&prop, 0) != cudaSuccess) return "";
  return prop.name;
}

}  // namespace millsim::backend
