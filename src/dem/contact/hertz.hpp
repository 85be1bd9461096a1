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
  T k_coef = 0;    // 4/3 E*  [Pa]; k_n = k_coef sqrt(R*)
  T alpha = 0;     // damping: gamma_n = alpha sqrt(m* k_n)
  T friction = 0;  // mu
};

template <class T>
struct ContactResult {
  core::Vec3<T> force;    // total force on this particle
  core::Vec3<T> force_t;  // tangential part (for the torque)
  T dissipation_rate;     // damping power + tangential work rate [W] (>= 0 for damping)
  T elastic_energy;       // normal elastic energy 2/5 k_n d^5/2 [J] (tangential work is in the rate)
};

// The pair's constants k_n = k_coef sqrt(R*) and gamma_n / d^1/4 = alpha sqrt(m* k_n), which
// DualSPHysics's tangential law needs on their own. (Caching them per neighbour-list slot was
// measured slower on 49k balls: the extra 16 bytes a slot cost more memory traffic than the
// square roots they save.)
template <class T>
struct PairStiffness {
  T kn;
  T gamma0;
};

enum class FrictionSmoothing { kNone, kTanh };

template <class T>
MILLSIM_HD PairStiffness<T> hertzStiffness(const HertzParams<T>& p, T r_star, T m_star) {
  const T kn = p.k_coef * std::sqrt(r_star);
  return {kn, p.alpha * std::sqrt(m_star * kn)};
}

// The normal part shared by the laws: F_n = k_n d^3/2 - gamma_n d^1/4 v_n (eq. 51), written with
// the contact radius a = sqrt(R* d) so it takes two square roots, not four:
//   k_n d^1/2 = k_coef a,   gamma_n d^1/4 = alpha sqrt(m* k_n) d^1/4 = alpha sqrt(m* k_coef a).
template <class T>
struct HertzNormal {
  T fn;       // signed normal force (> 0 repulsive)
  T gamma;    // gamma_n d^1/4
  T k_tan;    // dF_n/dd of the elastic part: 3/2 k_n d^1/2
  T elastic;  // 2/5 k_n d^5/2
};

template <class T>
MILLSIM_HD HertzNormal<T> hertzNormal(const HertzParams<T>& p, T r_star, T m_star, T delta, T vn) {
  HertzNormal<T> h;
  const T kn_sqrt_delta = p.k_coef * std::sqrt(r_star * delta);  // k_n d^1/2
  h.gamma = p.alpha * std::sqrt(m_star * kn_sqrt_delta);
  h.fn = kn_sqrt_delta * delta - h.gamma * vn;
  h.k_tan = T(1.5) * kn_sqrt_delta;
  h.elastic = T(0.4) * kn_sqrt_delta * delta * delta;
  return h;
}

template <class T, FrictionSmoothing kSmoothing = FrictionSmoothing::kNone>
struct HertzMindlin {
  HertzParams<T> p;

  MILLSIM_HD MILLSIM_FORCE_INLINE ContactResult<T> operator()(core::Vec3<T> n, T delta, T r_star, T m_star, core::Vec3<T> v_rel,
                                         core::Vec3<T>& xi, T dt) const {
    using core::Vec3;
    const T vn = core::dot(v_rel, n);
    const HertzNormal<T> h = hertzNormal(p, r_star, m_star, delta, vn);
    const T gamma = h.gamma, fn = h.fn;

    const Vec3<T> vt = v_rel - vn * n;
    // Carry the spring onto the current tangent plane, keeping its length (rigid rotation).
    // The length ratio is 1/sqrt(1 - c), c = (xi.n)^2 / |xi|^2, and c is tiny (~theta^2 for
    // the angle theta the normal turned in one step, 1e-8 in a dense drum): there the series
    // 1 + c/2 + 3c^2/8 (error 5/16 c^3 < 1e-18 for c < 1e-6) replaces the square root, which
    // sat on the pair's dependency chain (measured in docs/performance.md).
    const T xi_len2 = core::norm2(xi);
    const T xn = core::dot(xi, n);
    xi -= xn * n;
    if (xi_len2 > T(0)) {
      const T c = xn * xn / xi_len2;
      if (c < T(1e-6)) xi = (T(1) + c * (T(0.5) + T(0.375) * c)) * xi;
      else if (c < T(1) - T(1e-6)) xi = (T(1) / std::sqrt(T(1) - c)) * xi;
    }
    xi += dt * vt;

    const T kt = T(2) / T(7) * h.k_tan;
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
    r.elastic_energy = h.elastic;
    return r;
  }
};

// DualSPHysics's own tangential law for DEM contacts of floating bodies (the paper's "Rigid
// Algorithm: DEM", Table 2; DualSPHysics 5.x JSphCpu::InteractionForcesDEM), as it is coded,
// which is not what the paper's eqs. 55-56 read: no spring and no history,
//   F_t = min(mu F_n tanh(8 |v_t|), (k_n dt - gamma_n) |v_t| / 3.5) along v_t / |v_t|,
// with gamma_n the normal damping coefficient without its d^1/4 factor and v_t in m/s. At the
// paper's settings (k_n = 2.6e6 N/m^1.5 for R* = dp/4, dt = 1e-5 s: k_n dt = 26, against
// gamma_n ~ 1.4e3 N s/m for two 35 mm balls at e = 0.39) the second term is negative, so the
// minimum is always that one: a viscous drag -(gamma_n - k_n dt) v_t / 3.5 that friction never
// caps (the Coulomb term only wins when F_n < 0). The normal part is eq. 51 as above.
template <class T>
struct HertzDualSphysicsTangential {
  HertzParams<T> p;

  MILLSIM_HD MILLSIM_FORCE_INLINE ContactResult<T> operator()(core::Vec3<T> n, T delta, T r_star, T m_star, core::Vec3<T> v_rel,
                                         core::Vec3<T>& xi, T dt) const {
    using core::Vec3;
    const PairStiffness<T> k = hertzStiffness(p, r_star, m_star);
    const T vn = core::dot(v_rel, n);
    const HertzNormal<T> h = hertzNormal(p, r_star, m_star, delta, vn);
    const Vec3<T> vt = v_rel - vn * n;
    const T vt_len = core::norm(vt);
    const T elastic_branch = (k.kn * dt - k.gamma0) * vt_len / T(3.5);
    const T coulomb_branch = p.friction * h.fn * std::tanh(T(8) * vt_len);
    const T ft_len = coulomb_branch < elastic_branch ? coulomb_branch : elastic_branch;
    const Vec3<T> ft = vt_len > T(0) ? (ft_len / vt_len) * vt : core::zero3<T>();
    xi = core::zero3<T>();  // no history
    ContactResult<T> r;
    r.force_t = ft;
    r.force = h.fn * n + ft;
    r.dissipation_rate = h.gamma * vn * vn - core::dot(ft, vt);
    r.elastic_energy = h.elastic;
    return r;
  }
};

}  // namespace millsim::dem
