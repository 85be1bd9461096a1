#pragma once
// Restitution -> damping coefficient of the Hertz law F = k_n d^3/2 + gamma_n d^1/4 d'
// with gamma_n = alpha * sqrt(m* k_n). Host-side: evaluated once per case.
//
// Exact (default): alpha = sqrt(5) (-ln e) / sqrt(pi^2 + ln^2 e)  (Antypov & Elliott 2011,
//   EPL 94:50004). The substitution s = d^5/4 maps the d^1/4-damped Hertz oscillator exactly onto
//   a linear one with damping ratio alpha / sqrt(5), so e is the restitution actually obtained,
//   independent of impact speed (as long as the tensile force at the end is not clipped).
// DualSPHysics (compatibility): alpha = -2 ln e / sqrt(pi + ln^2 e) (JSphCpu InteractionForcesDEM,
//   note pi and not pi^2) and the wall's m* = m/2. It gives a lower real restitution (input 0.39
//   -> 0.234 ball-ball, 0.377 ball-wall); the paper's calibrated e = 0.390 is an input to it.
// See shared/reference/contact.md.
#include <cmath>
#include <string>

namespace millsim::dem {

enum class DampingModel { kExact, kDualSphysics };

inline constexpr double kPi = 3.14159265358979323846;

inline double dampingAlpha(DampingModel model, double e) {
  if (e >= 1.0) return 0.0;
  const double l = std::log(e);
  if (model == DampingModel::kExact) return std::sqrt(5.0) * (-l) / std::sqrt(kPi * kPi + l * l);
  return -2.0 * l / std::sqrt(kPi + l * l);
}

// m* used for a sphere-wall contact is wall_mass_factor * m.
inline double wallMassFactor(DampingModel model) { return model == DampingModel::kExact ? 1.0 : 0.5; }

inline DampingModel dampingModelFromName(const std::string& name) {
  return name == "dualsphysics" ? DampingModel::kDualSphysics : DampingModel::kExact;
}

// Effective modulus of two bodies of the same material: 1/E* = 2 (1 - nu^2) / E.
inline double effectiveModulus(double young, double poisson) { return young / (2.0 * (1.0 - poisson * poisson)); }

// Duration of an elastic Hertz impact at relative normal speed v (reference/contact.md):
// t_c = 2.868 (m*^2 / (R* E*^2 v))^(1/5).
inline double hertzContactTime(double m_star, double r_star, double e_star, double v) {
  return 2.868 * std::pow(m_star * m_star / (r_star * e_star * e_star * v), 0.2);
}

// Largest overlap of an elastic Hertz impact: (15 m* v^2 / (16 E* sqrt(R*)))^(2/5).
inline double hertzMaxOverlap(double m_star, double r_star, double e_star, double v) {
  return std::pow(15.0 * m_star * v * v / (16.0 * e_star * std::sqrt(r_star)), 0.4);
}

}  // namespace millsim::dem
