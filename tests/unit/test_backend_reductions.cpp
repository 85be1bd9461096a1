// reduceMax on the host keeps a NaN wherever it falls (backend::MaxKeepNan, the same combining
// step as on CUDA), on one thread and on two, on the serial path (n below the OpenMP threshold)
// and the parallel one; without a NaN it is the plain maximum. And what that is for: one fluid
// particle with a NaN velocity makes the SPH step's acceleration NaN, and the next time step
// stops the run with the cause instead of stepping on with the other particles' limit (before
// this, OpenMP's max reduction dropped the NaN and the run went on).
#include <gtest/gtest.h>
#include <omp.h>

#include <algorithm>
#include <cmath>
#include <limits>
#include <random>
#include <vector>

#include "millsim/backend/omp.hpp"
#include "millsim/core/error.hpp"
#include "support/sph_fixture.hpp"

namespace millsim {
namespace {

struct Read {
  const double* v;
  double operator()(int i) const { return v[i]; }
};

TEST(BackendReduceMax, KeepsANanAnywhereOnEveryPath) {
  std::mt19937 rng(11);
  std::uniform_real_distribution<double> u(-5, 5);
  for (int threads : {1, 2})
    for (int n : {100, 5000}) {  // below and above kOmpParallelThreshold (2048)
      omp_set_num_threads(threads);
      std::vector<double> v(n);
      for (double& x : v) x = u(rng);
      const double expected = std::max(*std::max_element(v.begin(), v.end()), -1e300);
      EXPECT_EQ(backend::reduceMax<double>(backend::Omp{}, n, -1e300, Read{v.data()}), expected)
          << threads << " threads, n = " << n;
      for (int at : {0, n / 3, n - 1}) {
        std::vector<double> w = v;
        w[at] = std::numeric_limits<double>::quiet_NaN();
        EXPECT_TRUE(std::isnan(backend::reduceMax<double>(backend::Omp{}, n, -1e300, Read{w.data()})))
            << threads << " threads, n = " << n << ", NaN at " << at;
      }
    }
  omp_set_num_threads(1);
}

TEST(BackendReduceMax, OneNanParticleStopsTheSphRunWithItsCause) {
  testing::TankScene sc;
  sc.dp = 0.01;
  const sph::SphSetup s = sc.setup();
  sph::SphHostState st = sc.state(s);
  // A fluid particle in the middle of the column (not the first: the old reduction kept a NaN
  // only there).
  std::size_t victim = 0;
  int fluid_seen = 0;
  for (std::size_t i = 0; i < st.size(); ++i)
    if (st.code[i] == sph::kFluid && ++fluid_seen == 200) victim = i;
  ASSERT_GT(victim, 0u);
  auto clean = sph::makeSphEngineOmp(s);
  clean->setState(st);
  clean->initialize({});
  EXPECT_GT(clean->nextDt(), 0);  // the same state without the NaN steps
  st.vel[3 * victim] = std::numeric_limits<double>::quiet_NaN();
  auto e = sph::makeSphEngineOmp(s);
  e->setState(st);
  e->initialize({});
  try {
    e->nextDt();
    FAIL() << "nextDt() returned a step with a NaN velocity in the fluid";
  } catch (const core::SimulationError& err) {
    EXPECT_NE(std::string(err.what()).find("NaN"), std::string::npos) << err.what();
  }
}

}  // namespace
}  // namespace millsim
