#pragma once
// Thin-plate-spline interpolation of scattered 2-D data (Duchon 1977; e.g. Wendland,
// "Scattered Data Approximation", 2005, ch. 8 and 10):
//   s(x) = sum_i w_i phi(|x - x_i|) + c0 + c1 x + c2 y,   phi(r) = r^2 log r,
// with sum_i w_i = sum_i w_i x_i = sum_i w_i y_i = 0, so that
//   [Phi  P] [w]   [f]
//   [P^T  0] [c] = [0],   Phi_ij = phi(|x_i - x_j|), P_i = (1, x_i, y_i).
// It is the paper method's "interpolated SSE space": defined for any scattered set of >= 3
// points that are not all on one line, exact at the data (s(x_i) = f_i, as the paper
// interpolates its measured SSEs), the smoothest such surface (least bending energy), free of
// a shape parameter to tune (unlike multiquadric or Gaussian RBFs), and defined over the whole
// box (natural-neighbour interpolation stops at the convex hull of the points, which the six
// initial candidates do not cover). The linear tail makes the system solvable and reproduces
// planes exactly. Solved with a pivoted QR (Eigen), robust when two points nearly coincide.
// `smoothing` > 0 (default 0: exact) adds lambda to the diagonal of Phi: a smoothing spline.
#include <vector>

#include "millsim/calib/param_box.hpp"

namespace millsim::calib {

class ThinPlateSpline {
 public:
  // Throws std::invalid_argument for fewer than 3 points, sizes that differ, or points all on
  // one line (the linear tail is then not determined).
  ThinPlateSpline(const std::vector<Point2>& points, const std::vector<double>& values, double smoothing = 0.0);

  double operator()(const Point2& x) const;

  const std::vector<Point2>& points() const { return m_points; }

 private:
  std::vector<Point2> m_points;
  std::vector<double> m_w;
  double m_c[3] = {0, 0, 0};
};

// phi(r) = r^2 log r, with its limit 0 at r = 0.
double thinPlateKernel(double r);

}  // namespace millsim::calib
