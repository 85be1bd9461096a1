#include "millsim/backend/simd.hpp"

#include <atomic>
#include <cstdlib>
#include <stdexcept>

namespace millsim::backend {

// The levels this build has loops for (contact_batch.hpp: GCC on x86-64) that the CPU supports.
SimdLevel cpuSimdLevel() {
#if defined(__x86_64__) && defined(__GNUC__) && !defined(__clang__)
  // libgcc's checks include the OS's: AVX-512 counts only when the kernel saves the ZMM state.
  __builtin_cpu_init();
  if (__builtin_cpu_supports("avx512f") && __builtin_cpu_supports("avx512vl") && __builtin_cpu_supports("avx512dq") &&
      __builtin_cpu_supports("avx512bw") && __builtin_cpu_supports("fma"))
    return SimdLevel::kAvx512;
  if (__builtin_cpu_supports("avx2") && __builtin_cpu_supports("fma")) return SimdLevel::kAvx2;
#endif
  return SimdLevel::kBaseline;
}

const char* simdLevelName(SimdLevel level) {
  switch (level) {
    case SimdLevel::kAvx512:
      return "avx512";
    case SimdLevel::kAvx2:
      return "avx2";
    case SimdLevel::kBaseline:
      return "baseline";
    case SimdLevel::kScalar:
      break;
  }
  return "scalar";
}

SimdLevel parseSimdLevel(const std::string& name) {
  for (SimdLevel l : {SimdLevel::kScalar, SimdLevel::kBaseline, SimdLevel::kAvx2, SimdLevel::kAvx512})
    if (name == simdLevelName(l)) return l;
  throw std::invalid_argument("MILLSIM_SIMD: unknown level '" + name + "' (expected scalar, baseline, avx2 or avx512)");
}

namespace {
void requireSupported(SimdLevel asked, const std::string& what) {
  const SimdLevel cpu = cpuSimdLevel();
  if (static_cast<int>(asked) > static_cast<int>(cpu))
    throw std::invalid_argument(what + ": this CPU supports up to " + simdLevelName(cpu));
}

SimdLevel levelFromEnvironment() {
  const char* env = std::getenv("MILLSIM_SIMD");
  if (env == nullptr || *env == '\0') return cpuSimdLevel();
  const SimdLevel asked = parseSimdLevel(env);
  requireSupported(asked, std::string("MILLSIM_SIMD=") + env);
  return asked;
}

std::atomic<int>& chosen() {
  static std::atomic<int> level{static_cast<int>(levelFromEnvironment())};
  return level;
}
}  // namespace

SimdLevel simdLevel() { return static_cast<SimdLevel>(chosen().load(std::memory_order_relaxed)); }

void setSimdLevel(SimdLevel level) {
  requireSupported(level, std::string("setSimdLevel(") + simdLevelName(level) + ")");
  chosen().store(static_cast<int>(level), std::memory_order_relaxed);
}

}  // namespace millsim::backend
