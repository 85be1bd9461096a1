// Angle-of-repose overlay, one drawing routine for video and simulation (see angle_overlay.hpp).
#include "millsim/vision/angle_overlay.hpp"

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <opencv2/imgproc.hpp>
#include <stdexcept>

#include "vision/cv_convert.hpp"

namespace millsim::vision {
namespace {

constexpr int kShift = 4;  // sub-pixel drawing: coordinates in 1/16 px
constexpr double kOne = 1 << kShift;

cv::Point2d place(const std::array<double, 6>& a, double col, double row) {
  return {a[0] * col + a[1] * row + a[2], a[3] * col + a[4] * row + a[5]};
}
cv::Point fixedPoint(const cv::Point2d& p) {
  return {static_cast<int>(std::lround(p.x * kOne)), static_cast<int>(std::lround(p.y * kOne))};
}

}  // namespace

ImageRgb heatmapColour(const ImageF& heat) {
  ImageRgb img(heat.width, heat.height, Rgb{0, 0, 0});
  for (std::size_t i = 0; i < img.pixels.size() && i < heat.pixels.size(); ++i) {
    const float v = heat.pixels[i];
    if (!(v > 0.0f)) continue;  // zero stays black so the empty drum does not read as charge
    const double t = std::min(1.0, static_cast<double>(v));
    const double g = 1.0 - std::abs(2.0 * t - 1.0);  // a little green mid-way marks the 0.5 contour
    img.pixels[i] = {static_cast<std::uint8_t>(std::lround(40 + 215 * t)),
                     static_cast<std::uint8_t>(std::lround(160 * g)),
                     static_cast<std::uint8_t>(std::lround(40 + 215 * (1.0 - t)))};
  }
  return img;
}

ImageRgb drawAngleOverlay(const ImageRgb& background, const AngleResult& r, double ppmm, const OverlayLayout& layout) {
  if (!(ppmm > 0.0)) throw std::invalid_argument("drawAngleOverlay: ppmm must be positive");
  if (background.width <= 0 || background.height <= 0)
    throw std::invalid_argument("drawAngleOverlay: empty background");
  cv::Mat img = detail::toBgr(background);
  const auto& A = layout.view_to_image;
  const double scale = std::sqrt(std::abs(A[0] * A[4] - A[1] * A[3]));  // view px -> image px
  const int h = r.processed.height;
  const int thick = std::max(1, static_cast<int>(std::lround(img.cols / 400.0)));

  const double vc = 0.5 * (r.processed.width - 1), vr = 0.5 * (h - 1);
  for (double rad : layout.circle_radii_px) {
    cv::circle(img, fixedPoint(place(A, vc, vr)), static_cast<int>(std::lround(rad * scale * kOne)),
               cv::Scalar(255, 255, 0), thick, cv::LINE_AA, kShift);
  }

  // Outline of the processed (thresholded, smoothed) heat map.
  if (r.processed.width > 0 && h > 0) {
    std::vector<std::vector<cv::Point>> contours;
    cv::findContours(detail::toMat(r.processed), contours, cv::RETR_EXTERNAL, cv::CHAIN_APPROX_NONE);
    for (auto& c : contours) {
      std::vector<cv::Point> mapped;
      mapped.reserve(c.size());
      for (const cv::Point& p : c) mapped.push_back(fixedPoint(place(A, p.x, p.y)));
      cv::polylines(img, mapped, true, cv::Scalar(0, 255, 255), thick, cv::LINE_AA, kShift);
    }
  }

  auto viewPoint = [&](double x_mm, double y_mm) { return place(A, x_mm * ppmm, (h - 1) - y_mm * ppmm); };
  // Edge points used in the fit, then the fitted line over the fit window.
  for (std::size_t k = 0; k < r.fit_x_mm.size(); k += 4)
    cv::circle(img, fixedPoint(viewPoint(r.fit_x_mm[k], r.fit_y_mm[k])), static_cast<int>(1.5 * kOne),
               cv::Scalar(0, 140, 255), cv::FILLED, cv::LINE_8, kShift);
  if (!r.fit_x_mm.empty()) {
    const double x0 = r.fit_x_mm.front(), x1 = r.fit_x_mm.back();
    cv::line(img, fixedPoint(viewPoint(x0, r.slope * x0 + r.intercept)),
             fixedPoint(viewPoint(x1, r.slope * x1 + r.intercept)), cv::Scalar(255, 255, 255), std::max(3, thick + 1),
             cv::LINE_8, kShift);
  }
  // Highest point.
  const cv::Point2d hp = viewPoint(r.highest_x_mm, r.highest_y_mm);
  const double arm = 7.0 * thick;
  cv::line(img, fixedPoint(hp - cv::Point2d(arm, 0)), fixedPoint(hp + cv::Point2d(arm, 0)), cv::Scalar(0, 255, 0),
           thick + 1, cv::LINE_8, kShift);
  cv::line(img, fixedPoint(hp - cv::Point2d(0, arm)), fixedPoint(hp + cv::Point2d(0, arm)), cv::Scalar(0, 255, 0),
           thick + 1, cv::LINE_8, kShift);

  // Text, white on a black box, scaled with the picture.
  char text[64];
  std::snprintf(text, sizeof text, "%.1f +/- %.2f deg", r.angle_deg, r.stderr_deg);
  const double font = std::max(0.5, img.cols / 600.0);
  const int ft = std::max(1, static_cast<int>(std::lround(2 * font)));
  auto label = [&](const std::string& s, int y, double f) {
    int base = 0;
    const cv::Size sz = cv::getTextSize(s, cv::FONT_HERSHEY_SIMPLEX, f, ft, &base);
    cv::rectangle(img, cv::Point(4, y - sz.height - 6), cv::Point(12 + sz.width, y + base), cv::Scalar(0, 0, 0),
                  cv::FILLED);
    cv::putText(img, s, cv::Point(8, y), cv::FONT_HERSHEY_SIMPLEX, f, cv::Scalar(255, 255, 255), ft, cv::LINE_AA);
    return y + sz.height + base + 8;
  };
  int y = static_cast<int>(std::lround(30 * font));
  y = label(text, y, font);
  if (!layout.caption.empty()) label(layout.caption, y + static_cast<int>(8 * font), 0.6 * font);
  return detail::toImageRgb(img);
}

ImageRgb renderAngleOverlay(const ImageF& heat, const AngleResult& r, double ppmm) {
  OverlayLayout layout;
  layout.circle_radii_px = {0.5 * heat.width};
  return drawAngleOverlay(heatmapColour(heat), r, ppmm, layout);
}

}  // namespace millsim::vision
