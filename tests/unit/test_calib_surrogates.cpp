// Calibration building blocks against hand values: the thin-plate spline interpolates its data
// and reproduces planes, the GP posterior on one and two points, expected improvement, the
// Latin hypercube, the surface search and its exclusion disc.
#include <gtest/gtest.h>

#include <cmath>
#include <random>

#include "millsim/calib/gaussian_process.hpp"
#include "millsim/calib/initial_design.hpp"
#include "millsim/calib/surface_search.hpp"
#include "millsim/calib/thin_plate_spline.hpp"

namespace calib = millsim::calib;
using calib::Point2;

namespace {

std::vector<Point2> randomPoints(int n, unsigned seed) {
  std::mt19937 rng(seed);
  std::uniform_real_distribution<double> u(0, 1);
  std::vector<Point2> p(n);
  for (auto& x : p) x = {u(rng), u(rng)};
  return p;
}

}  // namespace

TEST(ThinPlateSpline, InterpolatesItsDataExactly) {
  const auto pts = randomPoints(15, 3);
  std::vector<double> f;
  for (const auto& p : pts) f.push_back(std::sin(5 * p[0]) + p[1] * p[1] * 3);
  const calib::ThinPlateSpline s(pts, f);
  for (std::size_t i = 0; i < pts.size(); ++i) EXPECT_NEAR(s(pts[i]), f[i], 1e-10) << i;
}

TEST(ThinPlateSpline, ReproducesAPlaneEverywhere) {
  // The linear tail: data on a plane give w = 0 and the plane itself.
  const auto pts = randomPoints(8, 5);
  std::vector<double> f;
  for (const auto& p : pts) f.push_back(1 + 2 * p[0] - 3 * p[1]);
  const calib::ThinPlateSpline s(pts, f);
  for (const auto& x : randomPoints(20, 6)) EXPECT_NEAR(s(x), 1 + 2 * x[0] - 3 * x[1], 1e-10);
}

TEST(ThinPlateSpline, KernelAndBadInput) {
  EXPECT_EQ(calib::thinPlateKernel(0.0), 0.0);
  EXPECT_NEAR(calib::thinPlateKernel(2.0), 4 * std::log(2.0), 1e-15);
  EXPECT_THROW(calib::ThinPlateSpline({{0, 0}, {1, 1}}, {1, 2}), std::invalid_argument);
  EXPECT_THROW(calib::ThinPlateSpline({{0, 0}, {0.5, 0.5}, {1, 1}}, {1, 2, 3}), std::invalid_argument);  // a line
  EXPECT_THROW(calib::ThinPlateSpline({{0, 0}, {1, 0}, {0, 1}}, {1, 2}), std::invalid_argument);
}

TEST(GaussianProcess, OnePointAgainstHandValues) {
  // k(r) = (1 + sqrt5 r + 5/3 r^2) exp(-sqrt5 r), r = 0.1 / 0.3 = 1/3:
  //   k = (1 + 0.745356 + 0.185185) exp(-0.745356) = 0.916167907529589
  // mean = m + k (y - m) / (1 + g) = 1 + 0.916168 / 1.1 = 1.83287991593599
  // var  = s2 (1 - k^2 / (1 + g)) = 4 (1 - 0.839364 / 1.1) = 0.947768600774017
  const double r = 1.0 / 3.0, s5 = std::sqrt(5.0);
  const double k = (1 + s5 * r + 5.0 / 3.0 * r * r) * std::exp(-s5 * r);
  EXPECT_NEAR(k, 0.916167907529589, 1e-14);
  calib::GpHyper h;
  h.length_e = h.length_mu = 0.3;
  h.nugget = 0.1;
  h.signal_var = 4;
  h.mean = 1;
  const calib::GaussianProcess gp({{0.5, 0.5}}, {2.0}, h);
  EXPECT_NEAR(calib::matern52({0.6, 0.5}, {0.5, 0.5}, 0.3, 0.3), k, 1e-14);
  EXPECT_NEAR(gp.mean({0.6, 0.5}), 1.83287991593599, 1e-12);
  EXPECT_NEAR(gp.variance({0.6, 0.5}), 0.947768600774017, 1e-12);
  // Far away: the prior.
  EXPECT_NEAR(gp.mean({50, 50}), 1.0, 1e-12);
  EXPECT_NEAR(gp.variance({50, 50}), 4.0, 1e-12);
}

TEST(GaussianProcess, TwoPointsAgainstHandValues) {
  // Points (0.2, 0.3), (0.7, 0.6), y = 1.5, -0.5; m = 0.25, s2 = 2, g = 0.05, l = (0.4, 0.25).
  // Correlation between them: r = hypot(0.5/0.4, 0.3/0.25) = 1.7328, k12 = 0.2051098870196482;
  // at x = (0.45, 0.4): k = (0.6806273567972777, 0.5152706046836445). With the 2 x 2 inverse
  // [a -b; -b a] / (a^2 - b^2), a = 1.05, b = k12:
  //   mean = m + k^T A^-1 (y - m) = 0.6839197438228292,  var = s2 (1 - k^T A^-1 k) = 0.8281579242176605
  calib::GpHyper h{0.4, 0.25, 0.05, 2.0, 0.25};
  const calib::GaussianProcess gp({{0.2, 0.3}, {0.7, 0.6}}, {1.5, -0.5}, h);
  EXPECT_NEAR(calib::matern52({0.2, 0.3}, {0.7, 0.6}, 0.4, 0.25), 0.2051098870196482, 1e-14);
  EXPECT_NEAR(gp.mean({0.45, 0.4}), 0.6839197438228292, 1e-12);
  EXPECT_NEAR(gp.variance({0.45, 0.4}), 0.8281579242176605, 1e-12);
}

TEST(GaussianProcess, WithoutNuggetItInterpolatesAndIsCertainAtTheData) {
  const auto pts = randomPoints(6, 9);
  std::vector<double> f;
  for (const auto& p : pts) f.push_back(p[0] - 2 * p[1] * p[1]);
  calib::GpHyper h{0.5, 0.5, 0.0, 1.0, 0.0};
  const calib::GaussianProcess gp(pts, f, h);
  for (std::size_t i = 0; i < pts.size(); ++i) {
    EXPECT_NEAR(gp.mean(pts[i]), f[i], 1e-8);
    EXPECT_NEAR(gp.variance(pts[i]), 0.0, 1e-8);
  }
}

TEST(GaussianProcess, FitFindsTheNoiseOfNoisyData) {
  // Smooth function plus N(0, 0.2^2): the fitted noise variance (nugget * signal variance)
  // must be within a factor 4 of 0.04 (30 points estimate a variance to about +-25%, and the
  // nugget grid has steps of ~3x).
  std::mt19937 rng(4);
  std::normal_distribution<double> noise(0, 0.2);
  const auto pts = randomPoints(30, 11);
  std::vector<double> f;
  for (const auto& p : pts) f.push_back(3 * (p[0] - 0.4) * (p[0] - 0.4) + 2 * (p[1] - 0.6) * (p[1] - 0.6) + noise(rng));
  const auto gp = calib::GaussianProcess::fit(pts, f);
  const double noise_var = gp.hyper().nugget * gp.hyper().signal_var;
  EXPECT_GT(noise_var, 0.2 * 0.2 / 4);
  EXPECT_LT(noise_var, 0.2 * 0.2 * 4);
}

TEST(ExpectedImprovement, HandValues) {
  EXPECT_NEAR(calib::expectedImprovement(1.0, 0.0, 2.0), 1.0, 1e-15);
  EXPECT_NEAR(calib::expectedImprovement(3.0, 0.0, 2.0), 0.0, 1e-15);
  EXPECT_NEAR(calib::expectedImprovement(0.0, 1.0, 0.0), 1.0 / std::sqrt(2 * std::acos(-1.0)), 1e-12);
  // z = 1: (best - m) Phi(1) + sd phi(1) = 0.8413447460685429 + 0.24197072451914337
  EXPECT_NEAR(calib::expectedImprovement(0.0, 1.0, 1.0), 1.0833154705876864, 1e-12);
}

TEST(InitialDesign, LatinHypercubeIsSpaceFillingAndDeterministic) {
  const auto a = calib::maximinLatinHypercube(6, 1), b = calib::maximinLatinHypercube(6, 1);
  ASSERT_EQ(a.size(), 6u);
  std::vector<int> rows(6, 0), cols(6, 0);
  double dmin = 1e9;
  for (std::size_t i = 0; i < a.size(); ++i) {
    EXPECT_EQ(a[i], b[i]);
    ++rows[static_cast<int>(a[i][0] * 6)];
    ++cols[static_cast<int>(a[i][1] * 6)];
    for (std::size_t j = 0; j < i; ++j) dmin = std::min(dmin, std::hypot(a[i][0] - a[j][0], a[i][1] - a[j][1]));
  }
  for (int k = 0; k < 6; ++k) {
    EXPECT_EQ(rows[k], 1);
    EXPECT_EQ(cols[k], 1);
  }
  // The best 6-point Latin design on a 6 x 6 grid has a smallest distance of sqrt(5)/6 = 0.373.
  EXPECT_GE(dmin, std::sqrt(5.0) / 6 - 1e-12);
}

TEST(SurfaceSearch, FindsAMinimumBetweenGridPointsAndRespectsExclusion) {
  const auto f = [](const Point2& x) {
    return (x[0] - 0.3337) * (x[0] - 0.3337) + 2 * (x[1] - 0.7123) * (x[1] - 0.7123);
  };
  const auto r = calib::minimiseSurface(f, {});
  ASSERT_TRUE(r.found);
  EXPECT_NEAR(r.x[0], 0.3337, 2e-4);
  EXPECT_NEAR(r.x[1], 0.7123, 2e-4);
  // The minimum itself already evaluated: the proposal keeps the exclusion distance.
  calib::SearchOptions o;
  o.exclusion = 0.05;
  const auto q = calib::minimiseSurface(f, {{0.3337, 0.7123}}, o);
  ASSERT_TRUE(q.found);
  EXPECT_GE(std::hypot(q.x[0] - 0.3337, q.x[1] - 0.7123), 0.05);
  EXPECT_LT(std::hypot(q.x[0] - 0.3337, q.x[1] - 0.7123), 0.06);
}
