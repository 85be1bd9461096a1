#pragma once
// Linear spring-dashpot contact with a tangential spring, history and Coulomb limit: seed 004
// (stirred media mill) eqs. 2-4, the LIGGGHTS/LAMMPS gran/hooke/history family.
//
//   F_n = k_n d - gamma_n v_n,   gamma_n = 2 zeta sqrt(m* k_n),
//   zeta = -ln e / sqrt(pi^2 + ln^2 e)   (exact restitution e of a linear damped oscillator)
//   xi <- xi on the tangent plane + v_t dt,  F_t = -k_t xi - gamma_t v_t,  |F_t| <= mu max(F_n, 0)
//   k_t = 2/7 k_n (equal normal and tangential periods of a solid sphere, reference/contact.md),
//   gamma_t = gamma_n (seed eq. 3 uses the normal damping coefficient).
// Contact time t_c = pi / sqrt(k_n / m* (1 - zeta^2)). Energy: the pair's kinetic energy changes by
// -d(1/2 k_n d^2)/dt - gamma_n v_n^2 + F_t.v_t, so the dissipation rate returned is
// gamma_n v_n^2 - F_t.v_t and the elastic energy 1/2 k_n d^2.
// Units: SI; k_n [N/m] > 0, e in (0, 1], mu >= 0. Same interface and sign conventions as
// HertzMindlin (hertz.hpp): n from the partner to this particle, v_rel this particle's contact
// point velocity minus the partner's, force on this particle.
#include <cmath>

#include "dem/contact/hertz.hpp"
#include "millsim/core/hd.hpp"
#include "millsim/core/vec3.hpp"

namespace millsim::dem {

template <class T>
struct LinearSpringParams {
  T kn = 0;        // N/m
  T zeta = 0;      // damping ratio from the restitution
  T friction = 0;  // mu
};

inline double linearDampingRatio(double e) {
  if (e >= 1.0) return 0.0;
  const double l = std::log(e);
  return -l / std::sqrt(3.14159265358979323846 * 3.14159265358979323846 + l * l);
}

template <class T>
struct LinearSpringDashpot {
  LinearSpringParams<T> p;

  MILLSIM_HD ContactResult<T> operator()(core::Vec3<T> n, T delta, T /*r_star*/, T m_star, core::Vec3<T> v_rel,
                                         core::Vec3<T>& xi, T dt) const {
    using core::Vec3;
    const T kn = p.kn;
    const T gamma = T(2) * p.zeta * std::sqrt(m_star * kn);
    const T vn = core::dot(v_rel, n);
    const T fn = kn * delta - gamma * vn;
    const Vec3<T> vt = v_rel - vn * n;
    const T xi_len2 = core::norm2(xi);
    xi -= core::dot(xi, n) * n;
    const T new_len2 = core::norm2(xi);
    if (new_len2 > T(1e-6) * xi_len2 && new_len2 > T(0)) xi = std::sqrt(xi_len2 / new_len2) * xi;
    xi += dt * vt;
    const T kt = T(2) / T(7) * kn;
    Vec3<T> ft = -(kt * xi) - gamma * vt;
    const T limit = p.friction * (fn > T(0) ? fn : T(0));
    const T ft_len2 = core::norm2(ft);
    if (ft_len2 > limit * limit) {
      ft = ft_len2 > T(0) ? (limit / std::sqrt(ft_len2)) * ft : ft;
      xi = (T(-1) / kt) * ft;
    }
    ContactResult<T> r;
    r.force_t = ft;
    r.force = fn * n + ft;
    r.dissipation_rate = gamma * vn * vn - core::dot(ft, vt);
    r.elastic_energy = T(0.5) * kn * delta * delta;
    return r;
  }
};

}  // namespace millsim::dem
