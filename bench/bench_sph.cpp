// SPH throughput: particle-steps and particle interactions per second of the shipped dam-break
// cases, on OpenMP (threads from OMP_NUM_THREADS) and CUDA (skipped without a device).
// Run: build/bench/millsim_bench --benchmark_filter=Sph
#include <benchmark/benchmark.h>

#include <cmath>
#include <memory>
#include <string>

#include "bench_common.hpp"
#include "millsim/io/case_xml.hpp"
#include "sim/sph_run.hpp"
#include "sph/sph_engine.hpp"
#include "sph/sph_pair.hpp"

using namespace millsim;

static void runSteps(benchmark::State& state, const std::string& case_name, const std::vector<std::string>& sets,
                     int warm_steps = 200, bool cuda = false) {
  if (!bench::backendAvailable(state, cuda)) return;
  const scene::Scene sc = io::loadCaseFile(bench::sourceDir() + "/cases/" + case_name + ".xml", sets);
  const sph::SphSetup setup = sim::sphSetupOf(sc);
  std::unique_ptr<sph::SphEngine> engine;
#if defined(MILLSIM_HAVE_CUDA)
  if (cuda) engine = sph::makeSphEngineCuda(setup, bench::singlePrecision());
#endif
  if (!engine) engine = sph::makeSphEngineOmp(setup, bench::singlePrecision());
  const sph::SphHostState particles = sim::sphParticlesOf(sc, setup);
  engine->setState(particles);
  engine->initialize({});
  // Let the column start to collapse so the measured steps see a moving, sheared flow.
  for (int k = 0; k < warm_steps; ++k) engine->step(engine->nextDt(), {}, {});
  const double pairs = engine->interactionsPerEvaluation() * engine->evaluationsPerStep();
  for (auto _ : state) engine->step(engine->nextDt(), {}, {});
  long long fluid = 0;
  for (int c : particles.code) fluid += c == sph::kFluid;
  state.counters["particles"] = double(particles.size());
  state.counters["fluid"] = double(fluid);
  state.counters["particle_steps_per_s"] =
      benchmark::Counter(double(particles.size()), benchmark::Counter::kIsIterationInvariantRate);
  state.counters["fluid_steps_per_s"] =
      benchmark::Counter(double(fluid), benchmark::Counter::kIsIterationInvariantRate);
  state.counters["interactions_per_s"] = benchmark::Counter(pairs, benchmark::Counter::kIsIterationInvariantRate);
}

static void BM_SphDamBreak2d(benchmark::State& state) { runSteps(state, "dam_break_2d", {}); }
static void BM_SphDamBreak2dSymplectic(benchmark::State& state) {
  runSteps(state, "dam_break_2d", {"sph.integrator=symplectic"});
}
static void BM_SphDamBreak3d(benchmark::State& state) { runSteps(state, "dam_break_3d", {}); }
// Over 1e5 fluid particles (dp = a/40: 128 000 fluid, walls three layers deep), for thread scaling
// at the size the issue asks about; a short lead-in (the column barely starts to move).
static void BM_SphDamBreak3dFine(benchmark::State& state) {
  runSteps(state, "dam_break_3d", {"sph.dp=0.00142875"}, 20);
}

// Scaling with N (issue 10): the 3D dam break with dp chosen for about N fluid particles (16 000
// at dp = a/20, as dp^-3; the walls, three layers, grow as dp^-2), arg 1: 0 OpenMP, 1 CUDA. A
// short lead-in: the column barely moves, the flow is the dense column's.
static void BM_SphScaling3d(benchmark::State& state) {
  const double n = double(state.range(0));
  const double dp = 0.05715 / 20 * std::cbrt(16000.0 / n);
  runSteps(state, "dam_break_3d", {"sph.dp=" + std::to_string(dp)}, 5, state.range(1) != 0);
}

BENCHMARK(BM_SphDamBreak2d)->Unit(benchmark::kMillisecond)->MinTime(2.0)->UseRealTime();
BENCHMARK(BM_SphDamBreak2dSymplectic)->Unit(benchmark::kMillisecond)->MinTime(2.0)->UseRealTime();
BENCHMARK(BM_SphDamBreak3d)->Unit(benchmark::kMillisecond)->Iterations(40)->UseRealTime();
BENCHMARK(BM_SphDamBreak3dFine)->Unit(benchmark::kMillisecond)->Iterations(10)->UseRealTime();
// A fixed number of steps per N (the same stretch of the flow on every backend and thread count).
BENCHMARK(BM_SphScaling3d)
    ->Apply(bench::smallScalingArgs)
    ->Iterations(20)
    ->Unit(benchmark::kMillisecond)
    ->UseRealTime();
BENCHMARK(BM_SphScaling3d)->Apply(bench::largeScalingArgs)->Iterations(3)->Unit(benchmark::kMillisecond)->UseRealTime();
