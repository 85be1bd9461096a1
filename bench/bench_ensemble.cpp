// Ensembles (issue 10, Done-when 4): the paper's three drums (300, 400, 500 mm) times C
// candidates (restitution, friction) as ONE ensemble, against one scene alone, each simulated
// for the same time (0.5 s compaction, then turning, MILLSIM_ENSEMBLE_T seconds in all, default 2).
// The time of one iteration is the wall time of the whole run (charge placement included).
//   BM_DrumEnsemble/C/cuda: C = 0 is the 300 mm drum alone; C > 0 is 3 C scenes at once.
// The target: 18 scenes (C = 6) on the GPU in less than 3x the time of one scene alone.
// On the CPU an ensemble costs about the sum of its scenes' work (no launches to save; each
// scene steps by its own dt, the ensemble as often as its smallest).
#include <benchmark/benchmark.h>

#include <algorithm>
#include <cstdlib>
#include <string>
#include <vector>

#include "bench_common.hpp"
#include "millsim/io/case_xml.hpp"
#include "millsim/sim/ensemble_run.hpp"
#include "millsim/sim/simulation.hpp"

using namespace millsim;

namespace {

std::string simulatedTime() {
  const char* env = std::getenv("MILLSIM_ENSEMBLE_T");
  return env ? env : "2";
}

scene::Scene drumCase(const std::string& diameter, double e, double mu) {
  const std::string path = bench::sourceDir() + "/cases/ball_mill_" + diameter + "_balls.xml";
  return io::loadCaseFile(path, {"time.end=" + simulatedTime(), "compaction.duration=0.5", "drum.start_time=0.5",
                                 "angle_of_repose.start_time=1", "angle_of_repose.frames=20", "output.fields_every=0",
                                 "output.checkpoint_every=0", "dem.restitution=" + std::to_string(e),
                                 "dem.friction=" + std::to_string(mu)});
}

void BM_DrumEnsemble(benchmark::State& state) {
  const int candidates = static_cast<int>(state.range(0));
  const bool cuda = state.range(1) != 0;
  if (!bench::backendAvailable(state, cuda)) return;
  sim::RunOptions run;
  run.backend = cuda ? "cuda" : "omp";
  run.precision = bench::singlePrecision() ? "float" : "double";
  run.write_outputs = false;
  double particles = 0, steps = 0, work = 0;  // work: particle-steps, each scene by its own steps
  double rebuilds = 0;                        // neighbour-list rebuilds (the ensemble's, shared)
  for (auto _ : state) {
    if (candidates == 0) {
      sim::Simulation one(drumCase("300", 0.39, 0.5), run);
      const sim::RunSummary& s = one.run();
      particles = static_cast<double>(s.particles);
      steps = static_cast<double>(s.steps);
      work = particles * steps;
      rebuilds = static_cast<double>(s.neighbour_rebuilds);
      continue;
    }
    sim::EnsembleSpec spec;
    spec.run = run;
    for (int c = 0; c < candidates; ++c)
      for (const char* d : {"300", "400", "500"}) {
        spec.scenes.push_back(drumCase(d, 0.30 + 0.04 * c, 0.35 + 0.05 * c));
        spec.out_dirs.push_back("");
      }
    const std::vector<sim::RunSummary> all = sim::runEnsemble(spec);
    particles = work = steps = 0;
    for (const sim::RunSummary& s : all) {
      particles += static_cast<double>(s.particles);
      work += static_cast<double>(s.particles) * static_cast<double>(s.steps);
      steps = std::max(steps, static_cast<double>(s.steps));  // the ensemble's: its smallest dt's
    }
    rebuilds = static_cast<double>(all.front().neighbour_rebuilds);
  }
  state.counters["scenes"] = candidates == 0 ? 1 : 3 * candidates;
  state.counters["particles"] = particles;
  state.counters["steps"] = steps;
  state.counters["rebuilds"] = rebuilds;
  state.counters["particle_steps_per_s"] = benchmark::Counter(work, benchmark::Counter::kIsIterationInvariantRate);
}

}  // namespace

BENCHMARK(BM_DrumEnsemble)
    ->Args({0, 0})
    ->Args({1, 0})
    ->Args({6, 0})
    ->Args({0, 1})
    ->Args({1, 1})
    ->Args({6, 1})
    ->Unit(benchmark::kSecond)
    ->Iterations(1)
    ->UseRealTime();
