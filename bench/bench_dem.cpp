// DEM throughput: particle-steps per second of the drum engine for a settled-ish random charge
// of N equal balls in a rotating drum, as spheres (OpenMP or CUDA) and as the paper's DCDEM balls
// (elements at dp = 5 mm). Run: build/bench/millsim_bench.
#include <benchmark/benchmark.h>

#include <algorithm>
#include <cmath>
#include <memory>
#include <random>

#include "bench_common.hpp"

#include "dem/contact/damping.hpp"
#include "dem/dcdem_bodies.hpp"
#include "dem/dem_engine.hpp"

using namespace millsim;

namespace {

struct DrumScene {
  dem::DemSetup setup;
  dem::DemHostState balls;
  dem::DrumState drum;
};

// n balls of radius r on a loose lattice in a drum sized for ~25% solid fraction.
DrumScene drumScene(int n, double r) {
  const double vol = n * 4.0 / 3.0 * M_PI * r * r * r / 0.25;
  const double R = std::cbrt(vol / (2 * M_PI)), L = 2 * R;
  dem::DemSetup setup;
  setup.k_coef = 4.0 / 3.0 * dem::effectiveModulus(1e8, 0.29);
  setup.alpha = dem::dampingAlpha(dem::DampingModel::kExact, 0.39);
  setup.friction = 0.5;
  setup.skin = 0.2 * r;
  setup.max_radius = r;
  setup.domain_lo = {-R - 2 * r, -R - 2 * r, -2 * r};
  setup.domain_hi = {R + 2 * r, R + 2 * r, L + 2 * r};
  dem::DemHostState s;
  std::mt19937 rng(1);
  std::uniform_real_distribution<double> u(0, 1);
  const double a = (R - r) / std::sqrt(2.0), c = 2.05 * r;
  for (double z = r; z < L - r && static_cast<int>(s.radius.size()) < n; z += c)
    for (double y = -a; y < a && static_cast<int>(s.radius.size()) < n; y += c)
      for (double x = -a; x < a && static_cast<int>(s.radius.size()) < n; x += c) {
        s.pos.insert(s.pos.end(), {x, y, z});
        s.vel.insert(s.vel.end(), {0.1 * (u(rng) - 0.5), 0.1 * (u(rng) - 0.5), 0.0});
        s.omega.insert(s.omega.end(), {0, 0, 0});
        s.radius.push_back(r);
        const double m = 7800 * 4.0 / 3.0 * M_PI * r * r * r;
        s.mass.push_back(m);
        s.inertia.push_back(0.4 * m * r * r);
      }
  dem::DrumState drum;
  drum.radius = R;
  drum.z_back = L;
  drum.omega = -2.0;
  drum.lifter_count = 8;
  drum.lifter_height = r;
  drum.lifter_width = r;
  return {setup, s, drum};
}

}  // namespace

// Args: N, single precision (0/1), backend (0 OpenMP, 1 CUDA; skipped without a device).
static void BM_DemDrumStep(benchmark::State& state) {
  const bool cuda = state.range(2) != 0;
  if (!bench::backendAvailable(state, cuda)) return;
  DrumScene sc = drumScene(static_cast<int>(state.range(0)), 0.005);
  const dem::DemHostState& s = sc.balls;
  dem::DrumState& drum = sc.drum;
  std::unique_ptr<dem::DemEngine> engine;
#if defined(MILLSIM_HAVE_CUDA)
  if (cuda) engine = dem::makeDemEngineCuda(sc.setup, state.range(1) != 0);
#endif
  if (!engine) engine = dem::makeDemEngineOmp(sc.setup, state.range(1) != 0);
  engine->setState(s);
  engine->initialize(drum);
  const double dt = 1e-5;
  for (auto _ : state) {
    drum.phi += drum.omega * dt;
    engine->step(drum, dt);
  }
  state.counters["particles"] = static_cast<double>(s.radius.size());
  state.counters["rebuilds_per_step"] =
      static_cast<double>(engine->neighbourRebuilds()) / static_cast<double>(std::max<long long>(1, state.iterations()));
  state.counters["particle_steps_per_s"] =
      benchmark::Counter(static_cast<double>(s.radius.size()) * state.iterations(), benchmark::Counter::kIsRate);
}
BENCHMARK(BM_DemDrumStep)
    ->Args({1000, 0, 0})
    ->Args({10000, 0, 0})
    ->Args({10000, 1, 0})
    ->Args({50000, 0, 0})
    ->Args({200000, 0, 0})
    ->Unit(benchmark::kMicrosecond)
    ->UseRealTime();
// Scaling with N on both backends (issue 10: 1e4 .. 1e6, 1e7 on the GPU), float. A fixed number
// of steps per N, so every backend and thread count times the same stretch of the charge's
// motion (the loose lattice starts to tumble: rebuilds per step differ along it).
BENCHMARK(BM_DemDrumStep)
    ->Name("BM_DemScaling")
    ->Args({10000, 1, 0})
    ->Args({100000, 1, 0})
    ->Args({10000, 1, 1})
    ->Args({100000, 1, 1})
    ->Iterations(200)
    ->Unit(benchmark::kMicrosecond)
    ->UseRealTime();
BENCHMARK(BM_DemDrumStep)
    ->Name("BM_DemScaling")
    ->Args({1000000, 1, 0})
    ->Args({1000000, 1, 1})
    ->Args({10000000, 1, 1})
    ->Iterations(20)
    ->Unit(benchmark::kMicrosecond)
    ->UseRealTime();

// The paper's balls: 35 mm balls of 123 elements at dp = 5 mm (docs/cases.md, DCDEM balls);
// counters per element and per ball.
static void BM_DemDcdemDrumStep(benchmark::State& state) {
  const double r = 0.0175, dp = 0.005;
  DrumScene sc = drumScene(static_cast<int>(state.range(0)), r);
  sc.setup.skin = 0.2 * dp;
  sc.setup.max_radius = 0.5 * dp;
  dem::BodyAssembler a;
  for (std::size_t i = 0; i < sc.balls.size(); ++i) {
    std::vector<core::Vec3<double>> pts = dem::latticeBallPoints(r, dp);
    for (auto& p : pts) p += core::Vec3<double>{sc.balls.pos[3 * i], sc.balls.pos[3 * i + 1], sc.balls.pos[3 * i + 2]};
    a.addBody(pts, 0.5 * dp, sc.balls.mass[i], {sc.balls.vel[3 * i], sc.balls.vel[3 * i + 1], 0.0}, {0, 0, 0}, r);
  }
  auto engine = dem::makeDemEngineOmp(sc.setup, false);
  engine->setState(a.state());
  engine->setBodies(a.bodies());
  engine->initialize(sc.drum);
  const double dt = 1e-5;
  for (auto _ : state) {
    sc.drum.phi += sc.drum.omega * dt;
    engine->step(sc.drum, dt);
  }
  const double elements = static_cast<double>(a.state().size()), balls = static_cast<double>(sc.balls.size());
  state.counters["elements"] = elements;
  state.counters["element_steps_per_s"] =
      benchmark::Counter(elements * state.iterations(), benchmark::Counter::kIsRate);
  state.counters["ball_steps_per_s"] = benchmark::Counter(balls * state.iterations(), benchmark::Counter::kIsRate);
}
BENCHMARK(BM_DemDcdemDrumStep)->Arg(300)->Unit(benchmark::kMicrosecond)->UseRealTime();

BENCHMARK_MAIN();
