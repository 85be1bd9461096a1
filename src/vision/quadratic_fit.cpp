// Quadratic fit and its confidence band (see the header for the formulas). Eigen does the
// linear algebra; the t quantile is computed here so the library needs no statistics package.
#include "millsim/vision/quadratic_fit.hpp"

#include <Eigen/Dense>
#include <algorithm>
#include <cmath>
#include <map>
#include <set>
#include <stdexcept>

namespace millsim::vision {
namespace {

// Continued fraction of the incomplete beta function I_x(a, b), evaluated with the modified
// Lentz method (terms d_{2m} and d_{2m+1} of the standard expansion, e.g. Abramowitz & Stegun
// 26.5.8). Converges quickly for x < (a + 1) / (a + b + 2); the caller uses the symmetry
// I_x(a, b) = 1 - I_{1-x}(b, a) otherwise.
double betaContinuedFraction(double a, double b, double x) {
  constexpr double kTiny = 1e-300;
  constexpr double kEps = 1e-15;
  double c = 1.0;
  double d = 1.0 - (a + b) * x / (a + 1.0);
  if (std::abs(d) < kTiny) d = kTiny;
  d = 1.0 / d;
  double f = d;
  for (int m = 1; m <= 500; ++m) {
    const double m2 = 2.0 * m;
    // Even term.
    double num = m * (b - m) * x / ((a + m2 - 1.0) * (a + m2));
    d = 1.0 + num * d;
    c = 1.0 + num / c;
    if (std::abs(d) < kTiny) d = kTiny;
    if (std::abs(c) < kTiny) c = kTiny;
    d = 1.0 / d;
    f *= c * d;
    // Odd term.
    num = -(a + m) * (a + b + m) * x / ((a + m2) * (a + m2 + 1.0));
    d = 1.0 + num * d;
    c = 1.0 + num / c;
    if (std::abs(d) < kTiny) d = kTiny;
    if (std::abs(c) < kTiny) c = kTiny;
    d = 1.0 / d;
    const double delta = c * d;
    f *= delta;
    if (std::abs(delta - 1.0) < kEps) break;
  }
  return f;
}

// Regularised incomplete beta I_x(a, b).
double incompleteBeta(double a, double b, double x) {
  if (x <= 0.0) return 0.0;
  if (x >= 1.0) return 1.0;
  const double log_front = std::lgamma(a + b) - std::lgamma(a) - std::lgamma(b) + a * std::log(x) + b * std::log1p(-x);
  if (x < (a + 1.0) / (a + b + 2.0)) return std::exp(log_front) * betaContinuedFraction(a, b, x) / a;
  return 1.0 - std::exp(log_front) * betaContinuedFraction(b, a, 1.0 - x) / b;
}

}  // namespace

double studentTCdf(double t, double dof) {
  if (!(dof > 0.0)) throw std::invalid_argument("studentTCdf: dof must be positive");
  // P(|T| > |t|) = I_{dof/(dof+t^2)}(dof/2, 1/2).
  const double tail = incompleteBeta(0.5 * dof, 0.5, dof / (dof + t * t));
  return t >= 0.0 ? 1.0 - 0.5 * tail : 0.5 * tail;
}

double studentTQuantile(double p, double dof) {
  if (!(p > 0.0 && p < 1.0)) throw std::invalid_argument("studentTQuantile: p must lie in (0, 1)");
  if (!(dof > 0.0)) throw std::invalid_argument("studentTQuantile: dof must be positive");
  if (p == 0.5) return 0.0;
  if (p < 0.5) return -studentTQuantile(1.0 - p, dof);
  // Bracket: the quantile grows without bound as dof -> 0; double the upper end until it holds.
  double lo = 0.0, hi = 2.0;
  while (studentTCdf(hi, dof) < p && hi < 1e12) hi *= 2.0;
  for (int i = 0; i < 200 && hi - lo > 1e-13 * std::max(1.0, hi); ++i) {
    const double mid = 0.5 * (lo + hi);
    (studentTCdf(mid, dof) < p ? lo : hi) = mid;
  }
  return 0.5 * (lo + hi);
}

double fisherFQuantile(double p, double d1, double d2) {
  if (!(p > 0.0 && p < 1.0)) throw std::invalid_argument("fisherFQuantile: p must lie in (0, 1)");
  if (!(d1 > 0.0) || !(d2 > 0.0)) throw std::invalid_argument("fisherFQuantile: dof must be positive");
  auto cdf = [&](double f) { return incompleteBeta(0.5 * d1, 0.5 * d2, d1 * f / (d1 * f + d2)); };
  double lo = 0.0, hi = 4.0;
  while (cdf(hi) < p && hi < 1e12) hi *= 2.0;
  for (int i = 0; i < 200 && hi - lo > 1e-13 * std::max(1.0, hi); ++i) {
    const double mid = 0.5 * (lo + hi);
    (cdf(mid) < p ? lo : hi) = mid;
  }
  return 0.5 * (lo + hi);
}

double QuadraticFit::standardError(double x) const {
  const double f[3] = {1.0, x, x * x};
  double v = 0.0;
  for (int i = 0; i < 3; ++i)
    for (int j = 0; j < 3; ++j) v += f[i] * covariance[3 * i + j] * f[j];
  return std::sqrt(std::max(0.0, v));
}

double QuadraticFit::halfWidth(double x) const { return t_quantile * standardError(x); }

double QuadraticFit::simultaneousHalfWidth(double x) const { return scheffe_factor * standardError(x); }

QuadraticFit fitQuadratic(const std::vector<double>& x, const std::vector<double>& y, const std::vector<int>& group,
                          double confidence) {
  if (x.size() != y.size()) throw std::invalid_argument("fitQuadratic: x and y differ in length");
  if (!group.empty() && group.size() != x.size())
    throw std::invalid_argument("fitQuadratic: group labels differ in length from the points");
  if (!(confidence > 0.0 && confidence < 1.0))
    throw std::invalid_argument("fitQuadratic: confidence must lie in (0, 1)");
  const int n = static_cast<int>(x.size());
  if (n < 4) throw std::invalid_argument("fitQuadratic: need at least 4 points (3 coefficients and a residual)");
  if (std::set<double>(x.begin(), x.end()).size() < 3)
    throw std::invalid_argument("fitQuadratic: need at least 3 distinct x values");

  // u = (x - m) / s keeps the columns of X of similar size; transformed back at the end.
  double m = 0.0;
  for (double v : x) m += v;
  m /= n;
  double s = 0.0;
  for (double v : x) s = std::max(s, std::abs(v - m));
  if (!(s > 0.0)) s = 1.0;
  Eigen::MatrixXd X(n, 3);
  Eigen::VectorXd Y(n);
  for (int i = 0; i < n; ++i) {
    const double u = (x[i] - m) / s;
    X(i, 0) = 1.0;
    X(i, 1) = u;
    X(i, 2) = u * u;
    Y(i) = y[i];
  }
  const Eigen::Matrix3d xtx = X.transpose() * X;
  const Eigen::Matrix3d xtx_inv = xtx.ldlt().solve(Eigen::Matrix3d::Identity());
  const Eigen::Vector3d b = X.colPivHouseholderQr().solve(Y);
  const Eigen::VectorXd e = Y - X * b;
  const double ssr = e.squaredNorm();

  QuadraticFit fit;
  fit.points = n;
  fit.confidence = confidence;
  fit.residual_sd = std::sqrt(ssr / (n - 3));

  std::map<int, std::vector<int>> members;
  for (int i = 0; i < static_cast<int>(group.size()); ++i) members[group[i]].push_back(i);
  Eigen::Matrix3d cov_u;
  if (members.size() >= 4) {
    Eigen::Matrix3d meat = Eigen::Matrix3d::Zero();
    for (const auto& [label, idx] : members) {
      Eigen::Vector3d score = Eigen::Vector3d::Zero();
      for (int i : idx) score += X.row(i).transpose() * e(i);
      meat += score * score.transpose();
    }
    const double g = static_cast<double>(members.size());
    const double factor = g / (g - 1.0) * (n - 1.0) / (n - 3.0);
    cov_u = factor * xtx_inv * meat * xtx_inv;
    fit.groups = static_cast<int>(members.size());
    fit.dof = g - 1.0;
  } else {
    cov_u = (ssr / (n - 3)) * xtx_inv;
    fit.dof = n - 3.0;
  }
  fit.t_quantile = studentTQuantile(0.5 * (1.0 + confidence), fit.dof);
  fit.scheffe_factor = std::sqrt(3.0 * fisherFQuantile(confidence, 3.0, fit.dof));

  // Back to x: (1, u, u^2) = T (1, x, x^2) with u = (x - m)/s, so c = T' b and V_c = T' V_b T.
  Eigen::Matrix3d T;
  T << 1.0, 0.0, 0.0,        //
      -m / s, 1.0 / s, 0.0,  //
      m * m / (s * s), -2.0 * m / (s * s), 1.0 / (s * s);
  const Eigen::Vector3d c = T.transpose() * b;
  const Eigen::Matrix3d cov = T.transpose() * cov_u * T;
  for (int i = 0; i < 3; ++i) {
    fit.coef[i] = c(i);
    for (int j = 0; j < 3; ++j) fit.covariance[3 * i + j] = cov(i, j);
  }
  return fit;
}

}  // namespace millsim::vision
