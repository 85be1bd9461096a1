// Slurry curve of a recording and its overlay (see video_slurry.hpp).
#include "millsim/vision/video_slurry.hpp"

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <opencv2/imgproc.hpp>

#include "millsim/vision/video_angle.hpp"
#include "vision/cv_convert.hpp"

namespace millsim::vision {
namespace {

constexpr int kShift = 4;
constexpr double kOne = 1 << kShift;

cv::Point toImage(const std::array<double, 6>& a, double x, double y) {
  return {static_cast<int>(std::lround((a[0] * x + a[1] * y + a[2]) * kOne)),
          static_cast<int>(std::lround((a[3] * x + a[4] * y + a[5]) * kOne))};
}

}  // namespace

std::array<double, 6> millToFrameAffine(const MillView& view) {
  double u0, v0, ux, vx, uy, vy;
  view.mmToFrame(0, 0, u0, v0);
  view.mmToFrame(1, 0, ux, vx);
  view.mmToFrame(0, 1, uy, vy);
  return {ux - u0, uy - u0, u0, vx - v0, vy - v0, v0};
}

std::array<double, 6> millToViewAffine(double R, double p) {
  return {p, 0.0, mmToViewCol(0.0, R, p), 0.0, -p, mmToViewRow(0.0, R, p)};
}

ImageRgb drawSlurryOverlay(const ImageRgb& background, const SlurryCurve& c, const std::array<double, 6>& A,
                           const std::vector<double>& circle_radii_mm) {
  cv::Mat img = detail::toBgr(background);
  const double scale = std::sqrt(std::abs(A[0] * A[4] - A[1] * A[3]));
  const int thick = std::max(1, static_cast<int>(std::lround(img.cols / 400.0)));
  for (double r : circle_radii_mm)
    cv::circle(img, toImage(A, 0, 0), static_cast<int>(std::lround(r * scale * kOne)), cv::Scalar(255, 255, 0), thick,
               cv::LINE_AA, kShift);
  const int dot = static_cast<int>(std::max(1.0, 0.8 * thick) * kOne);
  for (const SurfacePoint& p : c.rejected)
    cv::circle(img, toImage(A, p.x_mm, p.y_mm), dot, cv::Scalar(150, 150, 150), cv::FILLED, cv::LINE_8, kShift);
  for (const SurfacePoint& p : c.used)
    cv::circle(img, toImage(A, p.x_mm, p.y_mm), dot, cv::Scalar(0, 140, 255), cv::FILLED, cv::LINE_8, kShift);
  std::vector<cv::Point> mid, lo, hi, slo, shi;
  const int n = 200;
  for (int i = 0; i <= n; ++i) {
    const double x = c.x_min_mm + (c.x_max_mm - c.x_min_mm) * i / n;
    const double y = c.fit.value(x), hw = c.fit.halfWidth(x);
    mid.push_back(toImage(A, x, y));
    lo.push_back(toImage(A, x, y - hw));
    hi.push_back(toImage(A, x, y + hw));
    const double hs = c.fit.simultaneousHalfWidth(x);
    slo.push_back(toImage(A, x, y - hs));
    shi.push_back(toImage(A, x, y + hs));
  }
  cv::polylines(img, slo, false, cv::Scalar(200, 120, 40), 1, cv::LINE_AA, kShift);
  cv::polylines(img, shi, false, cv::Scalar(200, 120, 40), 1, cv::LINE_AA, kShift);
  cv::polylines(img, lo, false, cv::Scalar(255, 200, 120), thick, cv::LINE_AA, kShift);
  cv::polylines(img, hi, false, cv::Scalar(255, 200, 120), thick, cv::LINE_AA, kShift);
  cv::polylines(img, mid, false, cv::Scalar(255, 255, 255), thick + 1, cv::LINE_AA, kShift);

  char text[160];
  const auto& k = c.fit.coef;
  std::snprintf(text, sizeof text, "y = %.2f %+.4f x %+.6f x^2 (mm)", k[0], k[1], k[2]);
  char sub[160];
  std::snprintf(sub, sizeof sub, "%d pts, %s, %.0f%% band +/-%.2f mm", c.fit.points,
                c.fit.groups > 0 ? (std::to_string(c.fit.groups) + " frames").c_str() : "independent",
                100.0 * c.fit.confidence, c.fit.halfWidth(0.0));
  const double font = std::max(0.4, img.cols / 900.0);
  const int ft = std::max(1, static_cast<int>(std::lround(2 * font)));
  int y = static_cast<int>(std::lround(28 * font));
  for (const char* s : {static_cast<const char*>(text), static_cast<const char*>(sub)}) {
    int base = 0;
    const cv::Size sz = cv::getTextSize(s, cv::FONT_HERSHEY_SIMPLEX, font, ft, &base);
    cv::rectangle(img, cv::Point(4, y - sz.height - 6), cv::Point(12 + sz.width, y + base), cv::Scalar(0, 0, 0),
                  cv::FILLED);
    cv::putText(img, s, cv::Point(8, y), cv::FONT_HERSHEY_SIMPLEX, font, cv::Scalar(255, 255, 255), ft, cv::LINE_AA);
    y += sz.height + base + 10;
  }
  return detail::toImageRgb(img);
}

SlurryMeasurement measureVideoSlurry(const FrameSequence& seq, const VideoSlurryOptions& opt) {
  const MillView view = locateMill(seq, opt.detection, opt.view);
  const double ppmm = opt.view.pixels_per_mm;
  std::vector<SurfacePoint> pts;
  SlurryMeasurement out;
  out.circle = view.circle();
  for (std::size_t k = 0; k < seq.frames.size(); ++k) {
    const std::vector<SurfacePoint> p =
        slurrySurfacePoints(view.apply(seq.frames[k]), view.mask(), view.innerRadiusMm(), ppmm, opt.slurry,
                            seq.indices.empty() ? static_cast<int>(k) : seq.indices[k]);
    if (!p.empty()) ++out.frames;
    pts.insert(pts.end(), p.begin(), p.end());
  }
  out.curve = fitSlurryCurve(pts, opt.slurry.outlier_sigmas, opt.slurry.confidence);
  const double R = view.innerRadiusMm();
  out.overlay = drawSlurryOverlay(seq.frames[seq.frames.size() / 2], out.curve, millToFrameAffine(view),
                                  {R + opt.view.wall_mm, R - opt.view.margin_mm});
  return out;
}

}  // namespace millsim::vision
