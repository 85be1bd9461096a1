#pragma once
// What execution spaces this build and this machine offer (for `millsim info` and --backend auto).
#include <string>

namespace millsim::backend {

bool cudaCompiled();
int cudaDevices();           // 0 without a driver or a GPU
std::string cudaDeviceName();  // "" when none (else the calling thread's device)
// Why there is or is not a device: "N device(s)", or the runtime's error (e.g. a driver older
// than the toolkit, which otherwise looks like "no GPU").
std::string cudaStatus();
// Makes GPU `index mod cudaDevices()` the calling thread's device (MPI: one GPU per rank of a
// node). False, and nothing changes, without CUDA or a GPU.
bool selectCudaDevice(int index);
int ompMaxThreads();
// What --backend auto means here: "cuda" with CUDA compiled and a GPU present, else "omp".
std::string resolvedBackend(const std::string& backend);

}  // namespace millsim::backend
