// Angle-of-repose pipeline (Doroszek et al. 2024, section 3.7.1): synthetic charges with a known
// surface angle, the heat-map threshold against balls thrown into the air, the error paths, the
// disc renderer used for simulated frames, PNG I/O and the regression's standard error.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <filesystem>
#include <random>
#include <stdexcept>
#include <string>
#include <vector>

#include "millsim/core/error.hpp"
#include "millsim/vision/angle_of_repose.hpp"
#include "millsim/vision/angle_overlay.hpp"
#include "millsim/vision/heatmap.hpp"
#include "millsim/vision/image.hpp"
#include "millsim/vision/png_io.hpp"
#include "millsim/vision/render_discs.hpp"

namespace mv = millsim::vision;

namespace {

constexpr double kPi = 3.14159265358979323846;
constexpr double kPpmm = 2.0;          // the pipeline's default scale
constexpr double kDrumRadiusMm = 146.0;
constexpr double kViewMm = 300.0;      // square view, drum centred
constexpr double kCentreMm = kViewMm / 2.0;

// Front view of a charge in the drum, in the pipeline's own coordinates (x = col / ppmm,
// y = (H - 1 - row) / ppmm, y up): everything in the drum below a straight surface through the
// drum centre that falls to the right at `angle_deg`, plus a round "shoulder" of radius 35 mm
// centred on the surface 75 mm left of the centre. The shoulder top is above the surface's
// left end for 35 and 42 deg, so the highest point is on the lifted (left) side as in the
// experiments, and the shoulder ends 40 mm left of the centre, outside the fit window.
mv::ImageU8 syntheticCharge(double angle_deg) {
  const int n = static_cast<int>(std::lround(kViewMm * kPpmm));
  const double k = std::tan(angle_deg * kPi / 180.0);
  const double bx = kCentreMm - 75.0;
  const double by = kCentreMm + 75.0 * k;
  mv::ImageU8 img(n, n, 0);
  for (int row = 0; row < n; ++row) {
    for (int col = 0; col < n; ++col) {
      const double x = col / kPpmm;
      const double y = (n - 1 - row) / kPpmm;
      const double dx = x - kCentreMm;
      const double dy = y - kCentreMm;
      if (dx * dx + dy * dy >= kDrumRadiusMm * kDrumRadiusMm) continue;
      const bool below_surface = y < kCentreMm - k * dx;
      const bool in_shoulder = (x - bx) * (x - bx) + (y - by) * (y - by) < 35.0 * 35.0;
      if (below_surface || in_shoulder) img.at(col, row) = 255;
    }
  }
  return img;
}

mv::ImageF toHeat(const mv::ImageU8& mask) {
  mv::HeatmapAccumulator acc;
  acc.add(mask);
  return acc.heatmap();
}

// Unique per process, so parallel test runs do not share files.
std::filesystem::path tempPath(const std::string& name) {
  static const unsigned tag = std::random_device{}();
  return std::filesystem::temp_directory_path() /
         ("millsim_test_vision_" + std::to_string(tag) + "_" + name);
}

}  // namespace

// (a) The paper's scale is 2 px/mm: an edge row is off by at most 0.25 mm, which over a fit of
// ~100 mm bounds the slope error by about 0.5 mm / 100 mm = 0.3 deg even if the errors lined up
// as a ramp; least squares over ~250 columns does better. Hence 0.5 deg.
TEST(VisionAngle, RecoversKnownAngleOfSyntheticCharge) {
  for (double angle : {35.0, 42.0}) {
    SCOPED_TRACE("angle " + std::to_string(angle));
    const mv::ImageU8 mask = syntheticCharge(angle);
    const mv::AngleResult r = mv::angleFromHeatmap(toHeat(mask), mv::AngleOptions{});
    EXPECT_NEAR(r.angle_deg, angle, 0.5);
    // The highest point is the shoulder top on the left, 75 mm left of the drum centre. The
    // top pixel row of a 35 mm circle at 2 px/mm is ~12 mm wide and its leftmost pixel is taken.
    EXPECT_NEAR(r.highest_x_mm, kCentreMm - 75.0, 8.0);
    EXPECT_GT(r.highest_y_mm, kCentreMm + kDrumRadiusMm * std::sin(angle * kPi / 180.0));
    // Fit starts 60 mm right of it and runs to where the surface meets the drum wall.
    ASSERT_FALSE(r.fit_x_mm.empty());
    EXPECT_GE(r.fit_x_mm.front(), r.highest_x_mm + 60.0 - 1e-9);
    EXPECT_GT(r.fit_x_mm.back() - r.fit_x_mm.front(), 100.0);
    EXPECT_EQ(r.points_used, static_cast<int>(r.fit_x_mm.size()));
    EXPECT_GT(r.stderr_deg, 0.0);
    EXPECT_LT(r.stderr_deg, 0.2);
    // The line passes through the drum centre.
    EXPECT_NEAR(r.slope * kCentreMm + r.intercept, kCentreMm, 1.0);
    EXPECT_EQ(r.processed.width, mask.width);
  }
}

TEST(VisionAngle, FitLengthLimitsTheWindow) {
  mv::AngleOptions opt;
  opt.fit_length_mm = 50.0;
  const mv::AngleResult r = mv::angleFromHeatmap(toHeat(syntheticCharge(38.0)), opt);
  EXPECT_NEAR(r.angle_deg, 38.0, 0.5);
  EXPECT_LE(r.fit_x_mm.back(), r.highest_x_mm + 60.0 + 50.0 + 1e-9);
  EXPECT_EQ(r.points_used, 101);  // 50 mm at 2 px/mm, both ends included
}

// (b) Section 3.8.2: a lifter throws balls into the air in some frames; the heat-map threshold
// keeps only the charge's most frequent position.
TEST(VisionAngle, HeatmapThresholdRemovesSpuriousLiftedBall) {
  const double angle = 40.0;
  const mv::ImageU8 base = syntheticCharge(angle);
  // A 10 mm ball 35 mm above the surface, 80 mm right of the drum centre (near the lower end
  // of the fit window, where it tilts the line most), drawn with the simulation renderer at the
  // same scale and view.
  const double bx_mm = kCentreMm + 80.0;
  const double by_mm = kCentreMm - std::tan(angle * kPi / 180.0) * 80.0 + 35.0;
  const mv::ImageU8 ball = mv::renderDiscs({bx_mm / 1000.0}, {by_mm / 1000.0}, {0.010}, 0.0, 0.0,
                                           kViewMm / 1000.0, kViewMm / 1000.0, kPpmm);
  ASSERT_EQ(ball.width, base.width);
  ASSERT_EQ(ball.height, base.height);
  std::vector<mv::ImageU8> masks;
  for (int f = 0; f < 100; ++f) {
    mv::ImageU8 m = base;
    if (f % 5 == 0) {  // 20 % of the frames
      for (std::size_t i = 0; i < m.pixels.size(); ++i) m.pixels[i] |= ball.pixels[i];
    }
    masks.push_back(std::move(m));
  }
  const mv::AngleResult clean = mv::angleFromHeatmap(toHeat(base), mv::AngleOptions{});
  const mv::AngleResult r = mv::angleFromMasks(masks, mv::AngleOptions{});
  EXPECT_NEAR(r.angle_deg, angle, 0.5);
  EXPECT_NEAR(r.angle_deg, clean.angle_deg, 0.5);

  // The test has teeth: with a threshold below 20 % the ball becomes part of the surface.
  mv::AngleOptions loose;
  loose.threshold = 0.1;
  const mv::AngleResult polluted = mv::angleFromMasks(masks, loose);
  EXPECT_GT(std::abs(polluted.angle_deg - angle), 1.0);
}

TEST(VisionAngle, HeatmapIsFractionOfFrames) {
  mv::HeatmapAccumulator acc;
  EXPECT_EQ(acc.heatmap().width, 0);
  mv::ImageU8 a(3, 2, 0);
  mv::ImageU8 b(3, 2, 0);
  a.at(0, 0) = 255;
  b.at(0, 0) = 1;  // any nonzero value is charge
  b.at(2, 1) = 255;
  acc.add(a);
  acc.add(b);
  acc.add(mv::ImageU8(3, 2, 0));
  acc.add(mv::ImageU8(3, 2, 0));
  EXPECT_EQ(acc.frames(), 4);
  const mv::ImageF h = acc.heatmap();
  EXPECT_FLOAT_EQ(h.at(0, 0), 0.5f);
  EXPECT_FLOAT_EQ(h.at(2, 1), 0.25f);
  EXPECT_FLOAT_EQ(h.at(1, 1), 0.0f);
  EXPECT_THROW(acc.add(mv::ImageU8(2, 3, 0)), std::invalid_argument);
}

// (c)
TEST(VisionAngle, TooFewPointsInWindowThrowsWithMessage) {
  const mv::ImageF heat = toHeat(syntheticCharge(35.0));
  mv::AngleOptions opt;
  opt.fit_offset_mm = 400.0;  // beyond the drum
  try {
    mv::angleFromHeatmap(heat, opt);
    FAIL() << "expected std::runtime_error";
  } catch (const std::runtime_error& e) {
    EXPECT_NE(std::string(e.what()).find(
                  "angle of repose: only 0 surface points in the fit window"),
              std::string::npos)
        << e.what();
  }
  opt = mv::AngleOptions{};
  opt.fit_length_mm = 1.0;  // 3 columns at 2 px/mm, fewer than min_points = 5
  try {
    mv::angleFromHeatmap(heat, opt);
    FAIL() << "expected std::runtime_error";
  } catch (const std::runtime_error& e) {
    EXPECT_NE(std::string(e.what()).find(
                  "angle of repose: only 3 surface points in the fit window"),
              std::string::npos)
        << e.what();
  }
  EXPECT_THROW(mv::angleFromHeatmap(mv::ImageF(50, 50, 0.0f), mv::AngleOptions{}),
               std::runtime_error);
  mv::AngleOptions bad;
  bad.pixels_per_mm = 0.0;
  EXPECT_THROW(mv::angleFromHeatmap(heat, bad), std::invalid_argument);
  EXPECT_THROW(mv::angleFromMasks({}, mv::AngleOptions{}), std::invalid_argument);
}

// (d)
TEST(VisionAngle, RenderedDiscAreaMatchesPiRSquared) {
  // Centre off the pixel grid so the test does not ride on a symmetric special case.
  const double r_m = 0.010;
  const mv::ImageU8 img =
      mv::renderDiscs({0.0313}, {0.0287}, {r_m}, 0.0, 0.0, 0.060, 0.060, kPpmm);
  ASSERT_EQ(img.width, 120);
  ASSERT_EQ(img.height, 120);
  int covered = 0;
  for (std::uint8_t p : img.pixels) covered += (p == 255) ? 1 : 0;
  const double area_mm2 = covered / (kPpmm * kPpmm);
  const double exact_mm2 = kPi * 10.0 * 10.0;
  EXPECT_NEAR(area_mm2, exact_mm2, 0.01 * exact_mm2);
  // y up: the disc centre (31.3 mm, 28.7 mm) lands on column 62, row 120 - 57.4 -> 62.
  EXPECT_EQ(img.at(62, 62), 255);
  EXPECT_EQ(img.at(0, 0), 0);
}

TEST(VisionAngle, RenderDiscsClipsToWindow) {
  // Partly outside, fully outside and absurdly far: no out-of-range writes, no overflow.
  const mv::ImageU8 img = mv::renderDiscs({0.0, 1.0, 1e300}, {0.0, 1.0, -1e300},
                                          {0.005, 0.005, 0.005}, 0.0, 0.0, 0.02, 0.01, kPpmm);
  ASSERT_EQ(img.width, 40);
  ASSERT_EQ(img.height, 20);
  int covered = 0;
  for (std::uint8_t p : img.pixels) covered += (p == 255) ? 1 : 0;
  // A quarter of a 5 mm disc at the lower left corner.
  EXPECT_NEAR(covered / (kPpmm * kPpmm), kPi * 25.0 / 4.0, 0.05 * kPi * 25.0 / 4.0);
  EXPECT_EQ(img.at(0, 19), 255);
  EXPECT_EQ(img.at(39, 0), 0);
  EXPECT_THROW(mv::renderDiscs({0.0}, {}, {0.1}, 0, 0, 1, 1, 2), std::invalid_argument);
}

// (e)
TEST(VisionAngle, PngRoundTripOfGrayImageIsExact) {
  mv::ImageU8 img(37, 23, 0);
  std::mt19937 rng(7);
  for (std::size_t i = 0; i < img.pixels.size(); ++i) {
    img.pixels[i] = static_cast<std::uint8_t>(i < 256 ? i : rng() & 0xFF);  // every value once
  }
  const std::string path = tempPath("gray.png").string();
  mv::writePng(path, img);
  const mv::ImageU8 back = mv::readPngGray(path);
  std::filesystem::remove(path);
  ASSERT_EQ(back.width, img.width);
  ASSERT_EQ(back.height, img.height);
  EXPECT_EQ(back.pixels, img.pixels);
}

TEST(VisionAngle, PngColourReadsAsGrayAndErrorsNameThePath) {
  mv::ImageRgb rgb(4, 2, mv::Rgb{0, 0, 0});
  rgb.at(0, 0) = {255, 255, 255};
  rgb.at(1, 0) = {255, 0, 0};
  rgb.at(2, 0) = {0, 255, 0};
  rgb.at(3, 1) = {128, 128, 128};
  const std::string path = tempPath("rgb.png").string();
  mv::writePng(path, rgb);
  const mv::ImageU8 g = mv::readPngGray(path);
  std::filesystem::remove(path);
  ASSERT_EQ(g.width, 4);
  ASSERT_EQ(g.height, 2);
  EXPECT_EQ(g.at(0, 0), 255);
  EXPECT_EQ(g.at(0, 1), 0);
  EXPECT_NEAR(g.at(3, 1), 128, 1);
  EXPECT_GT(g.at(2, 0), g.at(1, 0));  // green is brighter than red in luminance

  const std::string missing = tempPath("does_not_exist.png").string();
  try {
    mv::readPngGray(missing);
    FAIL() << "expected InputError";
  } catch (const millsim::core::InputError& e) {
    EXPECT_EQ(std::string(e.what()).rfind(missing, 0), 0u) << e.what();
  }
  const std::string bad_dir = (tempPath("no_such_dir") / "x.png").string();
  EXPECT_THROW(mv::writePng(bad_dir, mv::ImageU8(2, 2, 0)), millsim::core::InputError);
  EXPECT_THROW(mv::writePng(path, mv::ImageU8{}), millsim::core::InputError);
}

// (f)
TEST(VisionAngle, RegressionStandardErrorMatchesTextbook) {
  // Perfect line: no scatter, no error.
  const mv::LineFit exact = mv::fitLine({0, 1, 2, 3, 4, 5}, {3, 1, -1, -3, -5, -7});
  EXPECT_NEAR(exact.slope, -2.0, 1e-12);
  EXPECT_NEAR(exact.intercept, 3.0, 1e-12);
  EXPECT_NEAR(exact.slope_stderr, 0.0, 1e-12);

  // Hand-made points, evaluated with the raw-sum textbook formulas:
  // Sxx = sum x^2 - (sum x)^2 / n, b = Sxy / Sxx, SE(b) = sqrt(SSR / (n - 2) / Sxx).
  const std::vector<double> x{0, 1, 2, 3, 4};
  const std::vector<double> y{1.0, 2.9, 5.2, 6.8, 9.1};
  const double n = 5, sx = 10, sy = 25.0, sxx_raw = 30, sxy_raw = 0 + 2.9 + 10.4 + 20.4 + 36.4;
  const double sxx = sxx_raw - sx * sx / n;  // 10
  const double sxy = sxy_raw - sx * sy / n;  // 20.1
  const double b = sxy / sxx;
  const double a = (sy - b * sx) / n;
  double ssr = 0;
  for (int i = 0; i < 5; ++i) ssr += std::pow(y[i] - (a + b * x[i]), 2);
  const double se = std::sqrt(ssr / (n - 2) / sxx);
  const mv::LineFit f = mv::fitLine(x, y);
  EXPECT_NEAR(f.slope, 2.01, 1e-12);
  EXPECT_NEAR(f.slope, b, 1e-12);
  EXPECT_NEAR(f.intercept, a, 1e-12);
  EXPECT_NEAR(f.slope_stderr, se, 1e-12);
  EXPECT_GT(f.slope_stderr, 0.0);
  EXPECT_THROW(mv::fitLine({1, 2}, {1, 2}), std::invalid_argument);
  EXPECT_THROW(mv::fitLine({1, 1, 1}, {1, 2, 3}), std::invalid_argument);
}

TEST(VisionAngle, AngleStderrThroughThePipeline) {
  // A 45 deg staircase (one row down per column) is a perfect line: angle 45, stderr 0.
  const int n = 40;
  mv::ImageF stair(n, n, 0.0f);
  for (int c = 0; c < n; ++c) {
    for (int row = c; row < n; ++row) stair.at(c, row) = 1.0f;
  }
  mv::AngleOptions opt;
  opt.smoothing_px = 0;
  opt.fit_offset_mm = 0.0;
  const mv::AngleResult perfect = mv::angleFromHeatmap(stair, opt);
  EXPECT_NEAR(perfect.angle_deg, 45.0, 1e-9);
  EXPECT_NEAR(perfect.stderr_deg, 0.0, 1e-9);
  EXPECT_EQ(perfect.points_used, n);
  EXPECT_DOUBLE_EQ(perfect.highest_x_mm, 0.0);

  // Same staircase with the edge row jittered: positive error, equal to the slope's textbook
  // standard error propagated through atan, d(angle)/d(slope) = 1 / (1 + slope^2).
  mv::ImageF noisy(n, n, 0.0f);
  const int jitter[] = {0, 1, -1, 2, 0, -2, 1, 0, -1, 1};
  double sc = 0, st = 0, scc = 0, sct = 0;  // sums for the staircase's own least-squares slope
  for (int c = 0; c < n; ++c) {
    const int top = c == 0 ? 0 : std::clamp(c + 2 + jitter[c % 10], 1, n - 1);  // column 0 stays highest
    for (int row = top; row < n; ++row) noisy.at(c, row) = 1.0f;
    sc += c, st += top, scc += double(c) * c, sct += double(c) * top;
  }
  // The pipeline fits every column (offset 0), so its angle is the one of the edge rows drawn:
  // slope (rows down per column) = (n Sct - Sc St) / (n Scc - Sc^2), 44.84 deg here.
  const double drawn = std::atan((n * sct - sc * st) / (n * scc - sc * sc)) * 180.0 / kPi;
  const mv::AngleResult r = mv::angleFromHeatmap(noisy, opt);
  EXPECT_GT(r.stderr_deg, 0.0);
  const mv::LineFit f = mv::fitLine(r.fit_x_mm, r.fit_y_mm);
  EXPECT_NEAR(r.slope, f.slope, 1e-12);
  EXPECT_NEAR(r.stderr_deg, f.slope_stderr / (1 + f.slope * f.slope) * 180.0 / kPi, 1e-12);
  EXPECT_EQ(r.points_used, n);
  EXPECT_NEAR(r.angle_deg, drawn, 1e-9);
}

TEST(VisionAngle, OverlayHasImageSizeAndDrawsLineAndText) {
  const mv::ImageF heat = toHeat(syntheticCharge(41.7));
  const mv::AngleResult r = mv::angleFromHeatmap(heat, mv::AngleOptions{});
  const mv::ImageRgb img = mv::renderAngleOverlay(heat, r, kPpmm);
  ASSERT_EQ(img.width, heat.width);
  ASSERT_EQ(img.height, heat.height);
  // The fitted line is white at the middle of the fit window.
  const double xm = 0.5 * (r.fit_x_mm.front() + r.fit_x_mm.back());
  const int col = static_cast<int>(std::lround(xm * kPpmm));
  const double ym = r.slope * xm + r.intercept;
  const int row = static_cast<int>(std::lround(img.height - 1 - ym * kPpmm));
  EXPECT_EQ(img.at(col, row).r, 255);
  EXPECT_EQ(img.at(col, row).g, 255);
  EXPECT_EQ(img.at(col, row).b, 255);
  // Some white text pixels in the top-left label box.
  int white = 0;
  for (int y = 0; y < 40; ++y) {
    for (int x = 0; x < 160; ++x) white += (img.at(x, y).g == 255 && img.at(x, y).b == 255) ? 1 : 0;
  }
  EXPECT_GT(white, 100);
  const std::string path = tempPath("overlay.png").string();
  mv::writePng(path, img);
  EXPECT_TRUE(std::filesystem::exists(path));
  std::filesystem::remove(path);
}
