// DCDEM rigid-body pieces (src/dem/rigid_body.hpp) against analytic mechanics: the inertia of a
// lattice ball, the torque-free precession of a symmetric top, the conservation of energy of a
// tumbling asymmetric body (with its intermediate-axis flips), and a constant torque.
#include <gtest/gtest.h>

#include <cmath>
#include <vector>

#include "dem/rigid_body.hpp"

using namespace millsim;
using namespace millsim::dem;
using core::Vec3;

namespace {

constexpr double kPi = 3.14159265358979323846;

struct OneBody {
  Vec3<double> pos{0, 0, 0}, vel{0, 0, 0}, L{0, 0, 0}, omega{0, 0, 0};
  Quat<double> q{1, 0, 0, 0};
  Vec3<double> force{0, 0, 0}, torque{0, 0, 0};
  double inv_mass = 1;
  Sym3<double> inv_inertia{1, 1, 1, 0, 0, 0};
  int start[2] = {0, 1};
  BodyView<double> view() { return {&pos, &vel, &L, &omega, &q, &force, &torque, &inv_mass, &inv_inertia, start}; }
  void step(double dt) {
    BodyKickDrift<double>{view(), dt}(0);
    BodyKick<double>{view(), dt}(0);
  }
  double kinetic(const Sym3<double>& inertia_body) const {
    const Vec3<double> wb = quatRotateInverse(q, omega);
    return 0.5 * core::dot(wb, symApply(inertia_body, wb));
  }
};

Sym3<double> diag(double a, double b, double c) { return {a, b, c, 0, 0, 0}; }

}  // namespace

// A ball of point masses on a cubic lattice (the paper's balls: particles at dp filling the
// sphere): cubic symmetry makes its inertia tensor exactly isotropic, and it tends to the solid
// sphere's 2/5 M rho^2 (rho the lattice radius) as rho/dp grows; measured 0.29% off at
// rho/dp = 10 and 0.08% at 40, asserted 0.5% and 0.15%.
TEST(RigidBody, LatticeBallInertiaIsIsotropicAndTendsToSolidSphere) {
  for (double ratio : {3.0, 10.0, 40.0}) {
    std::vector<Vec3<double>> pts;
    const int n = static_cast<int>(ratio) + 1;
    for (int i = -n; i <= n; ++i)
      for (int j = -n; j <= n; ++j)
        for (int k = -n; k <= n; ++k) {
          const Vec3<double> p{double(i), double(j), double(k)};
          if (core::norm2(p) <= ratio * ratio + 1e-9) pts.push_back(p);
        }
    const RigidBodyMass b = rigidBodyMass(
        static_cast<int>(pts.size()), [&](int k) { return pts[k]; }, [](int) { return 2.0; });
    EXPECT_DOUBLE_EQ(b.mass, 2.0 * pts.size());
    EXPECT_NEAR(core::norm(b.centre), 0.0, 1e-12);
    EXPECT_NEAR(b.inertia.yy / b.inertia.xx, 1.0, 1e-13);
    EXPECT_NEAR(b.inertia.zz / b.inertia.xx, 1.0, 1e-13);
    EXPECT_NEAR(b.inertia.xy, 0.0, 1e-9 * b.inertia.xx);
    const double rel = b.inertia.xx / (0.4 * b.mass * ratio * ratio) - 1.0;
    if (ratio == 10.0) {
      EXPECT_LT(std::fabs(rel), 5e-3);
    }
    if (ratio == 40.0) {
      EXPECT_LT(std::fabs(rel), 1.5e-3);
    }
  }
}

// Inertia of an off-centre pair about their centre: two masses m at +-a on x give I_yy = I_zz =
// 2 m a^2, I_xx = 0; tilted into the xy plane at 45 degrees the product of inertia appears.
TEST(RigidBody, PointMassTensorOfATiltedDumbbell) {
  const double a = 0.3, m = 1.5, c = std::sqrt(0.5);
  const Vec3<double> pts[2] = {{1 + a * c, 2 + a * c, 3}, {1 - a * c, 2 - a * c, 3}};
  const RigidBodyMass b = rigidBodyMass(
      2, [&](int k) { return pts[k]; }, [&](int) { return m; });
  EXPECT_NEAR(b.centre.x, 1.0, 1e-15);
  EXPECT_NEAR(b.centre.y, 2.0, 1e-15);
  EXPECT_NEAR(b.inertia.zz, 2 * m * a * a, 1e-14);
  EXPECT_NEAR(b.inertia.xx, m * a * a, 1e-14);
  EXPECT_NEAR(b.inertia.xy, -m * a * a, 1e-14);
}

// Torque-free symmetric top (I1 = I2 != I3): L stays fixed in space and the symmetry axis turns
// about it at the rate |L| / I1 (Landau & Lifshitz, Mechanics, section 33). Over five precession
// periods the axis error is second order in dt (measured 2.3e-4 rad at 2000 steps per period,
// 5.8e-5 at 4000: ratio 0.250), and |L| is kept exactly (it is the kicked variable).
namespace {
double topAxisError(int steps_per_period, OneBody* out = nullptr) {
  const double i1 = 2.0, i3 = 0.5;
  OneBody b;
  b.inv_inertia = symInverse(diag(i1, i1, i3));
  // Symmetry axis e3 tilted 30 degrees from L = |L| z.
  const double tilt = kPi / 6, Lmag = 3.0;
  const Quat<double> q0 = quatFromRotationVector(Vec3<double>{tilt, 0, 0});
  b.q = q0;
  b.L = {0, 0, Lmag};
  b.omega = angularVelocity(b.q, b.inv_inertia, b.L);
  const double rate = Lmag / i1;
  const int steps = 5 * steps_per_period;
  const double t_end = 5 * 2 * kPi / rate, dt = t_end / steps;
  for (int s = 0; s < steps; ++s) b.step(dt);
  const Vec3<double> axis0 = quatRotate(q0, Vec3<double>{0, 0, 1});
  const Vec3<double> expected = quatRotate(quatFromRotationVector(Vec3<double>{0, 0, rate * t_end}), axis0);
  if (out) *out = b;
  return core::norm(quatRotate(b.q, Vec3<double>{0, 0, 1}) - expected);
}
}  // namespace

TEST(RigidBody, SymmetricTopPrecessesAtLOverI1) {
  OneBody b;
  const double coarse = topAxisError(2000, &b), fine = topAxisError(4000);
  EXPECT_LT(coarse, 3e-4);
  EXPECT_NEAR(fine / coarse, 0.25, 0.03);
  EXPECT_DOUBLE_EQ(b.L.z, 3.0);
  EXPECT_DOUBLE_EQ(b.L.x, 0.0);
}

// Asymmetric body spun close to its intermediate axis flips over and over (Dzhanibekov); with
// no torque its kinetic energy L . Omega / 2 must stay constant: to 1e-6 relative over 3 flips.
TEST(RigidBody, TumblingAsymmetricBodyConservesEnergyAndFlips) {
  const Sym3<double> inertia = diag(1.0, 2.0, 3.0);
  OneBody b;
  b.inv_inertia = symInverse(inertia);
  b.L = symApply(inertia, Vec3<double>{0.05, 5.0, 0.0});  // body = world frame at t = 0
  b.omega = angularVelocity(b.q, b.inv_inertia, b.L);
  const double e0 = b.kinetic(inertia);
  int flips = 0;
  double last_sign = 1;
  const double dt = 2e-4;
  for (int s = 0; s < 60000; ++s) {
    b.step(dt);
    const double w2 = quatRotateInverse(b.q, b.omega).y;
    if (w2 * last_sign < 0) {
      ++flips;
      last_sign = -last_sign;
    }
    ASSERT_NEAR(b.kinetic(inertia) / e0, 1.0, 1e-6) << "step " << s;
  }
  EXPECT_GE(flips, 3);
}

// A constant torque along a principal axis from rest spins the body up linearly: the angle
// turned is tau t^2 / (2 I); a constant force moves the centre by F t^2 / (2 M). Both exact for
// velocity Verlet.
TEST(RigidBody, ConstantTorqueAndForceAreIntegratedExactly) {
  OneBody b;
  b.inv_mass = 1 / 4.0;
  b.inv_inertia = symInverse(diag(5.0, 5.0, 0.8));
  b.force = {0, 0, -2.0};
  b.torque = {0, 0, 0.4};
  const double dt = 1e-3;
  const int steps = 1000;
  for (int s = 0; s < steps; ++s) b.step(dt);
  const double t = steps * dt;
  EXPECT_NEAR(b.pos.z, -2.0 * t * t / (2 * 4.0), 1e-12);
  EXPECT_NEAR(b.omega.z, 0.4 * t / 0.8, 1e-12);
  const Vec3<double> x = quatRotate(b.q, Vec3<double>{1, 0, 0});
  EXPECT_NEAR(std::atan2(x.y, x.x), 0.4 * t * t / (2 * 0.8), 1e-12);
}
