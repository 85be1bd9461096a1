#include "dem/dcdem_bodies.hpp"

#include <algorithm>
#include <cmath>
#include <stdexcept>

#include "dem/rigid_body.hpp"

namespace millsim::dem {

using core::Vec3;

std::vector<Vec3<double>> latticeBallPoints(double radius, double dp) {
  if (!(dp > 0) || !(radius >= 0.5 * dp))
    throw std::invalid_argument("latticeBallPoints: need dp > 0 and radius >= dp/2");
  const double reach = radius - 0.5 * dp;
  const int n = static_cast<int>(std::floor(reach / dp + 1e-9));
  std::vector<Vec3<double>> pts;
  for (int i = -n; i <= n; ++i)
    for (int j = -n; j <= n; ++j)
      for (int k = -n; k <= n; ++k) {
        const Vec3<double> p{i * dp, j * dp, k * dp};
        if (core::norm(p) <= reach * (1 + 1e-12)) pts.push_back(p);
      }
  return pts;
}

void BodyAssembler::addBody(const std::vector<Vec3<double>>& points, double element_radius, double mass,
                            std::array<double, 3> v, std::array<double, 3> w, double outer_radius) {
  if (points.empty() || !(mass > 0)) throw std::invalid_argument("BodyAssembler::addBody: empty body or mass <= 0");
  const int count = static_cast<int>(points.size());
  const double share = mass / count;
  const RigidBodyMass b = rigidBodyMass(
      count, [&](int k) { return points[k]; }, [&](int) { return share; });
  // Fewer than three non-collinear elements have a singular inertia tensor (no rotation about
  // their line): such a body cannot be integrated.
  const Sym3<double>& J = b.inertia;
  const double det =
      J.xx * (J.yy * J.zz - J.yz * J.yz) - J.xy * (J.xy * J.zz - J.yz * J.xz) + J.xz * (J.xy * J.yz - J.yy * J.xz);
  const double scale = J.xx + J.yy + J.zz;
  if (!(det > 1e-9 * scale * scale * scale))
    throw std::invalid_argument(
        "BodyAssembler::addBody: the elements lie on a line or a point (singular inertia); "
        "use a finer element spacing");
  const Vec3<double> V{v[0], v[1], v[2]}, W{w[0], w[1], w[2]};
  double bounding = 0;
  for (const Vec3<double>& p : points) {
    const Vec3<double> r = p - b.centre;
    bounding = std::max(bounding, core::norm(r) + element_radius);
    const Vec3<double> vel = V + core::cross(W, r);
    m_state.pos.insert(m_state.pos.end(), {p.x, p.y, p.z});
    m_state.vel.insert(m_state.vel.end(), {vel.x, vel.y, vel.z});
    m_state.omega.insert(m_state.omega.end(), {W.x, W.y, W.z});
    m_state.radius.push_back(element_radius);
    m_state.mass.push_back(share);
    m_state.inertia.push_back(0.0);
    // The body frame is the world frame at the start (orientation 1).
    m_bodies.offset.insert(m_bodies.offset.end(), {r.x, r.y, r.z});
  }
  m_state.dissipated.resize(m_state.size(), 0.0);
  m_state.work_in.resize(m_state.size(), 0.0);
  m_bodies.start.push_back(m_bodies.start.back() + count);
  m_bodies.pos.insert(m_bodies.pos.end(), {b.centre.x, b.centre.y, b.centre.z});
  m_bodies.vel.insert(m_bodies.vel.end(), {v[0], v[1], v[2]});
  const Vec3<double> L = symApply(b.inertia, W);
  m_bodies.ang_mom.insert(m_bodies.ang_mom.end(), {L.x, L.y, L.z});
  m_bodies.quat.insert(m_bodies.quat.end(), {1.0, 0.0, 0.0, 0.0});
  m_bodies.mass.push_back(mass);
  m_bodies.radius.push_back(outer_radius > 0 ? outer_radius : bounding);
  const Sym3<double>& I = b.inertia;
  m_bodies.inertia.insert(m_bodies.inertia.end(), {I.xx, I.yy, I.zz, I.xy, I.xz, I.yz});
}

DemHostState ballStates(const DemEngine& engine) {
  DemBodies b;
  engine.getBodies(b);
  DemHostState s;
  if (b.size() == 0) {
    engine.getState(s);
    return s;
  }
  const std::size_t n = b.size();
  const std::vector<double> none(n, 0.0);
  s.pos = b.pos;
  s.vel = b.vel;
  s.mass = b.mass;
  s.radius = b.radius;
  s.omega.resize(3 * n);
  for (std::size_t k = 0; k < n; ++k) {
    const double* I = &b.inertia[6 * k];
    const Quat<double> q{b.quat[4 * k], b.quat[4 * k + 1], b.quat[4 * k + 2], b.quat[4 * k + 3]};
    const Vec3<double> w = angularVelocity(q, symInverse(Sym3<double>{I[0], I[1], I[2], I[3], I[4], I[5]}),
                                           Vec3<double>{b.ang_mom[3 * k], b.ang_mom[3 * k + 1], b.ang_mom[3 * k + 2]});
    s.omega[3 * k] = w.x;
    s.omega[3 * k + 1] = w.y;
    s.omega[3 * k + 2] = w.z;
  }
  s.inertia = none;
  s.dissipated = none;
  s.work_in = none;
  return s;
}

}  // namespace millsim::dem
