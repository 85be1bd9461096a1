#pragma once
// One whole run of a loaded case per benchmark iteration, as `millsim run` does it, for the
// benchmarks that time a case end to end (bench_stirred.cpp, bench_case_run.cpp). The outputs are
// written only when MILLSIM_BENCH_OUT=DIR is set, to DIR/<leaf>_<backend>: the GPU machine has no
// CLI, so this is how a run there brings its outputs back.
#include <benchmark/benchmark.h>

#include <cstdlib>
#include <string>

#include "bench_common.hpp"
#include "millsim/sim/simulation.hpp"

namespace millsim::bench {

inline sim::RunSummary runWholeCase(benchmark::State& state, const scene::Scene& scene, bool cuda,
                                    const std::string& leaf) {
  const char* out = std::getenv("MILLSIM_BENCH_OUT");
  sim::RunOptions run;
  run.backend = cuda ? "cuda" : "omp";
  run.precision = singlePrecision() ? "float" : "double";
  run.write_outputs = out != nullptr;
  if (out) run.out_dir = std::string(out) + "/" + leaf + "_" + run.backend;
  sim::RunSummary summary;
  for (auto _ : state) {
    sim::Simulation sim(scene, run);
    summary = sim.run();
  }
  return summary;
}

}  // namespace millsim::bench
