#pragma once
// What the benchmarks share: where the case files are, which backend a benchmark asks for, and
// the precision (MILLSIM_BENCH_FLOAT=1: single precision where the engine offers it).
#include <benchmark/benchmark.h>

#include <cstdlib>
#include <filesystem>
#include <string>

#include "millsim/backend/info.hpp"

namespace millsim::bench {

// The source tree's cases/: MILLSIM_SOURCE_DIR from the environment (a copied tree, e.g. on the
// GPU machine, sits elsewhere than where it was built), else where it was built, else the working
// directory.
inline std::string sourceDir() {
  if (const char* env = std::getenv("MILLSIM_SOURCE_DIR")) return env;
  if (std::filesystem::exists(std::string(MILLSIM_SOURCE_DIR) + "/cases")) return MILLSIM_SOURCE_DIR;
  return ".";
}

inline bool singlePrecision() {
  const char* env = std::getenv("MILLSIM_BENCH_FLOAT");
  return env && std::string(env) == "1";
}

// False (and the benchmark marked skipped with the reason) when CUDA is asked for and absent.
inline bool backendAvailable(benchmark::State& state, bool cuda) {
  if (!cuda) return true;
#if defined(MILLSIM_HAVE_CUDA)
  if (backend::cudaDevices() > 0) return true;
  state.SkipWithError(("no CUDA device on this machine: " + backend::cudaStatus()).c_str());
#else
  state.SkipWithError("built without CUDA");
#endif
  return false;
}

// Issue 10's scaling points as (N, backend) pairs, backend 0 OpenMP and 1 CUDA: N = 1e4 and 1e5
// on both, and 1e6 on both with 1e7 on CUDA (registered apart: fewer iterations). Each scaling
// benchmark runs a fixed number of iterations per N, so every backend and thread count times
// the same stretch of the motion.
inline void smallScalingArgs(benchmark::internal::Benchmark* b) {
  b->Args({10000, 0})->Args({100000, 0})->Args({10000, 1})->Args({100000, 1});
}
inline void largeScalingArgs(benchmark::internal::Benchmark* b) {
  b->Args({1000000, 0})->Args({1000000, 1})->Args({10000000, 1});
}

}  // namespace millsim::bench
