// Stirred-mill walls (src/dem/walls/stirrer_walls.hpp): volumes of the documented LS1-like
// geometry, and contacts with the chamber, plates, shaft, disk faces, rim and holes at known
// positions (hand-computed overlaps and normals, 1e-12 m in double).
#include <gtest/gtest.h>

#include <cmath>
#include <vector>

#include "dem/walls/stirrer_walls.hpp"
#include "millsim/scene/scene.hpp"

namespace {

using millsim::core::Vec3;
using millsim::dem::StirrerWalls;
using millsim::dem::WallContact;

constexpr double kPi = 3.14159265358979323846;

StirrerWalls<double> ls1Walls(double omega, double phi) {
  const millsim::scene::StirrerParams st;  // the Scene defaults are the LS1 geometry of docs/cases.md
  StirrerWalls<double> w{};
  w.radius = 0.5 * st.chamber_diameter;
  w.length = st.chamber_length;
  w.shaft_radius = 0.5 * st.shaft_diameter;
  w.omega = omega;
  w.disk_count = st.disk_count;
  w.disk_radius = 0.5 * st.disk_diameter;
  w.disk_half_thickness = 0.5 * st.disk_thickness;
  for (int k = 0; k < st.disk_count; ++k) w.disk_z[k] = st.chamber_length * (k + 0.5) / st.disk_count;
  w.hole_count = st.hole_count;
  w.hole_radius = 0.5 * st.hole_diameter;
  w.hole_ring_radius = 0.5 * st.hole_ring_diameter;
  for (int m = 0; m < st.hole_count; ++m) {
    w.hole_cos[m] = std::cos(phi + 2 * kPi * m / st.hole_count);
    w.hole_sin[m] = std::sin(phi + 2 * kPi * m / st.hole_count);
  }
  return w;
}

std::vector<WallContact<double>> contacts(const StirrerWalls<double>& w, Vec3<double> p, double r) {
  std::vector<WallContact<double>> out;
  w.forEachContact(p, r, [&](const WallContact<double>& c) { out.push_back(c); });
  return out;
}

TEST(StirrerWalls, Ls1VolumesMatchTheSeed) {
  // Seed 004: empty chamber 0.66 l (free volume with the stirrer), void volume 0.910 l (the
  // chamber without the stirrer, which the 43 % filling refers to). 1% tolerance: the geometry is
  // rounded to 0.5 mm.
  const millsim::scene::StirrerParams st;
  const auto v =
      millsim::dem::stirrerVolumes(0.5 * st.chamber_diameter, st.chamber_length, 0.5 * st.shaft_diameter, st.disk_count,
                                   0.5 * st.disk_diameter, st.disk_thickness, st.hole_count, 0.5 * st.hole_diameter);
  EXPECT_NEAR(v.chamber * 1e3, 0.910, 0.01 * 0.910);
  EXPECT_NEAR(v.free_volume * 1e3, 0.66, 0.01 * 0.66);
  // 128 000 beads of 1.8 mm are 43 % of the chamber volume (seed: 0.393 l, 43 %).
  const double solids = 128000 * kPi / 6 * std::pow(1.8e-3, 3);
  EXPECT_NEAR(solids / v.chamber, 0.43, 0.005);
}

TEST(StirrerWalls, ChamberPlatesAndShaft) {
  const double omega = 100.0, r = 0.9e-3;
  const auto w = ls1Walls(omega, 0.0);
  // Against the chamber, between two disks (z = L/4 is midway between disks 0 and 1).
  const double z = w.length / 4, R = w.radius;
  auto c = contacts(w, {R - r + 1e-5, 0, z}, r);
  ASSERT_EQ(c.size(), 1u);
  EXPECT_EQ(c[0].wall, 0);
  EXPECT_NEAR(c[0].delta, 1e-5, 1e-12);
  EXPECT_NEAR(c[0].n.x, -1.0, 1e-12);
  EXPECT_FALSE(StirrerWalls<double>::isMoving(c[0].wall));
  EXPECT_EQ(c[0].velocity.y, 0.0);
  // Front plate, away from the shaft.
  c = contacts(w, {0.03, 0, r - 2e-5}, r);
  ASSERT_EQ(c.size(), 1u);
  EXPECT_EQ(c[0].wall, 1);
  EXPECT_NEAR(c[0].delta, 2e-5, 1e-12);
  // Shaft: moving, surface velocity omega x p.
  const double rs = w.shaft_radius;
  c = contacts(w, {0, rs + r - 3e-5, z}, r);
  ASSERT_EQ(c.size(), 1u);
  EXPECT_EQ(c[0].wall, 3);
  EXPECT_TRUE(StirrerWalls<double>::isMoving(3));
  EXPECT_NEAR(c[0].delta, 3e-5, 1e-12);
  EXPECT_NEAR(c[0].n.y, 1.0, 1e-12);
  EXPECT_NEAR(c[0].velocity.x, -omega * rs, 1e-12);
}

TEST(StirrerWalls, DiskFaceRimAndHoles) {
  const double r = 0.9e-3, omega = 50.0;
  const auto w = ls1Walls(omega, 0.0);
  const double z0 = w.disk_z[1], ht = w.disk_half_thickness;
  // Face, between holes (angle 45 deg; holes at 0, 90, ...): overlap along +z.
  const double rho = 0.030, a = kPi / 4;
  auto c = contacts(w, {rho * std::cos(a), rho * std::sin(a), z0 + ht + r - 4e-5}, r);
  ASSERT_EQ(c.size(), 1u);
  EXPECT_EQ(c[0].wall, 5);
  EXPECT_NEAR(c[0].delta, 4e-5, 1e-12);
  EXPECT_NEAR(c[0].n.z, 1.0, 1e-12);
  EXPECT_NEAR(c[0].velocity.x, -omega * rho * std::sin(a), 1e-12);
  // Over the hole at angle 0 (centre on the ring): no face, so no contact while the bead fits.
  c = contacts(w, {w.hole_ring_radius, 0, z0 + ht + r - 4e-5}, r);
  EXPECT_TRUE(c.empty());
  // Inside the hole, against its wall (outward side): normal towards the hole axis.
  const double hx = w.hole_ring_radius, hr = w.hole_radius;
  c = contacts(w, {hx + hr - r + 5e-5, 0, z0}, r);
  ASSERT_EQ(c.size(), 1u);
  EXPECT_NEAR(c[0].delta, 5e-5, 1e-12);
  EXPECT_NEAR(c[0].n.x, -1.0, 1e-12);
  // At the hole's rim edge: centre above the face, inside the hole's circle.
  const double e = 0.5e-3;  // mm inside the circle and above the face
  c = contacts(w, {hx + hr - e, 0, z0 + ht + e}, r);
  ASSERT_EQ(c.size(), 1u);
  EXPECT_NEAR(c[0].delta, r - std::sqrt(2.0) * e, 1e-12);
  EXPECT_NEAR(c[0].n.x, -std::sqrt(0.5), 1e-12);
  EXPECT_NEAR(c[0].n.z, std::sqrt(0.5), 1e-12);
  // Beyond the rim, in the disk's plane: radial contact with the rim.
  const double R_d = w.disk_radius;
  c = contacts(w, {0, R_d + r - 6e-5, z0}, r);
  ASSERT_EQ(c.size(), 1u);
  EXPECT_NEAR(c[0].delta, 6e-5, 1e-12);
  EXPECT_NEAR(c[0].n.y, 1.0, 1e-12);
  // The holes turn with the stirrer: at phi = 45 deg the former face point is over a hole.
  const auto turned = ls1Walls(omega, kPi / 4);
  c = contacts(turned, {w.hole_ring_radius * std::cos(a), w.hole_ring_radius * std::sin(a), z0 + ht + r - 4e-5}, r);
  EXPECT_TRUE(c.empty());
}

}  // namespace
