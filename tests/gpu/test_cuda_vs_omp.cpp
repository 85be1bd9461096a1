// The CUDA backend runs the same functors as OpenMP: a settling pile of balls in a rotating drum
// must give the same state on both. Skips with a message where no GPU (or no CUDA build) exists.
#include <gtest/gtest.h>

#include <cmath>
#include <cstdio>
#include <random>

#include "dem/contact/damping.hpp"
#include "dem/dem_engine.hpp"
#include "dem/dem_kernels.hpp"
#include "millsim/backend/info.hpp"
#include "support/cuda_skip.hpp"

using namespace millsim;

namespace {

[[maybe_unused]] dem::DemHostState pile(int n) {
  dem::DemHostState s;
  std::mt19937 rng(3);
  std::uniform_real_distribution<double> u(-1.0, 1.0);
  for (int i = 0; i < n; ++i) {
    const double r = 0.005 + 0.001 * (i % 3);
    s.pos.insert(s.pos.end(), {0.03 * u(rng), 0.03 * u(rng), 0.01 + 0.02 * (i % 5) + 0.001 * u(rng)});
    s.vel.insert(s.vel.end(), {0.0, 0.0, 0.0});
    s.omega.insert(s.omega.end(), {0.0, 0.0, 0.0});
    s.radius.push_back(r);
    const double m = 7800 * 4.0 / 3.0 * M_PI * r * r * r;
    s.mass.push_back(m);
    s.inertia.push_back(0.4 * m * r * r);
  }
  return s;
}

}  // namespace

TEST(CudaVsOmp, SameStateAfterSettlingInRotatingDrum) {
  MILLSIM_SKIP_WITHOUT_CUDA();
#if defined(MILLSIM_HAVE_CUDA)
  dem::DemSetup setup;
  setup.k_coef = 4.0 / 3.0 * dem::effectiveModulus(1e8, 0.29);
  setup.alpha = dem::dampingAlpha(dem::DampingModel::kExact, 0.39);
  setup.friction = 0.496;
  setup.gravity = {0, -9.81, 0};
  setup.skin = 0.001;
  setup.max_radius = 0.007;
  setup.domain_lo = {-0.06, -0.06, -0.01};
  setup.domain_hi = {0.06, 0.06, 0.12};
  dem::DrumState drum;
  drum.radius = 0.05;
  drum.z_back = 0.11;
  drum.omega = -3.0;
  drum.lifter_count = 4;
  drum.lifter_height = 0.004;
  drum.lifter_width = 0.004;
  const auto start = pile(60);
  auto omp = dem::makeDemEngineOmp(setup, false);
  auto cuda = dem::makeDemEngineCuda(setup, false);
  auto cuda2 = dem::makeDemEngineCuda(setup, false);  // the GPU against itself: its own spread
  for (auto* e : {omp.get(), cuda.get(), cuda2.get()}) {
    e->setState(start);
    e->initialize(drum);
  }
  const double dt = 2e-6;
  for (int k = 0; k < 3000; ++k) {
    drum.phi += drum.omega * dt;
    omp->step(drum, dt);
    cuda->step(drum, dt);
    cuda2->step(drum, dt);
  }
  dem::DemHostState a, b, c;
  omp->getState(a);
  cuda->getState(b);
  cuda2->getState(c);
  // 3000 steps of settling with many contacts: the two differ only by rounding (FMA contraction
  // on the GPU, the order of its atomic adds), amplified by the contacts; 1e-9 m is 1e-7 of a
  // ball radius. The GPU's run-to-run spread is printed: a miss far above it is a bug, one of its
  // size is rounding.
  double worst = 0, spread = 0;
  for (std::size_t i = 0; i < a.pos.size(); ++i) {
    worst = std::max(worst, std::abs(a.pos[i] - b.pos[i]));
    spread = std::max(spread, std::abs(b.pos[i] - c.pos[i]));
  }
  std::printf("drum: max |x_omp - x_cuda| = %.3g m, CUDA run-to-run %.3g m\n", worst, spread);
  EXPECT_LT(worst, 1e-9) << "CUDA run-to-run spread " << spread << " m";
  EXPECT_NEAR(omp->sums().dissipated, cuda->sums().dissipated, 1e-6 * omp->sums().dissipated + 1e-15);
#endif
}

// The stirred mill's instantiation (linear law, stirrer walls, lubrication and collision tallies)
// on both backends: 300 beads of 2 mm around a turning disk, 2000 steps at 3000 rpm, eta 0.5.
TEST(CudaVsOmp, SameStateInLubricatedStirredSlice) {
  MILLSIM_SKIP_WITHOUT_CUDA();
#if defined(MILLSIM_HAVE_CUDA)
  dem::DemSetup setup;
  setup.linear_law = true;
  setup.linear_kn = 1e5;
  setup.linear_zeta = 0.2;
  setup.friction = 0.3;
  setup.lubrication_viscosity = 0.5;
  setup.gravity = {0, -9.81, 0};
  setup.skin = 0.0002;
  setup.max_radius = 0.001;
  setup.domain_lo = {-0.05, -0.05, -0.005};
  setup.domain_hi = {0.05, 0.05, 0.04};
  dem::StirrerState st;
  st.radius = 0.045;
  st.length = 0.03575;
  st.shaft_radius = 0.019;
  st.omega = 3000 * 2 * M_PI / 60;
  st.disk_count = 1;
  st.disk_radius = 0.038;
  st.disk_thickness = 0.0075;
  st.disk_z = {0.5 * 0.03575};
  st.hole_count = 4;
  st.hole_radius = 0.006;
  st.hole_ring_radius = 0.029;
  dem::DemHostState s;
  std::mt19937 rng(5);
  std::uniform_real_distribution<double> ang(0, 2 * M_PI), rad(0.0395, 0.043), z(0.002, 0.034);
  for (int i = 0; i < 300; ++i) {
    const double a = ang(rng), r = rad(rng), r_b = 0.001, m = 6000 * 4.0 / 3.0 * M_PI * r_b * r_b * r_b;
    s.pos.insert(s.pos.end(), {r * std::cos(a), r * std::sin(a), z(rng)});
    s.vel.insert(s.vel.end(), {0.0, 0.0, 0.0});
    s.omega.insert(s.omega.end(), {0.0, 0.0, 0.0});
    s.radius.push_back(r_b);
    s.mass.push_back(m);
    s.inertia.push_back(0.4 * m * r_b * r_b);
  }
  auto omp = dem::makeDemEngineOmp(setup, false);
  auto cuda = dem::makeDemEngineCuda(setup, false);
  for (auto* e : {omp.get(), cuda.get()}) {
    e->setState(s);
    e->initialize(st);
  }
  const double dt = 5e-7;
  for (int k = 0; k < 2000; ++k) {
    st.phi += st.omega * dt;
    omp->step(st, dt);
    cuda->step(st, dt);
  }
  dem::DemHostState a, b;
  omp->getState(a);
  cuda->getState(b);
  // Same tolerance reasoning as the drum: rounding (FMA, atomic order) amplified by contacts.
  double worst = 0;
  for (std::size_t i = 0; i < a.pos.size(); ++i) worst = std::max(worst, std::abs(a.pos[i] - b.pos[i]));
  EXPECT_LT(worst, 1e-9);
  const auto la = omp->stirredSums(), lb = cuda->stirredSums();
  EXPECT_NEAR(la.lubrication_dissipated, lb.lubrication_dissipated, 1e-6 * la.lubrication_dissipated + 1e-15);
  // Collision starts: a contact beginning within rounding of the threshold may be counted on one side only.
  EXPECT_NEAR(la.totals.collisions, lb.totals.collisions, 1e-3 * la.totals.collisions + 2);
#endif
}
