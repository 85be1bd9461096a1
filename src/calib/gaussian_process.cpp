// Gaussian-process regression with a Matern 5/2 kernel and expected improvement (see header).
#include "millsim/calib/gaussian_process.hpp"

#include <Eigen/Dense>
#include <algorithm>
#include <cmath>
#include <limits>
#include <stdexcept>

namespace millsim::calib {

namespace {

constexpr double kSqrt5 = 2.23606797749978969641;
constexpr double kLog2Pi = 1.83787706640934548356;

using RowMatrix = Eigen::Matrix<double, Eigen::Dynamic, Eigen::Dynamic, Eigen::RowMajor>;

Eigen::MatrixXd correlation(const std::vector<Point2>& p, double le, double lm, double nugget) {
  const int n = static_cast<int>(p.size());
  Eigen::MatrixXd A(n, n);
  for (int i = 0; i < n; ++i)
    for (int j = 0; j <= i; ++j) A(i, j) = A(j, i) = matern52(p[i], p[j], le, lm);
  A.diagonal().array() += nugget;
  return A;
}

Eigen::VectorXd toVector(const std::vector<double>& v) {
  return Eigen::Map<const Eigen::VectorXd>(v.data(), static_cast<Eigen::Index>(v.size()));
}

// Closed-form GLS mean and ML signal variance for a factorised correlation matrix, and the
// resulting (profile) log likelihood.
struct Profile {
  double mean = 0, signal_var = 0, log_likelihood = -std::numeric_limits<double>::infinity();
};

Profile profile(const Eigen::LLT<Eigen::MatrixXd>& llt, const Eigen::VectorXd& y) {
  const Eigen::Index n = y.size();
  const Eigen::VectorXd ones = Eigen::VectorXd::Ones(n);
  const Eigen::VectorXd ai1 = llt.solve(ones), aiy = llt.solve(y);
  Profile p;
  p.mean = ones.dot(aiy) / ones.dot(ai1);
  const Eigen::VectorXd r = y - p.mean * ones;
  p.signal_var = std::max(r.dot(llt.solve(r)) / static_cast<double>(n), 1e-300);
  const Eigen::MatrixXd L = llt.matrixL();
  const double log_det = 2 * L.diagonal().array().log().sum();
  p.log_likelihood = -0.5 * static_cast<double>(n) * (std::log(p.signal_var) + 1 + kLog2Pi) - 0.5 * log_det;
  return p;
}

}  // namespace

double matern52(const Point2& a, const Point2& b, double length_e, double length_mu) {
  const double de = (a[0] - b[0]) / length_e, dm = (a[1] - b[1]) / length_mu;
  const double r = std::sqrt(de * de + dm * dm);
  return (1 + kSqrt5 * r + 5.0 / 3.0 * r * r) * std::exp(-kSqrt5 * r);
}

double expectedImprovement(double mean, double sd, double best) {
  if (!(sd > 0)) return std::max(0.0, best - mean);
  const double z = (best - mean) / sd;
  const double pdf = std::exp(-0.5 * z * z) / std::sqrt(2 * std::acos(-1.0));
  const double cdf = 0.5 * std::erfc(-z / std::sqrt(2.0));
  return (best - mean) * cdf + sd * pdf;
}

GaussianProcess::GaussianProcess(const std::vector<Point2>& points, const std::vector<double>& values,
                                 const GpHyper& hyper)
    : m_points(points), m_hyper(hyper) {
  const int n = static_cast<int>(points.size());
  if (n < 1 || n != static_cast<int>(values.size()))
    throw std::invalid_argument("GaussianProcess: needs at least one point and one value per point");
  if (!(hyper.length_e > 0 && hyper.length_mu > 0 && hyper.nugget >= 0 && hyper.signal_var > 0))
    throw std::invalid_argument("GaussianProcess: length scales and signal variance must be > 0, nugget >= 0");
  Eigen::LLT<Eigen::MatrixXd> llt(correlation(points, hyper.length_e, hyper.length_mu, hyper.nugget));
  if (llt.info() != Eigen::Success)
    throw std::invalid_argument("GaussianProcess: correlation matrix not positive definite (coincident points?)");
  const Eigen::VectorXd r = toVector(values).array() - hyper.mean;
  const Eigen::VectorXd alpha = llt.solve(r);
  m_alpha.assign(alpha.data(), alpha.data() + n);
  RowMatrix L = llt.matrixL();
  m_chol.assign(L.data(), L.data() + static_cast<std::size_t>(n) * n);
  const double log_det = 2 * L.diagonal().array().log().sum() + n * std::log(hyper.signal_var);
  m_log_likelihood = -0.5 * r.dot(alpha) / hyper.signal_var - 0.5 * log_det - 0.5 * n * kLog2Pi;
}

GaussianProcess GaussianProcess::fit(const std::vector<Point2>& points, const std::vector<double>& values,
                                     double min_nugget) {
  if (points.empty() || points.size() != values.size())
    throw std::invalid_argument("GaussianProcess::fit: needs at least one point and one value per point");
  static const double kLengths[] = {0.05, 0.08, 0.12, 0.18, 0.27, 0.4, 0.6, 0.9, 1.35, 2.0};
  static const double kNuggets[] = {1e-6, 1e-5, 1e-4, 1e-3, 1e-2, 0.03, 0.1, 0.3, 0.5};
  const Eigen::VectorXd y = toVector(values);
  GpHyper best;
  double best_ll = -std::numeric_limits<double>::infinity();
  for (double g : kNuggets) {
    if (g < min_nugget) continue;
    for (double le : kLengths)
      for (double lm : kLengths) {
        Eigen::LLT<Eigen::MatrixXd> llt(correlation(points, le, lm, g));
        if (llt.info() != Eigen::Success) continue;
        const Profile p = profile(llt, y);
        if (p.log_likelihood > best_ll) {
          best_ll = p.log_likelihood;
          best = GpHyper{le, lm, g, p.signal_var, p.mean};
        }
      }
  }
  if (!std::isfinite(best_ll)) {
    // Only when every grid correlation matrix failed: fall back to the largest nugget.
    best = GpHyper{0.3, 0.3, std::max(0.5, min_nugget), 1, 0};
  }
  return GaussianProcess(points, values, best);
}

double GaussianProcess::mean(const Point2& x) const {
  double s = m_hyper.mean;
  for (std::size_t i = 0; i < m_points.size(); ++i)
    s += matern52(x, m_points[i], m_hyper.length_e, m_hyper.length_mu) * m_alpha[i];
  return s;
}

double GaussianProcess::variance(const Point2& x) const {
  // var = s2 (1 - |L^-1 k|^2), forward substitution on the stored factor.
  const std::size_t n = m_points.size();
  std::vector<double> v(n);
  double q = 0;
  for (std::size_t i = 0; i < n; ++i) {
    double s = matern52(x, m_points[i], m_hyper.length_e, m_hyper.length_mu);
    for (std::size_t j = 0; j < i; ++j) s -= m_chol[i * n + j] * v[j];
    v[i] = s / m_chol[i * n + i];
    q += v[i] * v[i];
  }
  return std::max(0.0, m_hyper.signal_var * (1 - q));
}

}  // namespace millsim::calib
