#pragma once
// Cheap objectives with known minima for tests and method comparisons: an SSE function of
// (e, mu) evaluated in microseconds. The noisy one adds a deterministic pseudo-random term per
// candidate (hash of e and mu), so results do not depend on thread scheduling.
#include <functional>
#include <string>

#include "millsim/calib/objective.hpp"

namespace millsim::calib {

class AnalyticObjective : public Objective {
 public:
  using Function = std::function<double(double e, double mu)>;
  AnalyticObjective(std::string name, Function f) : m_name(std::move(name)), m_f(std::move(f)) {}
  Evaluation evaluate(const Candidate& c) const override;
  std::string signature() const override { return "analytic:" + m_name; }

 private:
  std::string m_name;
  Function m_f;
};

// Quadratic bowl, minimum 0 at (e0, mu0); scales chosen so the box edges give SSE ~ 1..10
// like the angle SSE: sse = ((e - e0) / 0.05)^2 + ((mu - mu0) / 0.08)^2.
AnalyticObjective smoothBowl(double e0, double mu0);

// Narrow curved valley: a Rosenbrock-type banana in scaled coordinates x = 1 + (e - e0) / 0.1,
// y = 1 + (mu - mu0) / 0.1: sse = (x - 1)^2 + 10 (y - x^2)^2. The floor is the parabola
// y = x^2, rising only as (x - 1)^2 along it while the walls are 10 times steeper (100, as in
// Rosenbrock, makes it 0.003 wide in mu at SSE 0.1, narrower than any proposal spacing); the
// minimum 0 is at (e0, mu0).
AnalyticObjective curvedValley(double e0, double mu0);

// smoothBowl plus noise of standard deviation `sigma` on the SSE (an angle noise of s deg per
// diameter gives an SSE noise of ~ 2 s |error| + s^2), floored at 0.
AnalyticObjective noisyBowl(double e0, double mu0, double sigma, unsigned seed = 1);

}  // namespace millsim::calib
