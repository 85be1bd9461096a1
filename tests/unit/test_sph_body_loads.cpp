// The per-body sum of the fluid's load on a shell (sph::BodyLoadSum, with SlotOfId after a
// renumbering), against closed forms: a body whose particles all carry one acceleration a feels
// N m a and, its offsets centred, no torque; a ring of N particles at radius r pushed
// tangentially by a feels no force and the torque N m a r about the ring's axis. Fluid particles
// (large accelerations, not members) are interleaved and the slots shuffled as a cell sort would,
// so a member looked up in the wrong slot or a fluid particle summed shows at once. Tolerance
// 1e-12 relative: the sums are of O(100) doubles of O(1).
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <numeric>
#include <random>
#include <vector>

#include "millsim/backend/omp.hpp"
#include "sph/sph_kernels.hpp"

namespace millsim {
namespace {

using V = core::Vec3<double>;

TEST(SphBodyLoads, PerBodySumsMatchClosedFormsAfterARenumbering) {
  const double pi = std::acos(-1.0), mass = 0.125, r = 0.02;
  const int ring = 96, block = 64, fluid = 500;
  const V g{0.3, -9.81, 1.7};
  const double a_t = 4.0;
  // Host order: body 0 = a ring in the xy plane about its centre, body 1 = a centred 4x4x4
  // block, then fluid; slot order is a random permutation of it.
  std::vector<V> ace_host, offset_host;
  std::vector<int> body_host;
  for (int k = 0; k < ring; ++k) {
    const double phi = 2 * pi * k / ring;
    offset_host.push_back({r * std::cos(phi), r * std::sin(phi), 0.0});
    ace_host.push_back({-a_t * std::sin(phi), a_t * std::cos(phi), 0.0});
    body_host.push_back(0);
  }
  for (int k = 0; k < block; ++k) {
    offset_host.push_back({0.01 * (k % 4 - 1.5), 0.01 * (k / 4 % 4 - 1.5), 0.01 * (k / 16 - 1.5)});
    ace_host.push_back(g);
    body_host.push_back(1);
  }
  std::mt19937 rng(7);
  std::uniform_real_distribution<double> u(-1e3, 1e3);
  for (int k = 0; k < fluid; ++k) {
    offset_host.push_back({u(rng), u(rng), u(rng)});
    ace_host.push_back({u(rng), u(rng), u(rng)});
    body_host.push_back(-1);
  }
  const int n = static_cast<int>(ace_host.size());

  // Members by host number (CSR over the two bodies).
  const std::vector<int> start{0, ring, ring + block};
  std::vector<int> members(ring + block);
  std::iota(members.begin(), members.end(), 0);

  // The renumbering: slot s holds host particle id[s].
  std::vector<int> id(n);
  std::iota(id.begin(), id.end(), 0);
  std::shuffle(id.begin(), id.end(), rng);
  std::vector<V> ace(n), offset(n);
  for (int s = 0; s < n; ++s) {
    ace[s] = ace_host[id[s]];
    offset[s] = offset_host[id[s]];
  }
  std::vector<int> slot_of(n, -1);
  backend::parallelFor(backend::Omp{}, n, sph::SlotOfId{id.data(), slot_of.data()});

  std::vector<V> force(2), torque(2);
  backend::parallelFor(backend::Omp{}, 2,
                       sph::BodyLoadSum<double>{start.data(), members.data(), slot_of.data(), ace.data(),
                                                offset.data(), mass, force.data(), torque.data()});

  const double tol = 1e-12;
  // Ring: no net force, torque N m a r about +z.
  EXPECT_NEAR(force[0].x, 0.0, tol);
  EXPECT_NEAR(force[0].y, 0.0, tol);
  EXPECT_NEAR(force[0].z, 0.0, tol);
  EXPECT_NEAR(torque[0].x, 0.0, tol);
  EXPECT_NEAR(torque[0].y, 0.0, tol);
  EXPECT_NEAR(torque[0].z, ring * mass * a_t * r, tol * ring * mass * a_t * r);
  // Block: N m g, and no torque about its centre.
  EXPECT_NEAR(force[1].x, block * mass * g.x, tol * block * mass * 10);
  EXPECT_NEAR(force[1].y, block * mass * g.y, tol * block * mass * 10);
  EXPECT_NEAR(force[1].z, block * mass * g.z, tol * block * mass * 10);
  EXPECT_NEAR(torque[1].x, 0.0, tol);
  EXPECT_NEAR(torque[1].y, 0.0, tol);
  EXPECT_NEAR(torque[1].z, 0.0, tol);
}

}  // namespace
}  // namespace millsim
