#pragma once
// DCDEM rigid bodies (paper eqs. 49-50; Canelas et al. 2016): a body is a set of element
// particles whose relative positions never change. Its mass, centre and inertia tensor come from
// the elements as point masses; the force and torque on it are the sums over its elements of
// what the DEM contacts (and gravity) put on each element:
//   M dV/dt = sum_k F_k,      dL/dt = sum_k [ (r_k - R) x F_k + T_k ],      L = I(q) Omega
// with I(q) = R(q) I_body R(q)^T. The integrator is velocity Verlet on (V, L) with the
// orientation q a unit quaternion: half kick, drift of R by V dt and of q by the rotation
// Omega dt (Omega taken at the half-rotated orientation: second order; exact when the inertia
// is isotropic, as for a lattice ball), half kick. Angular momentum is the kicked variable, so
// a torque-free body keeps L exactly and only its orientation carries the integration error.
//
// Functors run over bodies (kicks, drift, loads) or over element particles (placement), on
// OpenMP or CUDA through backend::parallelFor: the same code on both.
#include <cmath>

#include "millsim/core/hd.hpp"
#include "millsim/core/vec3.hpp"

namespace millsim::dem {

using core::Vec3;

// Unit quaternion w + (x, y, z): rotates body-frame vectors into the world frame.
template <class T>
struct Quat {
  T w, x, y, z;
};

template <class T>
MILLSIM_HD inline Quat<T> quatMul(Quat<T> a, Quat<T> b) {
  return {a.w * b.w - a.x * b.x - a.y * b.y - a.z * b.z, a.w * b.x + a.x * b.w + a.y * b.z - a.z * b.y,
          a.w * b.y - a.x * b.z + a.y * b.w + a.z * b.x, a.w * b.z + a.x * b.y - a.y * b.x + a.z * b.w};
}

template <class T>
MILLSIM_HD inline Quat<T> quatNormalized(Quat<T> q) {
  const T s = T(1) / std::sqrt(q.w * q.w + q.x * q.x + q.y * q.y + q.z * q.z);
  return {s * q.w, s * q.x, s * q.y, s * q.z};
}

// The rotation by the rotation vector phi (axis phi/|phi|, angle |phi|), exactly.
template <class T>
MILLSIM_HD inline Quat<T> quatFromRotationVector(Vec3<T> phi) {
  const T angle = core::norm(phi);
  const T half = T(0.5) * angle;
  // sin(a/2)/a by its series below 1e-4 rad (its error there is a^4/1920, below rounding).
  const T s = angle > T(1e-4) ? std::sin(half) / angle : T(0.5) - angle * angle / T(48);
  return {std::cos(half), s * phi.x, s * phi.y, s * phi.z};
}

// v' = q v q*, for unit q.
template <class T>
MILLSIM_HD inline Vec3<T> quatRotate(Quat<T> q, Vec3<T> v) {
  const Vec3<T> u{q.x, q.y, q.z};
  const Vec3<T> t = T(2) * core::cross(u, v);
  return v + q.w * t + core::cross(u, t);
}

template <class T>
MILLSIM_HD inline Vec3<T> quatRotateInverse(Quat<T> q, Vec3<T> v) {
  return quatRotate(Quat<T>{q.w, -q.x, -q.y, -q.z}, v);
}

// Symmetric 3x3 tensor (inertia and its inverse).
template <class T>
struct Sym3 {
  T xx, yy, zz, xy, xz, yz;
};

template <class T>
MILLSIM_HD inline Vec3<T> symApply(const Sym3<T>& a, Vec3<T> v) {
  return {a.xx * v.x + a.xy * v.y + a.xz * v.z, a.xy * v.x + a.yy * v.y + a.yz * v.z,
          a.xz * v.x + a.yz * v.y + a.zz * v.z};
}

// Inverse by cofactors; the caller guarantees a positive definite tensor.
template <class T>
MILLSIM_HD inline Sym3<T> symInverse(const Sym3<T>& a) {
  const T cxx = a.yy * a.zz - a.yz * a.yz, cyy = a.xx * a.zz - a.xz * a.xz, czz = a.xx * a.yy - a.xy * a.xy;
  const T cxy = a.xz * a.yz - a.xy * a.zz, cxz = a.xy * a.yz - a.xz * a.yy, cyz = a.xy * a.xz - a.xx * a.yz;
  const T det = a.xx * cxx + a.xy * cxy + a.xz * cxz;
  const T s = T(1) / det;
  return {s * cxx, s * cyy, s * czz, s * cxy, s * cxz, s * cyz};
}

// Omega = R I_body^-1 R^T L.
template <class T>
MILLSIM_HD inline Vec3<T> angularVelocity(Quat<T> q, const Sym3<T>& inv_inertia_body, Vec3<T> L) {
  return quatRotate(q, symApply(inv_inertia_body, quatRotateInverse(q, L)));
}

// Mass, centre and inertia tensor (about the centre) of point masses, eqs. 49-50's M, R, I.
struct RigidBodyMass {
  double mass = 0;
  Vec3<double> centre{0, 0, 0};
  Sym3<double> inertia{0, 0, 0, 0, 0, 0};
};

template <class PointAt, class MassAt>
inline RigidBodyMass rigidBodyMass(int count, PointAt point, MassAt mass) {
  RigidBodyMass b;
  for (int k = 0; k < count; ++k) {
    b.mass += mass(k);
    b.centre += mass(k) * point(k);
  }
  b.centre = (1.0 / b.mass) * b.centre;
  for (int k = 0; k < count; ++k) {
    const Vec3<double> r = point(k) - b.centre;
    const double m = mass(k), r2 = core::norm2(r);
    b.inertia.xx += m * (r2 - r.x * r.x);
    b.inertia.yy += m * (r2 - r.y * r.y);
    b.inertia.zz += m * (r2 - r.z * r.z);
    b.inertia.xy -= m * r.x * r.y;
    b.inertia.xz -= m * r.x * r.z;
    b.inertia.yz -= m * r.y * r.z;
  }
  return b;
}

// The bodies' arrays, one entry per body; elements of body b are the particles with host
// numbers start[b] .. start[b + 1] - 1, found at their current index through index_of_host.
template <class T>
struct BodyView {
  Vec3<T>* pos;      // centre of mass R
  Vec3<T>* vel;      // V
  Vec3<T>* ang_mom;  // L (world frame)
  Vec3<T>* omega;    // Omega, kept consistent with (q, L) by every functor that changes either
  Quat<T>* q;
  Vec3<T>* force;   // sum over the elements, from the last contact pass
  Vec3<T>* torque;  // about R
  const T* inv_mass;
  const Sym3<T>* inv_inertia_body;
  const int* start;
};

// Half kick: V += dt/2 F/M, L += dt/2 tau.
template <class T>
struct BodyKick {
  BodyView<T> b;
  T dt;
  MILLSIM_HD void operator()(int k) const {
    const T h = T(0.5) * dt;
    b.vel[k] += (h * b.inv_mass[k]) * b.force[k];
    b.ang_mom[k] += h * b.torque[k];
    b.omega[k] = angularVelocity(b.q[k], b.inv_inertia_body[k], b.ang_mom[k]);
  }
};

// Half kick, then drift: R += dt V, q <- exp(Omega(q_half) dt) q.
template <class T>
struct BodyKickDrift {
  BodyView<T> b;
  T dt;
  MILLSIM_HD void operator()(int k) const {
    BodyKick<T>{b, dt}(k);
    b.pos[k] += dt * b.vel[k];
    const Quat<T> q0 = b.q[k];
    const Vec3<T> L = b.ang_mom[k];
    const Quat<T> q_half =
        quatMul(quatFromRotationVector((T(0.5) * dt) * angularVelocity(q0, b.inv_inertia_body[k], L)), q0);
    const Vec3<T> w_half = angularVelocity(q_half, b.inv_inertia_body[k], L);
    b.q[k] = quatNormalized(quatMul(quatFromRotationVector(dt * w_half), q0));
    b.omega[k] = angularVelocity(b.q[k], b.inv_inertia_body[k], L);
  }
};

// The force and torque about R of body k's elements (gravity included: the contact pass puts
// m_k g on each element, and with R the elements' centre of mass its moment sums to zero).
template <class T>
struct BodyLoads {
  BodyView<T> b;
  const int* index_of_host;
  const Vec3<T>* offset;  // body frame, by host number: the lever arm is q r_body (exact in float,
                          // where x_element - R would lose digits to the positions' magnitude)
  const Vec3<T>* elem_force;
  const Vec3<T>* elem_torque;
  const Vec3<T>* ext_force = nullptr;  // per body, held (the fluid's), or none
  const Vec3<T>* ext_torque = nullptr;
  MILLSIM_HD void operator()(int k) const {
    Vec3<T> f = core::zero3<T>(), tq = core::zero3<T>();
    if (ext_force) {
      f = ext_force[k];
      tq = ext_torque[k];
    }
    const Quat<T> q = b.q[k];
    for (int h = b.start[k]; h < b.start[k + 1]; ++h) {
      const int i = index_of_host[h];
      const Vec3<T> fi = elem_force[i];
      f += fi;
      tq += elem_torque[i] + core::cross(quatRotate(q, offset[h]), fi);
    }
    b.force[k] = f;
    b.torque[k] = tq;
  }
};

// Work of a held external load on body k over a step: its power at the contact pass (V and
// Omega at the half step, as for spheres) times dt.
template <class T>
struct BodyExternalWork {
  BodyView<T> b;
  const Vec3<T>* ext_force;
  const Vec3<T>* ext_torque;
  double* work;
  T dt;
  MILLSIM_HD void operator()(int k) const {
    work[k] += double(core::dot(ext_force[k], b.vel[k]) + core::dot(ext_torque[k], b.omega[k])) * double(dt);
  }
};

// Places element i (current index) on its body: x = R + q r_body, v = V + Omega x (x - R), and
// the element spins with the body (its contact point velocity is the body's there).
template <class T>
struct PlaceElements {
  BodyView<T> b;
  const int* body_of;     // per current index; -1: a free sphere, left alone
  const int* id;          // host number per current index
  const Vec3<T>* offset;  // body-frame position of each element, by host number
  Vec3<T>* pos;
  Vec3<T>* vel;
  Vec3<T>* omega;
  MILLSIM_HD void operator()(int i) const {
    const int k = body_of[i];
    if (k < 0) return;
    const Vec3<T> r = quatRotate(b.q[k], offset[id[i]]);
    const Vec3<T> w = b.omega[k];
    pos[i] = b.pos[k] + r;
    vel[i] = b.vel[k] + core::cross(w, r);
    omega[i] = w;
  }
};

// index_of_host[id[i]] = i, after each renumbering.
struct InvertIds {
  const int* id;
  int* index_of_host;
  MILLSIM_HD void operator()(int i) const { index_of_host[id[i]] = i; }
};

}  // namespace millsim::dem
