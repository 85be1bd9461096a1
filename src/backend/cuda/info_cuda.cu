#include <cuda_runtime.h>

#include <string>

#include "millsim/backend/info.hpp"

namespace millsim::backend {

bool cudaCompiled() { return true; }

int cudaDevices() {
  int count = 0;
  if (cudaGetDeviceCount(&count) != cudaSuccess) return 0;
  return count;
}

std::string cudaStatus() {
  int count = 0;
  const cudaError_t err = cudaGetDeviceCount(&count);
  if (err != cudaSuccess) return cudaGetErrorString(err);
  return std::to_string(count) + " device(s)";
}

bool selectCudaDevice(int index) {
  const int count = cudaDevices();
  if (count == 0 || index < 0) return false;
  return cudaSetDevice(index % count) == cudaSuccess;
}

std::string cudaDeviceName() {
  if (cudaDevices() == 0) return "";
  int device = 0;
  if (cudaGetDevice(&device) != cudaSuccess) return "";
  cudaDeviceProp prop{};
  if (cudaGetDeviceProperties(&prop, device) != cudaSuccess) return "";
  return prop.name;
}

}  // namespace millsim::backend
