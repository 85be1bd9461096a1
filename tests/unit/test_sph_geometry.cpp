// Set-up geometry on one lattice (src/sph/geometry.hpp): fluid, drum end plates and body shells
// are cut from the same points, so the fluid meets every wall at dp, as it meets itself.
#include <gtest/gtest.h>

#include <array>
#include <cmath>
#include <set>
#include <tuple>

#include "sph/geometry.hpp"
#include "sph/sph_engine.hpp"
#include "sph/sph_pair.hpp"

using namespace millsim;

namespace {

using Point = std::tuple<double, double, double>;

std::set<Point> pointsWithCode(const sph::SphHostState& s, int code) {
  std::set<Point> out;
  for (std::size_t i = 0; i < s.size(); ++i)
    if (s.code[i] == code) out.insert({s.pos[3 * i], s.pos[3 * i + 1], s.pos[3 * i + 2]});
  return out;
}

}  // namespace

// The drum's slurry fills the layers k < drumAxialLayers(L, dp) (points at (k + 1/2) dp); the far
// end plate must start at the next layer, whatever L / dp is: no empty layer (a gap of 2 dp
// between fluid and plate, a slip layer) and no overlap. Lengths with a fractional L / dp of 0,
// 0.3, 0.5 (ball_mill_500_wet at dp = 4 mm: 150 / 4 = 37.5) and 0.7 and 0.9999. The plate's
// surface, half-way between its first layer and the fluid's last, must lie within dp/2 of L.
TEST(SphGeometry, DrumEndPlateFollowsTheLastFluidLayer) {
  const double dp = 0.004, R = 0.03;
  for (const double cells : {30.0, 30.3, 30.5, 37.5, 30.7, 30.9999}) {
    const double L = cells * dp;
    const int nz = sph::drumAxialLayers(L, dp);
    EXPECT_LT((nz - 0.5) * dp, L) << "L / dp = " << cells;  // the last fluid layer inside the drum
    sph::SphHostState s;
    sph::addDrumWalls(s, sph::DrumGeometry{R, L, 0, 0, 0, 0}, dp, 3, 1000.0);
    // The far plate's innermost layer on the axis (r < R: not the mantle).
    double first = 1e9;
    for (std::size_t i = 0; i < s.size(); ++i)
      if (std::hypot(s.pos[3 * i], s.pos[3 * i + 1]) < R && s.pos[3 * i + 2] > 0) first = std::min(first, s.pos[3 * i + 2]);
    const double last_fluid = (nz - 0.5) * dp;
    EXPECT_NEAR(first - last_fluid, dp, 1e-12) << "L / dp = " << cells;
    EXPECT_LE(std::abs(0.5 * (first + last_fluid) - L), 0.5 * dp + 1e-12) << "L / dp = " << cells;
  }
}

// A ball's shell cut from the fluid's lattice and the fluid carved for it split the lattice:
// every point of the box is fluid or shell, exactly one of the two (the box's corner is not a
// multiple of dp, so the shell must take the box's lattice origin). With the centre on a lattice
// point, r = 2 dp: 27 points lie within 2 dp, 33 with the six at exactly 2 dp, 57 with the 24 at
// sqrt(5) dp; the sphere's volume is 33.5 dp^3, so the cut keeps the 33 (the six ties together).
TEST(SphGeometry, ShellAndCarvedFluidSplitTheLattice) {
  const double dp = 0.01, rho0 = 1000;
  const sph::Box box{{0.1, 0.2, 0.3}, {0.2, 0.3, 0.4}};  // 10 x 10 x 10 points, lo not a multiple of dp
  const std::array<double, 3> origin = sph::cellCentredLattice(dp, box.lo);
  for (const double r : {2 * dp, 2.6 * dp, 3 * dp}) {
    sph::SphHostState s;
    sph::fillFluidBox(s, box, dp, 3, rho0);
    const std::size_t lattice_points = s.size();
    const std::array<double, 3> c{sph::latticeCoord(origin[0], dp, 5), sph::latticeCoord(origin[1], dp, 5),
                                  sph::latticeCoord(origin[2], dp, 4)};
    const sph::LatticeCut cut = sph::latticeCut(c, r, dp, 3, origin);
    sph::carveFluidForShell(s, c, cut);
    sph::addSphereShell(s, c, r, dp, 3, 10, 0, rho0, cut);  // 10 layers: the whole ball
    const std::set<Point> fluid = pointsWithCode(s, sph::kFluid), shell = pointsWithCode(s, sph::kBoundBody);
    EXPECT_EQ(fluid.size() + shell.size(), lattice_points) << "r = " << r / dp << " dp";
    for (const Point& p : shell) EXPECT_EQ(fluid.count(p), 0u) << "a shell point on a fluid one, r = " << r / dp;
    if (r == 2 * dp) {
      EXPECT_EQ(shell.size(), 33u);
    }
  }
}

// The cut holds as many lattice points as the body's volume / dp^3 to within half the step in
// count between two successive distances: for a generic centre (no ties) that is within 2% of
// the volume from a = 2.5 dp on (the cut at r itself: 0.86-1.19 at 2.5 dp, 0.95-1.11 at 3 dp,
// over 300 random centres), so the effective radius within 0.7%. Centres from the seed-fixed
// list below, each more than 0.01 dp from a symmetric spot; the cut lies strictly between two
// lattice distances.
TEST(SphGeometry, LatticeCutHoldsTheBodysVolume) {
  const double dp = 0.01, pi = std::acos(-1.0);
  const std::array<double, 3> origin = sph::cellCentredLattice(dp);
  for (const std::array<double, 3>& f : {std::array<double, 3>{0.42, 0.43, 0.53}, {0.06, 0.98, 0.02},
                                         {0.31, 0.17, 0.43}, {0.77, 0.61, 0.09}, {0.92, 0.94, 0.03}})
    for (const double a : {2.5, 3.0, 3.5, 4.0}) {
      const std::array<double, 3> c{f[0] * dp, f[1] * dp, 0.2 + f[2] * dp};
      sph::SphHostState s;
      sph::addSphereShell(s, c, a * dp, dp, 3, 10, 0, 1000.0, sph::latticeCut(c, a * dp, dp, 3, origin));
      const double volume = 4.0 / 3.0 * pi * a * a * a;
      EXPECT_NEAR(static_cast<double>(s.size()) / volume, 1.0, 0.02) << "a = " << a << " dp, centre " << f[0] << ", "
                                                                      << f[1] << ", " << f[2];
    }
}
