#pragma once
// Gaussian-process regression on the unit square (Rasmussen & Williams, "Gaussian Processes
// for Machine Learning", 2006, eqs. 2.25-2.26 and 4.17) and expected improvement (Jones,
// Schonlau & Welch 1998, eq. 15), the surrogate of the default method (`--method bo`).
//
//   f ~ GP(m, s2 k),  k(x, x') = Matern 5/2 of r = |(x - x') / l| (one length scale per axis):
//     k = (1 + sqrt5 r + 5/3 r^2) exp(-sqrt5 r)
//   y_i = f(x_i) + eps_i,  eps ~ N(0, s2 g)   (g: nugget, relative to s2)
//   mean(x) = m + k_x^T (K + g I)^-1 (y - m 1),  var(x) = s2 (1 - k_x^T (K + g I)^-1 k_x)
// The constant mean m is the generalised-least-squares estimate and s2 its maximum-likelihood
// value given (l_e, l_mu, g) (both in closed form); (l_e, l_mu, g) maximise the marginal
// likelihood over a grid (fit()). Matern 5/2 rather than the squared exponential because the
// SSE of a simulation is not infinitely smooth and the squared exponential then gives
// over-confident, wiggly fits; the nugget because each simulated angle carries ~0.3-0.5 deg of
// seed noise (docs/validation.md), which the surrogate must average, not interpolate.
// var() is the variance of the latent f (without the nugget), the one expected improvement
// needs.
#include <vector>

#include "millsim/calib/param_box.hpp"

namespace millsim::calib {

struct GpHyper {
  double length_e = 0.3;   // length scale along e, in units of the e range
  double length_mu = 0.3;  // length scale along mu, in units of the mu range
  double nugget = 1e-6;    // noise variance / signal variance
  double signal_var = 1;   // s2; fit() sets it to its maximum-likelihood value
  double mean = 0;         // m; fit() sets it to its GLS estimate
};

class GaussianProcess {
 public:
  // With given hyperparameters (all of GpHyper used as is; for tests and the kriging believer).
  GaussianProcess(const std::vector<Point2>& points, const std::vector<double>& values, const GpHyper& hyper);

  // Maximum marginal likelihood over a grid of length scales (0.05..2 per axis) and nuggets
  // (1e-6..0.5); mean and signal variance in closed form. `min_nugget` floors the nugget grid.
  static GaussianProcess fit(const std::vector<Point2>& points, const std::vector<double>& values,
                             double min_nugget = 1e-6);

  double mean(const Point2& x) const;
  double variance(const Point2& x) const;  // latent f, >= 0
  const GpHyper& hyper() const { return m_hyper; }
  double logLikelihood() const { return m_log_likelihood; }

 private:
  std::vector<Point2> m_points;
  GpHyper m_hyper;
  std::vector<double> m_alpha;  // (K + g I)^-1 (y - m 1)
  std::vector<double> m_chol;   // lower Cholesky factor L of K + g I, row-major n x n
  double m_log_likelihood = 0;
};

// Matern 5/2 correlation of two points of the unit square with the given length scales.
double matern52(const Point2& a, const Point2& b, double length_e, double length_mu);

// Expected improvement below `best` of a normal prediction (mean, sd); 0 when sd = 0 and
// mean >= best.
double expectedImprovement(double mean, double sd, double best);

}  // namespace millsim::calib
