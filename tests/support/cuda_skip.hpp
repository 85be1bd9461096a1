#pragma once
// The skip every CUDA-against-OpenMP test starts with (tests/gpu): why a comparison cannot run
// on this machine, or nothing. The reason names the runtime's own error (a driver older than the
// toolkit looks like "no device" otherwise).
#include <gtest/gtest.h>

#include <string>

#include "millsim/backend/info.hpp"

namespace millsim::testing {

inline std::string cudaUnavailable() {
#if !defined(MILLSIM_HAVE_CUDA)
  return "CUDA backend not built (MILLSIM_CUDA=OFF or no nvcc): nothing to compare";
#else
  if (backend::cudaDevices() == 0)
    return "no CUDA device on this machine (" + backend::cudaStatus() + "): GPU comparison skipped";
  return "";
#endif
}

}  // namespace millsim::testing

// In a test body: returns from it, skipped, where CUDA cannot run.
#define MILLSIM_SKIP_WITHOUT_CUDA()                                           \
  do {                                                                        \
    const std::string millsim_cuda_why = millsim::testing::cudaUnavailable(); \
    if (!millsim_cuda_why.empty()) GTEST_SKIP() << millsim_cuda_why;          \
  } while (0)
