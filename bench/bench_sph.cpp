// SPH throughput: particle-steps and particle interactions per second of the shipped dam-break
// cases (OpenMP; threads from OMP_NUM_THREADS). Run: build/bench/millsim_bench --benchmark_filter=Sph
#include <benchmark/benchmark.h>

#include <string>

#include "millsim/io/case_xml.hpp"
#include "sim/sph_run.hpp"
#include "sph/sph_engine.hpp"

using namespace millsim;

static void runSteps(benchmark::State& state, const std::string& case_name, const std::vector<std::string>& sets,
                     int warm_steps = 200) {
  const scene::Scene sc = io::loadCaseFile(std::string(MILLSIM_SOURCE_DIR) + "/cases/" + case_name + ".xml", sets);
  const sph::SphSetup setup = sim::sphSetupOf(sc);
  auto engine = sph::makeSphEngineOmp(setup);
  const sph::SphHostState particles = sim::sphParticlesOf(sc, setup);
  engine->setState(particles);
  engine->initialize({});
  // Let the column start to collapse so the measured steps see a moving, sheared flow.
  for (int k = 0; k < warm_steps; ++k) engine->step(engine->nextDt(), {}, {});
  const double pairs = engine->interactionsPerEvaluation() * engine->evaluationsPerStep();
  for (auto _ : state) engine->step(engine->nextDt(), {}, {});
  state.counters["particles"] = double(particles.size());
  state.counters["particle_steps_per_s"] =
      benchmark::Counter(double(particles.size()), benchmark::Counter::kIsIterationInvariantRate);
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

BENCHMARK(BM_SphDamBreak2d)->Unit(benchmark::kMillisecond)->MinTime(2.0)->UseRealTime();
BENCHMARK(BM_SphDamBreak2dSymplectic)->Unit(benchmark::kMillisecond)->MinTime(2.0)->UseRealTime();
BENCHMARK(BM_SphDamBreak3d)->Unit(benchmark::kMillisecond)->Iterations(40)->UseRealTime();
BENCHMARK(BM_SphDamBreak3dFine)->Unit(benchmark::kMillisecond)->Iterations(10)->UseRealTime();
