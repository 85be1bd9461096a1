// Coupled SPH-DEM throughput (issue 10: DEM, SPH and coupled cases at N = 1e4 .. 1e6, 1e7 on the
// GPU): the paper's wet mill (cases/ball_mill_500_wet.xml: dp 5 mm, 25-35 mm balls at 30 % of the
// drum, slurry 20 %, 30 % of the critical speed) with the drum scaled so that it holds about N
// SPH particles (fluid, drum walls, ball shells). dp and the balls keep the paper's sizes, so the
// work per particle and the DEM sub-steps per SPH step are the case's own at every N; only the
// number of particles and balls grows (628 balls at N = 195 329, the case itself).
//
// One iteration is one coupled step: an SPH step with the DEM's sub-steps inside it (WetMill::
// advance, what `millsim run` does). Set-up (charge placement, 0.5 s of compaction on the
// benchmark's backend, the pour) is not timed.
// Run: build/bench/millsim_bench --benchmark_filter=Coupled
#include <benchmark/benchmark.h>

#include <cmath>
#include <memory>
#include <string>

#include "bench_common.hpp"
#include "millsim/io/case_xml.hpp"
#include "sim/charge_setup.hpp"
#include "sim/drum_motion.hpp"
#include "sim/drum_setup.hpp"
#include "sim/engine_factory.hpp"
#include "sim/wet_mill.hpp"

using namespace millsim;

namespace {

// SPH particles of the unscaled case (500 mm x 150 mm drum, 195 329 in all): fluid and ball shells
// grow as the volume (s^3), the drum's wall layers as its surface (s^2).
constexpr double kVolumeParticles = 122000, kWallParticles = 73329;

// The scale s of the drum that holds about n particles (Newton on the cubic; +-15% at 1e4, where
// the lifters and the few balls' shells make the count less regular).
double drumScale(double n) {
  double s = std::cbrt(n / (kVolumeParticles + kWallParticles));
  for (int k = 0; k < 20; ++k)
    s -= (kVolumeParticles * s * s * s + kWallParticles * s * s - n) /
         (3 * kVolumeParticles * s * s + 2 * kWallParticles * s);
  return s;
}

scene::Scene scaledWetMill(double n) {
  const double s = drumScale(n);
  scene::Scene sc = io::loadCaseFile(
      bench::sourceDir() + "/cases/ball_mill_500_wet.xml",
      {"drum.diameter=" + std::to_string(0.492 * s), "drum.length=" + std::to_string(0.15 * s),
       "compaction.duration=0.5", "drum.start_time=0.5", "time.end=1", "angle_of_repose.enabled=false"});
  sc.drum.critical_fraction = 0.3;  // the paper's speed at every size (the case gives 18.7 rpm for 500 mm)
  return sc;
}

}  // namespace

// Args: N (SPH particles, about), backend (0 OpenMP, 1 CUDA; skipped without a device). Single
// precision, as the wet mill is run (docs/accuracy-cost.md).
static void BM_CoupledWetMill(benchmark::State& state) {
  const bool cuda = state.range(1) != 0;
  if (!bench::backendAvailable(state, cuda)) return;
  const scene::Scene sc = scaledWetMill(double(state.range(0)));
  sim::RunOptions options;
  options.backend = cuda ? "cuda" : "omp";
  options.precision = "float";
  options.write_outputs = false;
  const sim::ChargeSetup charge = sim::buildCharge(sc);
  const sim::DrumMotion motion(sc, charge.generation_length, sim::drumSpeedRpm(sc, charge));
  const double dt = sim::drumTimeStep(sc, charge);
  std::unique_ptr<dem::DemEngine> dem = sim::makeDemEngine(sim::drumDemSetup(sc, charge), options);
  dem->setState(charge.state);
  double t = 0, phi = 0;
  dem->initialize(motion.at(t, phi));
  long long dem_steps = 0;
  while (t < sc.drum.start_time - 0.5 * dt) {  // compaction: the piston packs the balls
    motion.stepDem(*dem, t, phi, dt);
    ++dem_steps;
  }
  sim::WetMill wet(sc, options, dem::ballStates(*dem), phi, t);
  for (int k = 0; k < 5; ++k) wet.advance(*dem, motion, t, phi, dem_steps, dt);  // the first pass and sorts
  const long long sph0 = wet.sphSteps(), dem0 = dem_steps;
  for (auto _ : state) wet.advance(*dem, motion, t, phi, dem_steps, dt);
  const double steps = double(wet.sphSteps() - sph0);
  const double particles = double(wet.particles() + charge.state.size());
  state.counters["particles"] = particles;
  state.counters["sph_particles"] = double(wet.particles());
  state.counters["balls"] = double(charge.state.size());
  state.counters["dem_substeps"] = double(dem_steps - dem0) / steps;
  state.counters["particle_steps_per_s"] = benchmark::Counter(particles * steps, benchmark::Counter::kIsRate);
}
// A fixed number of coupled steps per N, as for the DEM and SPH scaling benchmarks; and the case
// itself (195 329) on OpenMP.
BENCHMARK(BM_CoupledWetMill)
    ->Name("BM_CoupledScaling")
    ->Apply(bench::smallScalingArgs)
    ->Args({195329, 0})
    ->Iterations(100)
    ->Unit(benchmark::kMillisecond)
    ->UseRealTime();
BENCHMARK(BM_CoupledWetMill)
    ->Name("BM_CoupledScaling")
    ->Apply(bench::largeScalingArgs)
    ->Iterations(5)
    ->Unit(benchmark::kMillisecond)
    ->UseRealTime();
