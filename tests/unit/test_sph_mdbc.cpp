// mDBC (src/sph/mdbc.hpp): the small dense solver, the ghost offsets the geometry gives, and
// the wall densities. The correction is first-order consistent, so a fluid whose density is a
// linear function of position gives every wall particle exactly that function's value at the
// wall particle, whatever the fluid's particle layout (here a jittered lattice), as long as its
// ghost node has fluid around it; a wrong sign in the gradient moment or the extrapolation
// misses by the gradient times a spacing (~1e-3 relative here, against the 1e-9 asserted:
// double round-off of sums of ~50 terms), and so does a ghost that lands beyond the fluid's
// reach (the Shepard fallback). Both dimensions, both kernels, the walls of a closed tank
// (faces, edges and corners), fixed and turning.
#include <gtest/gtest.h>

#include <array>
#include <cmath>
#include <cstdio>
#include <random>

#include "sph/geometry.hpp"
#include "sph/mdbc.hpp"
#include "sph/sph_engine.hpp"
#include "support/linear_wall_flow.hpp"

namespace millsim {
namespace {

TEST(SphMdbc, SmallSolverSolvesAndRefusesSingular) {
  double a[4][4] = {{4, 1, 0, 2}, {1, 5, 1, 0}, {0, 1, 6, 1}, {2, 0, 1, 7}};
  const double x_true[4] = {1.5, -2.0, 0.25, 3.0};
  double b[4];
  for (int r = 0; r < 4; ++r) {
    b[r] = 0;
    for (int c = 0; c < 4; ++c) b[r] += a[r][c] * x_true[c];
  }
  double x[4] = {};
  ASSERT_TRUE((sph::solveSmall<double, 4>(a, b, x, 1e-3)));
  for (int k = 0; k < 4; ++k) EXPECT_NEAR(x[k], x_true[k], 1e-12);
  // Rows 0 and 1 equal: det 0, refused, x untouched.
  double s[3][3] = {{1, 2, 3}, {1, 2, 3}, {0, 1, 1}}, sb[3] = {1, 1, 1}, sx[3] = {7, 7, 7};
  EXPECT_FALSE((sph::solveSmall<double, 3>(s, sb, sx, 1e-3)));
  EXPECT_EQ(sx[0], 7.0);
  // A zero first pivot is fine with pivoting.
  double p[3][3] = {{0, 1, 0}, {1, 0, 0}, {0, 0, 2}}, pb[3] = {3, 4, 10}, px[3] = {};
  ASSERT_TRUE((sph::solveSmall<double, 3>(p, pb, px, 1e-3)));
  EXPECT_NEAR(px[0], 4, 1e-15);
  EXPECT_NEAR(px[1], 3, 1e-15);
  EXPECT_NEAR(px[2], 5, 1e-15);
}

// rotate: the tank's walls are moving boundaries turned by a quarter turn about the tank's
// centre (the square tank maps onto itself), so each wall particle's ghost offset must have
// turned with it: unturned, the ghosts of a side wall's outer layers (the floor's, before the
// turn) point along the wall, out of the fluid's reach (checked: the test then fails).
void expectLinearFieldExtrapolated(int dim, const std::string& kernel, bool rotate = false) {
  const double dp = 0.01, rho0 = 1000;
  const double L = 0.12;  // 12 spacings each way
  const sph::Box box{{0, 0, 0}, {L, L, dim == 3 ? L : 0}};
  auto field = [&](double x, double y, double z) { return 1010 + 20 * x + 30 * y + (dim == 3 ? 25 * z : 0.0); };
  sph::SphHostState st;
  sph::fillFluidBox(st, box, dp, dim, rho0);
  std::mt19937 rng(4);
  std::uniform_real_distribution<double> jitter(-0.2 * dp, 0.2 * dp);
  for (std::size_t i = 0; i < st.size(); ++i)
    for (int a = 0; a < dim; ++a) st.pos[3 * i + a] += jitter(rng);
  sph::addTankWalls(st, box, dp, dim, 3, true, rotate ? sph::kBoundMoving : sph::kBoundFixed, rho0);
  ASSERT_EQ(st.ghost.size(), 3 * st.size());
  for (std::size_t i = 0; i < st.size(); ++i) st.rho[i] = field(st.pos[3 * i], st.pos[3 * i + 1], st.pos[3 * i + 2]);
  for (std::size_t i = 0; i < st.size(); ++i)
    if (st.code[i] != sph::kFluid) st.rho[i] = rho0;  // the walls' own value must not matter

  sph::SphSetup s;
  s.dimension = dim;
  s.kernel = kernel;
  s.dp = dp;
  s.h = std::sqrt(double(dim)) * dp;
  s.c0 = 10;
  s.rho0 = rho0;
  s.boundary = "mdbc";
  s.gravity = {0, 0, 0};
  s.rho_min = 900;
  s.rho_max = 1100;
  s.domain_lo = {-0.1, -0.1, -0.1};
  s.domain_hi = {L + 0.1, L + 0.1, L + 0.1};
  s.motion_center = {0.5 * L, 0.5 * L, 0};
  auto e = sph::makeSphEngineOmp(s);
  e->setState(st);
  sph::SphMotion quarter;
  quarter.theta = rotate ? 0.5 * std::acos(-1.0) : 0.0;
  e->initialize(quarter);  // one force evaluation: the walls take their mDBC densities
  sph::SphHostState out;
  e->getState(out);
  int walls = 0;
  double worst = 0;
  for (std::size_t i = 0; i < out.size(); ++i) {
    if (out.code[i] == sph::kFluid) continue;
    ++walls;
    const double want = field(out.pos[3 * i], out.pos[3 * i + 1], out.pos[3 * i + 2]);
    worst = std::max(worst, std::abs(out.rho[i] - want) / want);
  }
  EXPECT_GT(walls, 100);
  EXPECT_LT(worst, 1e-9) << dim << "D " << kernel << ": largest relative miss over " << walls << " walls";
}

TEST(SphMdbc, WallsTakeTheLinearFieldsValue2dWendland) { expectLinearFieldExtrapolated(2, "wendland"); }
TEST(SphMdbc, WallsTakeTheLinearFieldsValue2dCubic) { expectLinearFieldExtrapolated(2, "cubic"); }
TEST(SphMdbc, WallsTakeTheLinearFieldsValue3dWendland) { expectLinearFieldExtrapolated(3, "wendland"); }
TEST(SphMdbc, GhostsTurnWithMovingWalls) { expectLinearFieldExtrapolated(2, "wendland", true); }

TEST(SphMdbc, NoSlipGhostVelocityHoldsALinearShearFlow) {
  const double ghost = testing::linearWallFlowChange("no_slip_ghost"), adami = testing::linearWallFlowChange("no_slip");
  std::printf("near-floor velocity change / (dt nu gamma / dp): no_slip_ghost %.3g, no_slip (Adami) %.3g\n", ghost,
              adami);
  EXPECT_LT(ghost, 1e-9);
  EXPECT_GT(adami, 1e-2);  // the control: the check can see a wall velocity that is off
}

// A rigid rotation of fluid and walls: both wall velocities hold it to round-off, no_slip
// because it mirrors the fluid in the turning wall's own frame (WallNoSlipVelocity). Adami's
// original, the wall's velocity taken at the wall particle, changed the fluid by 2.9 dt nu
// gamma / dp here (a fluid turning with its wall was sheared by it).
TEST(SphMdbc, NoSlipVelocitiesHoldARigidRotationWithTurningWalls) {
  const double ghost = testing::linearWallFlowChange("no_slip_ghost", true),
               adami = testing::linearWallFlowChange("no_slip", true);
  std::printf("rigid rotation, velocity change / (dt nu gamma / dp): no_slip_ghost %.3g, no_slip (Adami) %.3g\n", ghost,
              adami);
  EXPECT_LT(ghost, 1e-9);
  EXPECT_LT(adami, 1e-9);
}

// Ghost offsets from the geometry: a tank's floor particle mirrors across the floor, a corner
// particle through the corner; a drum's mantle particle radially across R, a lifter's top
// particle across the lifter's top; a ball's shell particle radially across its surface.
TEST(SphMdbc, GhostOffsetsMirrorAcrossTheWallSurface) {
  sph::SphHostState tank;
  const sph::Box box{{0, 0, 0}, {0.1, 0.1, 0}};
  sph::addTankWalls(tank, box, 0.01, 2, 3, false, sph::kBoundFixed, 1000);
  for (std::size_t i = 0; i < tank.size(); ++i) {
    const double x = tank.pos[3 * i], y = tank.pos[3 * i + 1], gx = tank.ghost[3 * i], gy = tank.ghost[3 * i + 1];
    const double cx = std::clamp(x, 0.0, 0.1), cy = std::clamp(y, 0.0, 0.1);
    EXPECT_NEAR(x + gx, 2 * cx - x, 1e-15);
    EXPECT_NEAR(y + gy, 2 * cy - y, 1e-15);
  }
  sph::DrumGeometry d;
  d.radius = 0.1;
  d.length = 0.05;
  d.lifters = 4;
  d.lifter_height = 0.02;
  d.lifter_width = 0.02;
  d.first_angle = 0;                                      // lifter 0 along +x
  const auto mantle = sph::drumGhost(d, 0, 0.115, 0.02);  // 1.5 cm outside R on +y (between lifters)
  EXPECT_NEAR(mantle[0], 0, 1e-15);
  EXPECT_NEAR(mantle[1], -0.03, 1e-15);
  EXPECT_NEAR(mantle[2], 0, 1e-15);
  const auto top = sph::drumGhost(d, 0.0825, 0.0, 0.02);  // 2.5 mm inside lifter 0's top (u = 0.08)
  EXPECT_NEAR(top[0], -0.005, 1e-15);
  EXPECT_NEAR(top[1], 0, 1e-15);
  const auto side = sph::drumGhost(d, 0.095, 0.008, 0.02);  // 2 mm inside its +v side (v = 0.01)
  EXPECT_NEAR(side[0], 0, 1e-15);
  EXPECT_NEAR(side[1], 0.004, 1e-15);
  const auto plate = sph::drumGhost(d, 0.0, 0.03, -0.005);  // behind the front plate
  EXPECT_NEAR(plate[2], 0.01, 1e-15);
  sph::SphHostState ball;
  sph::addSphereShell(ball, {0, 0, 0}, 0.02, 0.005, 3, 2, 0, 1000);
  for (std::size_t i = 0; i < ball.size(); ++i) {
    const double r = std::hypot(ball.pos[3 * i], ball.pos[3 * i + 1], ball.pos[3 * i + 2]);
    const double rg = std::hypot(ball.pos[3 * i] + ball.ghost[3 * i], ball.pos[3 * i + 1] + ball.ghost[3 * i + 1],
                                 ball.pos[3 * i + 2] + ball.ghost[3 * i + 2]);
    if (r > 0) {
      EXPECT_NEAR(rg, 2 * 0.02 - r, 1e-15);
    }
  }
}

}  // namespace
}  // namespace millsim
