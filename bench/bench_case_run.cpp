// Any case file run whole, as `millsim run` runs it, for the GPU machine, which cannot carry the
// CLI (its OpenCV video I/O is too large: docs/performance.md "GPU checks"). Issue 5, Done-when 5
// needs the full 500 mm wet mill on CUDA, its angle of repose and slurry curve set against the CPU
// run's; this runs it and writes the case's outputs.
//   MILLSIM_BENCH_CASE  a file under cases/, e.g. ball_mill_500_wet.xml (unset: skipped)
//   MILLSIM_BENCH_SET   overrides as `millsim run --set` takes them, separated by ';'
//   MILLSIM_BENCH_OUT   where the outputs go (DIR/<case>_<backend>); unset: none written
//   BM_CaseRun/cuda: cuda 0 OpenMP, 1 CUDA. One iteration is the whole run.
#include <benchmark/benchmark.h>

#include <cstdlib>
#include <sstream>
#include <string>
#include <vector>

#include "bench_common.hpp"
#include "bench_whole_run.hpp"
#include "millsim/io/case_xml.hpp"
#include "millsim/sim/simulation.hpp"

using namespace millsim;

namespace {

std::vector<std::string> overridesFromEnv() {
  std::vector<std::string> out;
  const char* env = std::getenv("MILLSIM_BENCH_SET");
  std::istringstream in(env ? env : "");
  for (std::string item; std::getline(in, item, ';');)
    if (!item.empty()) out.push_back(item);
  return out;
}

void BM_CaseRun(benchmark::State& state) {
  const char* name = std::getenv("MILLSIM_BENCH_CASE");
  if (!name) {
    state.SkipWithError("MILLSIM_BENCH_CASE names no case");
    return;
  }
  const bool cuda = state.range(0) != 0;
  if (!bench::backendAvailable(state, cuda)) return;
  const scene::Scene scene = io::loadCaseFile(bench::sourceDir() + "/cases/" + name, overridesFromEnv());
  const sim::RunSummary summary = bench::runWholeCase(state, scene, cuda, scene.name);
  state.counters["particles"] = static_cast<double>(summary.particles + summary.sph_particles);
  state.counters["steps"] = static_cast<double>(summary.steps);
  state.counters["simulated_s"] = summary.simulated_time_s;
  state.counters["run_wall_s"] = summary.wall_time_s;
}

}  // namespace

BENCHMARK(BM_CaseRun)->Arg(1)->Arg(0)->Unit(benchmark::kSecond)->Iterations(1)->UseRealTime();
