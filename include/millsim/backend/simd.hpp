#pragma once
// Which x86 vector extensions the host's vectorised loops may use. The library is compiled for
// the baseline x86-64 (SSE2) so it runs anywhere; the few loops that gain from wider vectors
// (the DEM contact blocks, contact_batch.hpp; the SPH pair blocks, sph_pair_batch.hpp) are
// compiled again for AVX2+FMA and AVX-512 and one is picked at run time from what the CPU (and
// OS) supports. The environment variable MILLSIM_SIMD=scalar|baseline|avx2|avx512 (or
// setSimdLevel) asks for a lower level, for comparisons; "scalar" runs the DEM contact pass and
// the SPH pair loop pair by pair per particle, as CUDA does, with no blocks. A higher level than
// the CPU has is refused, naming the level the CPU does have.
#include <string>

// Vectorise the loop that follows: its iterations are independent (each entry of a pair block is
// its own pair).
#if defined(__clang__)
#define MILLSIM_VECTORIZE_LOOP _Pragma("clang loop vectorize(enable)")
#elif defined(__GNUC__)
#define MILLSIM_VECTORIZE_LOOP _Pragma("GCC ivdep")
#else
#define MILLSIM_VECTORIZE_LOOP
#endif

// Function attributes that compile a block loop again for AVX2 and for AVX-512 (8 doubles or 16
// floats a vector); the library itself targets baseline x86-64. Contraction into FMA is switched
// off at both (GCC contracts by default in C++), so every level gives the same bits as the
// baseline loop: square root and division are correctly rounded at every width. GCC only (clang
// has no per-function fp-contract switch): other compilers run the baseline loop.
#if defined(__x86_64__) && defined(__GNUC__) && !defined(__clang__)
#define MILLSIM_HAVE_SIMD_LEVELS 1
#define MILLSIM_TARGET_AVX2 __attribute__((target("avx2,fma,bmi,bmi2"), optimize("fp-contract=off")))
#define MILLSIM_TARGET_AVX512                                                                                     \
  __attribute__((target("avx512f,avx512vl,avx512dq,avx512bw,avx512cd,avx2,fma,bmi,bmi2,prefer-vector-width=512"), \
                 optimize("fp-contract=off")))
#endif

// always_inline for a lambda (written after its parameter list), on the host: a search calls its
// per-hit lambda from several places (each row range, the dense fallback), and GCC then left
// the SPH pair loop's staging lambda as a call per pair.
#if defined(__GNUC__) && !defined(__CUDACC__)
#define MILLSIM_LAMBDA_FORCE_INLINE __attribute__((always_inline))
#else
#define MILLSIM_LAMBDA_FORCE_INLINE
#endif

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

// Sets a level for a scope and gives back the one it found when the scope ends, also when it
// ends by an exception or a failed test assertion (a comparison at the scalar level must not
// leave the rest of the process there).
class ScopedSimdLevel {
 public:
  explicit ScopedSimdLevel(SimdLevel level) : m_previous(simdLevel()) { setSimdLevel(level); }
  ~ScopedSimdLevel() { setSimdLevel(m_previous); }
  ScopedSimdLevel(const ScopedSimdLevel&) = delete;
  ScopedSimdLevel& operator=(const ScopedSimdLevel&) = delete;

 private:
  SimdLevel m_previous;
};

}  // namespace millsim::backend
