// Analytic test objectives (see the header for the formulas).
#include "millsim/calib/analytic_objective.hpp"

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <cstring>

namespace millsim::calib {

Evaluation AnalyticObjective::evaluate(const Candidate& c) const {
  Evaluation ev;
  ev.candidate = c;
  ev.sse = m_f(c.e, c.mu);
  ev.ok = std::isfinite(ev.sse);
  if (!ev.ok) ev.error = "non-finite value";
  return ev;
}

AnalyticObjective smoothBowl(double e0, double mu0) {
  return AnalyticObjective("bowl", [e0, mu0](double e, double mu) {
    const double a = (e - e0) / 0.05, b = (mu - mu0) / 0.08;
    return a * a + b * b;
  });
}

AnalyticObjective curvedValley(double e0, double mu0) {
  return AnalyticObjective("valley", [e0, mu0](double e, double mu) {
    const double x = 1 + (e - e0) / 0.1, y = 1 + (mu - mu0) / 0.1;
    return (x - 1) * (x - 1) + 10 * (y - x * x) * (y - x * x);
  });
}

namespace {

// SplitMix64 finaliser: a well-mixed 64-bit hash, enough for test noise.
std::uint64_t mix(std::uint64_t z) {
  z += 0x9e3779b97f4a7c15ULL;
  z = (z ^ (z >> 30)) * 0xbf58476d1ce4e5b9ULL;
  z = (z ^ (z >> 27)) * 0x94d049bb133111ebULL;
  return z ^ (z >> 31);
}

std::uint64_t bits(double d) {
  std::uint64_t u;
  std::memcpy(&u, &d, sizeof u);
  return u;
}

// Standard normal from two hashed uniforms (Box-Muller).
double hashedNormal(double e, double mu, unsigned seed) {
  const std::uint64_t h1 = mix(bits(e) ^ mix(bits(mu) ^ mix(seed)));
  const std::uint64_t h2 = mix(h1);
  const double u1 = (static_cast<double>(h1 >> 11) + 0.5) / 9007199254740992.0;
  const double u2 = static_cast<double>(h2 >> 11) / 9007199254740992.0;
  return std::sqrt(-2 * std::log(u1)) * std::cos(2 * std::acos(-1.0) * u2);
}

}  // namespace

AnalyticObjective noisyBowl(double e0, double mu0, double sigma, unsigned seed) {
  return AnalyticObjective("noisy_bowl", [e0, mu0, sigma, seed](double e, double mu) {
    const double a = (e - e0) / 0.05, b = (mu - mu0) / 0.08;
    return std::max(0.0, a * a + b * b + sigma * hashedNormal(e, mu, seed));
  });
}

}  // namespace millsim::calib
