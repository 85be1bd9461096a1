// Statistics of the vision pipeline: Student's t quantiles against tabulated values, the
// quadratic fit against hand-computed normal equations, and the confidence band's coverage
// (independent points: the textbook band; points in correlated groups: the cluster-robust band
// keeps its nominal coverage where the independent-points band would not).
#include <gtest/gtest.h>

#include <cmath>
#include <random>
#include <stdexcept>
#include <vector>

#include "millsim/vision/quadratic_fit.hpp"

namespace mv = millsim::vision;

// Tabulated two-sided 95 % (p = 0.975) and 99 % (p = 0.995) quantiles, 4 decimals as printed in
// statistics tables, so 5e-4.
TEST(VisionStats, StudentTQuantileMatchesTables) {
  EXPECT_NEAR(mv::studentTQuantile(0.975, 1), 12.7062, 5e-4);
  EXPECT_NEAR(mv::studentTQuantile(0.975, 2), 4.3027, 5e-4);
  EXPECT_NEAR(mv::studentTQuantile(0.975, 5), 2.5706, 5e-4);
  EXPECT_NEAR(mv::studentTQuantile(0.975, 10), 2.2281, 5e-4);
  EXPECT_NEAR(mv::studentTQuantile(0.975, 23), 2.0687, 5e-4);
  EXPECT_NEAR(mv::studentTQuantile(0.975, 30), 2.0423, 5e-4);
  EXPECT_NEAR(mv::studentTQuantile(0.995, 10), 3.1693, 5e-4);
  EXPECT_NEAR(mv::studentTQuantile(0.975, 1e6), 1.95996, 5e-4);  // the normal quantile
  EXPECT_NEAR(mv::studentTQuantile(0.025, 10), -2.2281, 5e-4);
  EXPECT_DOUBLE_EQ(mv::studentTQuantile(0.5, 7), 0.0);
  // t with 1 dof is Cauchy: CDF = 1/2 + atan(t)/pi, exactly.
  for (double t : {-3.0, -0.5, 0.2, 1.0, 7.0}) EXPECT_NEAR(mv::studentTCdf(t, 1), 0.5 + std::atan(t) / M_PI, 1e-12);
  EXPECT_THROW(mv::studentTQuantile(1.0, 3), std::invalid_argument);
  EXPECT_THROW(mv::studentTQuantile(0.9, 0), std::invalid_argument);
}

TEST(VisionStats, QuadraticFitMatchesNormalEquations) {
  // Exact quadratic: coefficients to round-off, zero band.
  std::vector<double> x, y;
  for (int i = -5; i <= 7; ++i) {
    x.push_back(10.0 * i + 3.0);
    y.push_back(-30.0 - 0.16 * x.back() + 0.0009 * x.back() * x.back());
  }
  const mv::QuadraticFit exact = mv::fitQuadratic(x, y);
  EXPECT_NEAR(exact.coef[0], -30.0, 1e-9);
  EXPECT_NEAR(exact.coef[1], -0.16, 1e-11);
  EXPECT_NEAR(exact.coef[2], 0.0009, 1e-13);
  EXPECT_NEAR(exact.halfWidth(0.0), 0.0, 1e-9);

  // Five points by hand: x = -2..2, y = (1, 0, 2, 3, 7). X'X = [5 0 10; 0 10 0; 10 0 34],
  // X'y = (13, 15, 35) -> c1 = 15/10, and [5 10; 10 34] (c0, c2) = (13, 35), determinant 70 ->
  // c2 = (5*35 - 10*13)/70 = 9/14, c0 = (34*13 - 10*35)/70 = 92/70. Residual variance SSR / 2,
  // band at x = 0: t(0.975, 2) sqrt(V00).
  const std::vector<double> hx{-2, -1, 0, 1, 2}, hy{1, 0, 2, 3, 7};
  const mv::QuadraticFit f = mv::fitQuadratic(hx, hy);
  const double c2 = 9.0 / 14.0, c1 = 1.5, c0 = 92.0 / 70.0;
  EXPECT_NEAR(f.coef[0], c0, 1e-12);
  EXPECT_NEAR(f.coef[1], c1, 1e-12);
  EXPECT_NEAR(f.coef[2], c2, 1e-12);
  double ssr = 0;
  for (int i = 0; i < 5; ++i) ssr += std::pow(hy[i] - (c0 + c1 * hx[i] + c2 * hx[i] * hx[i]), 2);
  const double s2 = ssr / 2.0;
  // (X'X)^-1 [0][0] = 34 / (5*34 - 100) = 34 / 70.
  EXPECT_NEAR(f.covariance[0], s2 * 34.0 / 70.0, 1e-12);
  EXPECT_NEAR(f.halfWidth(0.0), mv::studentTQuantile(0.975, 2) * std::sqrt(s2 * 34.0 / 70.0), 1e-12);
  EXPECT_EQ(f.groups, 0);
  EXPECT_DOUBLE_EQ(f.dof, 2.0);

  EXPECT_THROW(mv::fitQuadratic({1, 2, 3}, {1, 2, 3}), std::invalid_argument);
  EXPECT_THROW(mv::fitQuadratic({1, 1, 2, 2}, {1, 2, 3, 4}), std::invalid_argument);
  EXPECT_THROW(mv::fitQuadratic({1, 2, 3, 4}, {1, 2, 3}), std::invalid_argument);
}

// Monte Carlo coverage at 5 x positions: 95 % nominal. With 1000 trials the binomial sd of a
// coverage estimate is 0.7 %, so [0.93, 0.97] is about 3 sd.
TEST(VisionStats, IndependentPointsBandCovers95Percent) {
  std::mt19937 rng(11);
  std::normal_distribution<double> noise(0.0, 2.0);
  const std::vector<double> probes{-120, -60, 0, 50, 110};
  std::vector<int> hits(probes.size(), 0);
  const int trials = 1000;
  for (int t = 0; t < trials; ++t) {
    std::vector<double> x, y;
    for (int i = 0; i < 30; ++i) {
      x.push_back(-130.0 + 260.0 * i / 29.0);
      y.push_back(-30.0 - 0.16 * x.back() + 0.0009 * x.back() * x.back() + noise(rng));
    }
    const mv::QuadraticFit f = mv::fitQuadratic(x, y);
    for (std::size_t k = 0; k < probes.size(); ++k) {
      const double truth = -30.0 - 0.16 * probes[k] + 0.0009 * probes[k] * probes[k];
      hits[k] += std::abs(f.value(probes[k]) - truth) <= f.halfWidth(probes[k]) ? 1 : 0;
    }
  }
  for (std::size_t k = 0; k < probes.size(); ++k) {
    SCOPED_TRACE("x = " + std::to_string(probes[k]));
    EXPECT_GE(hits[k], 930);
    EXPECT_LE(hits[k], 970);
  }
}

// Frames: each one's surface is the curve plus a random level (sd 1.5 mm) shared by all its 40
// points, plus 0.5 mm independent noise. The cluster-robust band (frames as groups) keeps
// ~95 % coverage; the same points treated as independent give a band too narrow by ~4x.
TEST(VisionStats, FrameGroupedBandKeepsCoverageWhereIndependentBandFails) {
  std::mt19937 rng(5);
  std::normal_distribution<double> n01(0.0, 1.0);
  const int trials = 600;
  int hit_grouped = 0, hit_independent = 0;
  for (int t = 0; t < trials; ++t) {
    std::vector<double> x, y;
    std::vector<int> g;
    for (int frame = 0; frame < 24; ++frame) {
      const double level = 1.5 * n01(rng);
      for (int i = 0; i < 40; ++i) {
        x.push_back(-130.0 + 260.0 * i / 39.0);
        y.push_back(-30.0 - 0.16 * x.back() + 0.0009 * x.back() * x.back() + level + 0.5 * n01(rng));
        g.push_back(frame);
      }
    }
    const mv::QuadraticFit grouped = mv::fitQuadratic(x, y, g);
    const mv::QuadraticFit independent = mv::fitQuadratic(x, y);
    EXPECT_EQ(grouped.groups, 24);
    EXPECT_DOUBLE_EQ(grouped.dof, 23.0);
    hit_grouped += std::abs(grouped.value(0.0) + 30.0) <= grouped.halfWidth(0.0) ? 1 : 0;
    hit_independent += std::abs(independent.value(0.0) + 30.0) <= independent.halfWidth(0.0) ? 1 : 0;
  }
  // Binomial sd at 600 trials: 0.9 %; the grouped band within 3 sd of 95 %, a little below
  // allowed for the sandwich estimator's known small-sample optimism with 24 groups.
  EXPECT_GE(hit_grouped, static_cast<int>(0.91 * trials));
  EXPECT_LE(hit_grouped, static_cast<int>(0.98 * trials));
  EXPECT_LT(hit_independent, static_cast<int>(0.60 * trials));
}

// Tabulated F(0.95) quantiles; the simultaneous band's factor sqrt(3 F(3, dof)).
TEST(VisionStats, FisherQuantileAndSimultaneousBand) {
  EXPECT_NEAR(mv::fisherFQuantile(0.95, 3, 23), 3.0280, 5e-4);
  EXPECT_NEAR(mv::fisherFQuantile(0.95, 3, 10), 3.7083, 5e-4);
  EXPECT_NEAR(mv::fisherFQuantile(0.95, 1, 10), std::pow(mv::studentTQuantile(0.975, 10), 2), 1e-9);
  const mv::QuadraticFit f = mv::fitQuadratic({-2, -1, 0, 1, 2, 3}, {1, 0, 2, 3, 7, 8});
  EXPECT_NEAR(f.scheffe_factor, std::sqrt(3.0 * mv::fisherFQuantile(0.95, 3, 3)), 1e-12);
  EXPECT_GT(f.simultaneousHalfWidth(0.5), f.halfWidth(0.5));
  EXPECT_NEAR(f.simultaneousHalfWidth(0.5) / f.halfWidth(0.5), f.scheffe_factor / f.t_quantile, 1e-12);
}
