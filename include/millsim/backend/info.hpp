#pragma once
// What execution spaces this build and this machine offer (for `millsim info` and --backend auto).
#include <string>

namespace millsim::backend {

bool cudaCompiled();
int cudaDevices();           // 0 without a driver or a GPU
std::string cudaDeviceName();  // "" when none
int ompMaxThreads();

}  // namespace millsim::backend
