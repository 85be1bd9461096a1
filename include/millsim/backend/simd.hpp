#pragma once
// Which x86 vector extensions the host's vectorised loops may use. The library is compiled for
// the baseline x86-64 (SSE2) so it runs anywhere; the few loops that gain from wider vectors
// (the DEM pair blocks, contact_batch.hpp) are compiled again for AVX2+FMA and AVX-512 and one
// is picked at run time from what the CPU (and OS) supports. The environment variable
// MILLSIM_SIMD=scalar|baseline|avx2|avx512 (or setSimdLevel) asks for a lower level, for
// comparisons; "scalar" runs the contact pass pair by pair per particle, as CUDA does, with no
// blocks. A higher level than the CPU has is refused, naming the level the CPU does have.
#include <string>

namespace millsim::backend {

enum class SimdLevel { kScalar = -1, kBaseline = 0, kAvx2 = 1, kAvx512 = 2 };

// The widest level this CPU supports.
SimdLevel cpuSimdLevel();
// The level the loops use: cpuSimdLevel(), or MILLSIM_SIMD's when set (read at the first call;
// throws std::invalid_argument for an unknown name or a level the CPU lacks), or the last
// setSimdLevel's.
SimdLevel simdLevel();
// Process-wide, like omp_set_num_threads; not while a contact pass runs. Throws
// std::invalid_argument for a level the CPU lacks.
void setSimdLevel(SimdLevel level);
const char* simdLevelName(SimdLevel level);
// "avx2" -> kAvx2 etc.; throws std::invalid_argument naming the accepted values.
SimdLevel parseSimdLevel(const std::string& name);

}  // namespace millsim::backend
