#include <cuda_runtime.h>

#include "millsim/backend/info.hpp"

namespace millsim::backend {

bool cudaCompiled() { return true; }

int cudaDevices() {
  int count = 0;
  if (cudaGetDeviceCount(&count) != cudaSuccess) return 0;
  return count;
}

bool selectCudaDevice(int index) {
  const int count = cudaDevices();
  if (count == 0 || index < 0) return false;
  return cudaSetDevice(index % count) == cudaSuccess;
}

std::string cudaDeviceName() {
  if (cudaDevices() == 0) return "";
  cudaDeviceProp prop{};
  if (cudaGetDeviceProperties(&prop, 0) != cudaSuccess) return "";
  return prop.name;
}

}  // namespace millsim::backend
