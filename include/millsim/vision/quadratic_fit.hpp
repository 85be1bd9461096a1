#pragma once
// Quadratic least squares with a 95 % confidence band of the fitted curve, for the slurry free
// surface (Doroszek et al. 2024, section 3.7.3 step 3 and section 3.8.2: "quadratic equation
// curve approach, a 95 % confidence interval was calculated"; Figures 19, 22, 23).
//
//   y = c0 + c1 x + c2 x^2,  beta = (X'X)^-1 X'y,
//   band(x) = yhat(x) -/+ t_{1-alpha/2, dof} sqrt(f(x)' V f(x)),  f(x) = (1, x, x^2)'.
//
// V is the covariance of the coefficients:
// - independent points (manually picked, one label each): V = s^2 (X'X)^-1,
//   s^2 = SSR / (n - 3), dof = n - 3 (the textbook band of the mean response);
// - points grouped by frame (automatic detection gives many points per frame that share the
//   frame's waves and splashes, so they are not independent): the cluster-robust covariance
//   V = G/(G-1) (n-1)/(n-3) (X'X)^-1 [sum_g X_g' e_g e_g' X_g] (X'X)^-1 (Liang & Zeger 1986, the
//   "CR1" small-sample factor), dof = G - 1 with G frames. Treating the thousands of points of a
//   video as independent would give a band far narrower than the frame-to-frame scatter of the
//   surface justifies.
// The band above is POINTWISE (the paper's "95 % confidence interval"): at each x it holds the
// true curve with 95 % probability, but over a whole span the truth leaves it somewhere more
// often than 5 % of the time. For a statement about the whole curve the fit also gives the
// SIMULTANEOUS band (Working-Hotelling / Scheffe): t is replaced by sqrt(3 F_{3, dof}(0.95)),
// which holds all x at once with 95 % probability (about 1.46 x wider at dof = 23).
// Units are the caller's (millsim uses mm). x is centred and scaled internally for conditioning.
#include <array>
#include <vector>

namespace millsim::vision {

struct QuadraticFit {
  std::array<double, 3> coef{};        // c0, c1, c2
  std::array<double, 9> covariance{};  // of (c0, c1, c2), row-major
  int points = 0;                      // n
  int groups = 0;                      // G (frames); 0 when the points are independent
  double dof = 0.0;                    // degrees of freedom of the t quantile
  double confidence = 0.95;            // of the band
  double t_quantile = 0.0;             // t_{(1+confidence)/2, dof}
  double scheffe_factor = 0.0;         // sqrt(3 F_{3, dof}(confidence))
  double residual_sd = 0.0;            // sqrt(SSR / (n - 3))

  double value(double x) const { return coef[0] + x * (coef[1] + x * coef[2]); }
  // Half-width of the confidence band of the fitted curve at x.
  double halfWidth(double x) const;
  // Half-width of the simultaneous band at x.
  double simultaneousHalfWidth(double x) const;
  // Standard error of the fitted curve at x.
  double standardError(double x) const;
};

// Fits y = c0 + c1 x + c2 x^2. `group` (optional, same length as x) labels the frame of each
// point; with at least 4 distinct labels the cluster-robust covariance is used, otherwise the
// independent-points formula. Throws std::invalid_argument for mismatched sizes, fewer than 4
// points, fewer than 3 distinct x, or a confidence outside (0, 1).
QuadraticFit fitQuadratic(const std::vector<double>& x, const std::vector<double>& y,
                          const std::vector<int>& group = {}, double confidence = 0.95);

// Quantile of Student's t distribution: P(T <= t) = p for `dof` > 0 degrees of freedom
// (non-integer allowed). Inverts the CDF, written with the regularised incomplete beta
// function, by bisection to ~1e-12. Throws std::invalid_argument for p outside (0, 1) or dof <= 0.
double studentTQuantile(double p, double dof);

// CDF of Student's t distribution (used by studentTQuantile, exposed for tests).
double studentTCdf(double t, double dof);

// Quantile of the F distribution with (d1, d2) degrees of freedom, same method.
double fisherFQuantile(double p, double d1, double d2);

}  // namespace millsim::vision
