// Thin-plate spline: assemble the saddle-point system and solve it once (see the header).
#include "millsim/calib/thin_plate_spline.hpp"

#include <Eigen/Dense>
#include <cmath>
#include <stdexcept>

namespace millsim::calib {

double thinPlateKernel(double r) { return r > 0 ? r * r * std::log(r) : 0.0; }

namespace {

double distance(const Point2& a, const Point2& b) { return std::hypot(a[0] - b[0], a[1] - b[1]); }

}  // namespace

ThinPlateSpline::ThinPlateSpline(const std::vector<Point2>& points, const std::vector<double>& values, double smoothing)
    : m_points(points) {
  const int n = static_cast<int>(points.size());
  if (n != static_cast<int>(values.size()))
    throw std::invalid_argument("ThinPlateSpline: points and values differ in size");
  if (n < 3) throw std::invalid_argument("ThinPlateSpline: needs at least 3 points");
  Eigen::MatrixXd P(n, 3);
  for (int i = 0; i < n; ++i) P.row(i) << 1.0, points[i][0], points[i][1];
  // The linear tail is determined only when the points span the plane.
  Eigen::ColPivHouseholderQR<Eigen::MatrixXd> tail(P);
  tail.setThreshold(1e-10);
  if (tail.rank() < 3) throw std::invalid_argument("ThinPlateSpline: the points lie on one line");

  Eigen::MatrixXd A = Eigen::MatrixXd::Zero(n + 3, n + 3);
  for (int i = 0; i < n; ++i) {
    for (int j = 0; j < n; ++j) A(i, j) = thinPlateKernel(distance(points[i], points[j]));
    A(i, i) += smoothing;
  }
  A.block(0, n, n, 3) = P;
  A.block(n, 0, 3, n) = P.transpose();
  Eigen::VectorXd rhs = Eigen::VectorXd::Zero(n + 3);
  for (int i = 0; i < n; ++i) rhs(i) = values[i];
  const Eigen::VectorXd sol = A.colPivHouseholderQr().solve(rhs);
  m_w.assign(sol.data(), sol.data() + n);
  for (int k = 0; k < 3; ++k) m_c[k] = sol(n + k);
}

double ThinPlateSpline::operator()(const Point2& x) const {
  double s = m_c[0] + m_c[1] * x[0] + m_c[2] * x[1];
  for (std::size_t i = 0; i < m_points.size(); ++i) s += m_w[i] * thinPlateKernel(distance(x, m_points[i]));
  return s;
}

}  // namespace millsim::calib
