#pragma once
// Hertz normal contact with d^1/4 viscous damping and a Mindlin-type tangential spring with
// history and a Coulomb limit (paper eqs. 51-56; shared/reference/contact.md).
//
//   F_n = k_n d^3/2 - gamma_n d^1/4 v_n,   k_n = 4/3 E* sqrt(R*),   gamma_n = alpha sqrt(m* k_n)
//   k_t = 2/7 * dF_n/dd = 2/7 * 3/2 k_n sqrt(d),   gamma_t = 2/7 gamma_n d^1/4
//   xi  <- xi projected on the tangent plane + v_t dt,  F_t = -k_t xi - gamma_t v_t (sticking),
//   |F_t| <= mu max(F_n, 0) [* tanh(8 |v_t| / (1 m/s)) with the paper's smoothing, eq. 55]
// Energy: d(KE)/dt of a pair = -d(2/5 k_n d^5/2)/dt - gamma_n d^1/4 v_n^2 + F_t . v_t, so the
// dissipation rate returned is gamma_n d^1/4 v_n^2 - F_t . v_t (it includes the small elastic energy
// momentarily stored in the tangential spring).
// The paper writes k_t = 2/7 k_n with k_n in N/m^1.5; we apply the 2/7 ratio (equal normal and
// tangential periods for a solid sphere) to the tangent normal stiffness so k_t is in N/m.
//
// Units: SI. Valid for d >= 0 small against R*; e in (0, 1]; mu >= 0.
// Sign convention: n points from the partner to this particle; v_rel is this particle's contact
// point velocity minus the partner's; the force returned acts on this particle. Both sides of a
// pair call the law with mirrored inputs and get exactly opposite forces.
#include <cmath>

#include "millsim/core/hd.hpp"
#include "millsim/core/vec3.hpp"

namespace millsim::dem {

template <class T>
struct HertzParams {
  T k_coef = 0;      // 4/3 E*  [Pa]; k_n = k_coef sqrt(R*)
  T alpha = 0;       // damping: gamma_n = alpha sqrt(m* k_n)
  T friction = 0;    // mu
};

template <class T>
struct ContactResult {
  core::Vec3<T> force;    // total force on this particle
  core::Vec3<T> force_t;  // tangential part (for the torque)
  T dissipation_rate;     // damping power + tangential work rate [W] (>= 0 for damping)
  T elastic_energy;       // normal elastic energy 2/5 k_n d^5/2 [J] (tangential work is in the rate)
};

// The pair's constants: k_n = k_coef sqrt(R*) and gamma_n / d^1/4 = alpha sqrt(m* k_n). (Caching
// them per neighbour-list slot was measured slower on 49k balls: the extra 16 bytes a slot cost
// more memory traffic than the two square roots they save.)
template <class T>
struct PairStiffness {
  T kn;
  T gamma0;
};

enum class FrictionSmoothing { kNone, kTanh };

template <class T, FrictionSmoothing kSmoothing = FrictionSmoothing::kNone>
struct HertzMindlin {
  HertzParams<T> p;

  MILLSIM_HD PairStiffness<T> stiffness(T r_star, T m_star) const {
    const T kn = p.k_coef * std::sqrt(r_star);
    return {kn, p.alpha * std::sqrt(m_star * kn)};
  }

  MILLSIM_HD ContactResult<T> operator()(core::Vec3<T> n, T delta, T r_star, T m_star, core::Vec3<T> v_rel,
                                         core::Vec3<T>& xi, T dt) const {
    return (*this)(n, delta, stiffness(r_star, m_star), v_rel, xi, dt);
  }

  MILLSIM_HD ContactResult<T> operator()(core::Vec3<T> n, T delta, PairStiffness<T> k, core::Vec3<T> v_rel,
                                         core::Vec3<T>& xi, T dt) const {
    using core::Vec3;
    const T sqrt_delta = std::sqrt(delta);
    const T kn = k.kn;
    const T delta14 = std::sqrt(sqrt_delta);
    const T gamma = k.gamma0 * delta14;  // gamma_n d^1/4
    const T vn = core::dot(v_rel, n);
    const T fn = kn * delta * sqrt_delta - gamma * vn;

    const Vec3<T> vt = v_rel - vn * n;
    // Carry the spring onto the current tangent plane, keeping its length (rigid rotation).
    const T xi_len2 = core::norm2(xi);
    xi -= core::dot(xi, n) * n;
    const T new_len2 = core::norm2(xi);
    if (new_len2 > T(1e-6) * xi_len2 && new_len2 > T(0)) xi = std::sqrt(xi_len2 / new_len2) * xi;
    xi += dt * vt;

    const T kt = T(3) / T(7) * kn * sqrt_delta;
    const T gt = T(2) / T(7) * gamma;
    Vec3<T> ft = -(kt * xi) - gt * vt;
    T limit = p.friction * (fn > T(0) ? fn : T(0));
    if constexpr (kSmoothing == FrictionSmoothing::kTanh) limit *= std::tanh(T(8) * core::norm(vt));
    const T ft_len2 = core::norm2(ft);
    if (ft_len2 > limit * limit) {
      // Sliding: F_t on the Coulomb cone, and the spring alone is set to carry it (xi = -F_t/k_t).
      // Folding the damping into the spring instead (xi = -(F_t + g_t v_t)/k_t) makes the spring
      // point along the slip when k_t grows during loading, and friction then pushes forward.
      ft = (limit / std::sqrt(ft_len2)) * ft;
      xi = (kt > T(0) ? T(-1) / kt : T(0)) * ft;
    }
    ContactResult<T> r;
    r.force_t = ft;
    r.force = fn * n + ft;
    r.dissipation_rate = gamma * vn * vn - core::dot(ft, vt);
    r.elastic_energy = T(0.4) * kn * delta * delta * sqrt_delta;
    return r;
  }
};

}  // namespace millsim::dem
