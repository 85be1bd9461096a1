#pragma once
// Momentum dissipation for fluid particle a from neighbour b (paper eqs. 21-27). Each returns
// the contribution to dv_a/dt; r_ab = r_a - r_b, v_ab = v_a - v_b, grad_a W_ab = fac r_ab.
//
// ViscosityArtificial (Monaghan 1992, eq. 21): for v_ab . r_ab < 0,
//   mu = h v_ab.r_ab / (r^2 + eta^2),  Pi_ab = -alpha c0 mu / rho_bar,  dv_a/dt -= m_b Pi_ab grad W.
//   alpha is multiplied by visco_bound_factor for pairs with a boundary particle (paper: 0.1
//   in the wet mill).
// ViscosityLaminar, ViscosityLaminarSps (Lo & Shao 2002 + Dalrymple & Rogers 2006 SPS, eqs. 23-27):
//   dv_a/dt += m_b 4 nu (r_ab . grad W) / ((rho_a + rho_b)(r^2 + eta^2)) v_ab
//            + m_b (tau_a + tau_b) / (rho_a rho_b) . grad W,
//   tau from the previous step's strain rate (SpsStress below): nu_SPS = (Cs dp)^2 |S|,
//   |S| = sqrt(2 S_ij S_ij), tau_ij / rho = 2 nu_SPS (S_ij - S_kk delta_ij / 3)
//   - 2/3 C_I dp^2 |S|^2 delta_ij, Cs = 0.12, C_I = 0.0066.
// ViscosityLaminarCentral (Monaghan, Cleary & Gingold; Cleary 1998, Monaghan 2005 sec. 6.2):
//   dv_a/dt += m_b 2 xi nu (v_ab . r_ab) / ((rho_a + rho_b)(r^2 + eta^2)) grad W,  xi = 2 (d + 2),
//   i.e. nu (lap v + 2 grad div v), the same as Lo & Shao's nu lap v where the flow is
//   incompressible. The difference is where the force points: along r_ab (a central force).
//   Lo & Shao's pair force points along v_ab; the stress the fluid passes across a surface is
//   then mu grad v instead of mu (grad v + grad v^T), which is the same on a wall at rest or
//   translating (there the transpose part vanishes) but not on a turning one: a sphere turning
//   in fluid gets 2/3 of its torque, a cylinder 1/2 (the rigid rotation's part, mu Omega, is
//   missing), and the fluid's angular momentum is not conserved
//   (tests/validation/test_sph_rotating_sphere.cpp). The central force has both right. Its cost:
//   longitudinal waves diffuse at 3 nu k^2, so its viscous step limit is about a third of Lo &
//   Shao's (diffusion_stability.hpp).
// eta^2 = 0.01 h^2 (DualSPHysics; the paper prints "eta = 0.001 h^2", which is not a length:
// shared/reference/dualsphysics_anchor.md). It only matters as r -> 0.
#include <cmath>

#include "millsim/core/hd.hpp"
#include "millsim/core/vec3.hpp"

namespace millsim::sph {

using core::Vec3;

// Symmetric 3x3 tensor: xx, yy, zz, xy, xz, yz.
template <class T>
struct Sym3 {
  T xx, yy, zz, xy, xz, yz;
  MILLSIM_HD MILLSIM_FORCE_INLINE Sym3& operator+=(const Sym3& o) {
    xx += o.xx;
    yy += o.yy;
    zz += o.zz;
    xy += o.xy;
    xz += o.xz;
    yz += o.yz;
    return *this;
  }
  MILLSIM_HD Vec3<T> dot(Vec3<T> v) const {
    return {xx * v.x + xy * v.y + xz * v.z, xy * v.x + yy * v.y + yz * v.z, xz * v.x + yz * v.y + zz * v.z};
  }
};

template <class T>
MILLSIM_HD inline Sym3<T> zeroSym3() {
  return {T(0), T(0), T(0), T(0), T(0), T(0)};
}

template <class T>
struct ViscosityArtificial {
  static constexpr const char* kName = "artificial";
  static constexpr bool kNeedsStrain = false;
  T alpha = 0.1, alpha_bound = 0.1, h = 0, c0 = 0, eta2 = 0;
  MILLSIM_HD MILLSIM_FORCE_INLINE Vec3<T> operator()(Vec3<T> r_ab, Vec3<T> v_ab, T r2, T fac, T rho_a, T rho_b, T m_b,
                                                     bool bound, const Sym3<T>&, const Sym3<T>&) const {
    const T vr = core::dot(v_ab, r_ab);
    if (vr >= T(0)) return core::zero3<T>();
    const T mu = h * vr / (r2 + eta2);
    const T pi_ab = -(bound ? alpha_bound : alpha) * c0 * mu / (T(0.5) * (rho_a + rho_b));
    return (-m_b * pi_ab * fac) * r_ab;
  }
};

// Lo & Shao's laminar term alone (viscosity = laminar, or laminar_sps with Cs = C_I = 0): no
// strain rate to sum, no stress to read.
template <class T>
struct ViscosityLaminar {
  static constexpr const char* kName = "laminar";
  static constexpr bool kNeedsStrain = false;
  T nu = 1e-6, eta2 = 0;
  MILLSIM_HD MILLSIM_FORCE_INLINE Vec3<T> operator()(Vec3<T> /*r_ab*/, Vec3<T> v_ab, T r2, T fac, T rho_a, T rho_b,
                                                     T m_b, bool /*bound*/, const Sym3<T>& = {},
                                                     const Sym3<T>& = {}) const {
    return (m_b * T(4) * nu * fac * r2 / ((rho_a + rho_b) * (r2 + eta2))) * v_ab;
  }
};

// The central form of the laminar term (header): xi = 2 (d + 2).
template <class T>
struct ViscosityLaminarCentral {
  static constexpr const char* kName = "laminar_central";
  static constexpr bool kNeedsStrain = false;
  T nu = 1e-6, eta2 = 0, xi = 10;
  MILLSIM_HD MILLSIM_FORCE_INLINE Vec3<T> operator()(Vec3<T> r_ab, Vec3<T> v_ab, T r2, T fac, T rho_a, T rho_b, T m_b,
                                                     bool /*bound*/, const Sym3<T>& = {}, const Sym3<T>& = {}) const {
    return (m_b * T(2) * xi * nu * fac * core::dot(v_ab, r_ab) / ((rho_a + rho_b) * (r2 + eta2))) * r_ab;
  }
};

// The laminar term plus the SPS stress divergence.
template <class T>
struct ViscosityLaminarSps {
  static constexpr const char* kName = "laminar_sps";
  static constexpr bool kNeedsStrain = true;
  ViscosityLaminar<T> laminar;
  MILLSIM_HD MILLSIM_FORCE_INLINE Vec3<T> operator()(Vec3<T> r_ab, Vec3<T> v_ab, T r2, T fac, T rho_a, T rho_b, T m_b,
                                                     bool bound, const Sym3<T>& tau_a, const Sym3<T>& tau_b) const {
    Sym3<T> t = tau_a;
    t += tau_b;
    return laminar(r_ab, v_ab, r2, fac, rho_a, rho_b, m_b, bound) + (m_b * fac / (rho_a * rho_b)) * t.dot(r_ab);
  }
};

// Velocity gradient of particle a accumulated over its neighbours: grad v ~ sum_b V_b (v_b -
// v_a) (x) grad_a W_ab, stored as the symmetric strain rate S = (grad v + grad v^T) / 2.
template <class T>
MILLSIM_HD MILLSIM_FORCE_INLINE void addStrain(Sym3<T>& s, Vec3<T> v_ba, Vec3<T> grad_w, T vol_b) {
  s.xx += vol_b * v_ba.x * grad_w.x;
  s.yy += vol_b * v_ba.y * grad_w.y;
  s.zz += vol_b * v_ba.z * grad_w.z;
  s.xy += T(0.5) * vol_b * (v_ba.x * grad_w.y + v_ba.y * grad_w.x);
  s.xz += T(0.5) * vol_b * (v_ba.x * grad_w.z + v_ba.z * grad_w.x);
  s.yz += T(0.5) * vol_b * (v_ba.y * grad_w.z + v_ba.z * grad_w.y);
}

// SPS stress tau (Pa) of a particle from its strain rate S and density.
template <class T>
struct SpsStress {
  T smag = 0;  // (Cs dp)^2
  T blin = 0;  // 2/3 C_I dp^2
  MILLSIM_HD Sym3<T> operator()(const Sym3<T>& s, T rho) const {
    const T s2 = s.xx * s.xx + s.yy * s.yy + s.zz * s.zz + T(2) * (s.xy * s.xy + s.xz * s.xz + s.yz * s.yz);
    const T mag = std::sqrt(T(2) * s2);  // |S|
    const T nu_sps = smag * mag;
    const T tr3 = (s.xx + s.yy + s.zz) / T(3);
    const T iso = -blin * mag * mag;
    return {rho * (T(2) * nu_sps * (s.xx - tr3) + iso),
            rho * (T(2) * nu_sps * (s.yy - tr3) + iso),
            rho * (T(2) * nu_sps * (s.zz - tr3) + iso),
            rho * T(2) * nu_sps * s.xy,
            rho * T(2) * nu_sps * s.xz,
            rho * T(2) * nu_sps * s.yz};
  }
};

}  // namespace millsim::sph
