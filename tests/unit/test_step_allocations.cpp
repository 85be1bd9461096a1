// "No allocation in the step loop" (the house rules; issue 10): once a run is going, a DEM step
// (neighbour rebuilds included) and a coupled SPH-DEM step (fluid loads to the balls, the balls'
// kinematics back to their shells, the fluid's cell sort and renumbering) make no host
// allocation. Counted here by replacing the global operator new of this test binary with one
// that counts while armed; the first steps, which size every buffer, are left out of the count.
// A step that allocates shows up as a count of at least the number of steps counted.
#include <gtest/gtest.h>

#include <atomic>
#include <cstdlib>
#include <new>
#include <random>
#include <vector>

#ifdef _OPENMP
#include <omp.h>
#endif

#include "support/dem_fixture.hpp"
#include "support/momentum_box.hpp"

namespace {
std::atomic<bool> g_counting{false};
std::atomic<long long> g_allocations{0};
}  // namespace

// Every form of new and delete is replaced, not only the plain one: std::stable_sort takes its
// buffer with the nothrow form, and under AddressSanitizer (which intercepts each form) a buffer
// from the library's nothrow new freed by this delete is an alloc-dealloc mismatch.
namespace {
void* countedAlloc(std::size_t n) noexcept {
  if (g_counting.load(std::memory_order_relaxed)) g_allocations.fetch_add(1, std::memory_order_relaxed);
  return std::malloc(n == 0 ? 1 : n);
}
}  // namespace

void* operator new(std::size_t n) {
  if (void* p = countedAlloc(n)) return p;
  throw std::bad_alloc();
}
void* operator new[](std::size_t n) { return operator new(n); }
void* operator new(std::size_t n, const std::nothrow_t&) noexcept { return countedAlloc(n); }
void* operator new[](std::size_t n, const std::nothrow_t&) noexcept { return countedAlloc(n); }
void operator delete(void* p) noexcept { std::free(p); }
void operator delete[](void* p) noexcept { std::free(p); }
void operator delete(void* p, std::size_t) noexcept { std::free(p); }
void operator delete[](void* p, std::size_t) noexcept { std::free(p); }
void operator delete(void* p, const std::nothrow_t&) noexcept { std::free(p); }
void operator delete[](void* p, const std::nothrow_t&) noexcept { std::free(p); }

namespace millsim {
namespace {

// Host allocations made by f().
template <class F>
long long allocationsOf(F&& f) {
  g_allocations = 0;
  g_counting = true;
  f();
  g_counting = false;
  return g_allocations.load();
}

TEST(StepAllocations, CounterSeesAnAllocation) {
  // The counter itself: a vector that grows is seen (else the zeros below would prove nothing).
  std::vector<int>* v = nullptr;
  EXPECT_GE(allocationsOf([&] { v = new std::vector<int>(100, 1); }), 2);
  delete v;
}

// f() with `threads` OpenMP threads (ctest runs each test on one): the threaded paths keep
// scratch of their own (the partner rows of the DEM and SPH pair loops), which must not grow in
// the step loop either.
template <class F>
void withThreads(int threads, F&& f) {
#ifdef _OPENMP
  const int before = omp_get_max_threads();
  omp_set_num_threads(threads);
  f();
  omp_set_num_threads(before);
#else
  (void)threads;
  f();
#endif
}

// ~600 balls of 4-5 mm falling at 1 m/s onto the bottom of a turning drum with lifters: the
// neighbour list is rebuilt several times in the counted steps (asserted), contacts form.
TEST(StepAllocations, DemStepsAllocateNothing) {
  std::vector<testing::Ball> balls;
  std::mt19937 rng(5);
  std::uniform_real_distribution<double> radius(0.004, 0.005), jitter(-5e-4, 5e-4), v(-0.2, 0.2);
  for (int iz = 0; iz < 3; ++iz)
    for (int iy = 0; iy < 14; ++iy)
      for (int ix = 0; ix < 14; ++ix)
        balls.push_back({-0.066 + 0.0095 * ix + jitter(rng), -0.12 + 0.0095 * iy + jitter(rng),
                         0.006 + 0.0095 * iz + jitter(rng), v(rng), v(rng) - 1.0, v(rng), radius(rng)});
  auto e = dem::makeDemEngineOmp(testing::drumSetup(0.4, 0.5, 0.004, 0.005, {-0.17, -0.17, -0.01}, {0.17, 0.17, 0.045}),
                                 false);
  e->setState(testing::hostState(balls, 7800.0));
  dem::DrumState w;
  w.radius = 0.16;
  w.z_back = 0.035;
  w.omega = 2.0;
  w.lifter_count = 8;
  w.lifter_height = 0.01;
  w.lifter_width = 0.01;
  const double dt = 5e-6;
  int k = 0;
  auto step = [&] {
    ++k;
    w.phi = w.omega * k * dt;
    e->step(w, dt);
  };
  e->initialize(w);
  for (int i = 0; i < 200; ++i) step();
  const auto rebuilds0 = e->neighbourRebuilds();
  const long long n = allocationsOf([&] {
    for (int i = 0; i < 2000; ++i) step();
  });
  EXPECT_GE(e->neighbourRebuilds() - rebuilds0, 3) << "the counted steps should include neighbour rebuilds";
  EXPECT_GT(e->sums().pair_contacts, 0);
  EXPECT_EQ(n, 0) << "host allocations in 2000 DEM steps";
}

// The same on two threads, with ~4 000 balls (above the OpenMP threshold, so each thread's
// partner rows are in use) landing in the turning drum; rebuilds in the counted steps.
TEST(StepAllocations, DemStepsOnTwoThreadsAllocateNothing) {
  withThreads(2, [] {
    auto e = dem::makeDemEngineOmp(
        testing::drumSetup(0.4, 0.5, 0.004, 0.005, {-0.17, -0.17, -0.01}, {0.17, 0.17, 0.095}), false);
    e->setState(testing::denseDrumBed());
    const double dt = 5e-6;
    e->initialize(testing::turningDrum(0));
    int k = 0;
    for (; k < 200; ++k) e->step(testing::turningDrum((k + 1) * dt), dt);
    const auto rebuilds0 = e->neighbourRebuilds();
    const long long n = allocationsOf([&] {
      for (int i = 0; i < 600; ++i, ++k) e->step(testing::turningDrum((k + 1) * dt), dt);
    });
    EXPECT_GE(e->neighbourRebuilds() - rebuilds0, 3) << "the counted steps should include neighbour rebuilds";
    EXPECT_EQ(n, 0) << "host allocations in 600 DEM steps on two threads";
  });
}

// The closed box of the momentum test (two balls in fluid, walls as a held body), both
// integrators, balls as spheres and as DCDEM bodies, on one thread and on two (the SPH pair
// loop's windowed partner rows).
TEST(StepAllocations, CoupledStepsAllocateNothing) {
  for (int threads : {1, 2})
    for (const char* integrator : {"verlet", "symplectic"})
      for (bool dcdem : {false, true})
        withThreads(threads, [&] {
          testing::MomentumBox box = testing::makeMomentumBox(integrator, dcdem);
          for (int i = 0; i < 3; ++i) box.advance();
          const long long n = allocationsOf([&] {
            for (int i = 0; i < 12; ++i) box.advance();
          });
          EXPECT_EQ(n, 0) << "host allocations in 12 coupled steps, " << integrator
                          << (dcdem ? ", DCDEM balls, " : ", spheres, ") << threads << " thread(s)";
          // What the coupling read every step before: a full host copy of the DEM state.
          EXPECT_GT(allocationsOf([&] { (void)dem::ballStates(*box.dem); }), 0);
        });
}

}  // namespace
}  // namespace millsim
