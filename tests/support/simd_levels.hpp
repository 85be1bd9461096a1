#pragma once
// The SIMD levels a test should compare on this CPU: kScalar (one particle at a time, as CUDA)
// and every vector level up to the widest the CPU has (backend::cpuSimdLevel()).
#include <vector>

#include "millsim/backend/simd.hpp"

namespace millsim::testing {

inline std::vector<backend::SimdLevel> hostSimdLevels() {
  std::vector<backend::SimdLevel> levels;
  for (backend::SimdLevel l : {backend::SimdLevel::kScalar, backend::SimdLevel::kBaseline, backend::SimdLevel::kAvx2,
                               backend::SimdLevel::kAvx512})
    if (static_cast<int>(l) <= static_cast<int>(backend::cpuSimdLevel())) levels.push_back(l);
  return levels;
}

}  // namespace millsim::testing
