#include "millsim/io/plot_png.hpp"

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <opencv2/imgproc.hpp>

#include "vision/cv_convert.hpp"

namespace millsim::io {
namespace {

cv::Scalar bgr(const std::array<int, 3>& rgb) { return cv::Scalar(rgb[2], rgb[1], rgb[0]); }

// 1, 2 or 5 times a power of ten, about `target` ticks over the span.
double tickStep(double span, int target) {
  const double raw = span / target, p = std::pow(10.0, std::floor(std::log10(raw)));
  for (double m : {1.0, 2.0, 5.0, 10.0})
    if (m * p >= raw) return m * p;
  return 10 * p;
}

std::string label(double v, double step) {
  char buf[32];
  const int digits = std::max(0, -static_cast<int>(std::floor(std::log10(step) + 1e-9)));
  std::snprintf(buf, sizeof buf, "%.*f", digits, v);
  return buf;
}

void save(const std::string& path, const cv::Mat& img) { vision::detail::writePngBgr(path, img); }

// Blue (0) - white (0.5) - red (1).
cv::Scalar diverging(double s) {
  s = std::clamp(s, 0.0, 1.0);
  const double r = s < 0.5 ? 2 * s : 1.0, b = s < 0.5 ? 1.0 : 2 * (1 - s), g = 1 - 2 * std::abs(s - 0.5);
  return cv::Scalar(255 * (0.2 + 0.8 * b), 255 * (0.2 + 0.8 * g), 255 * (0.2 + 0.8 * r));
}

}  // namespace

void writeLinePlot(const std::string& path, const PlotAxes& ax, const std::vector<PlotSeries>& series) {
  double x0 = ax.x_min, x1 = ax.x_max, y0 = ax.y_min, y1 = ax.y_max;
  if (!(x1 > x0) || !(y1 > y0)) {
    x0 = y0 = 1e300;
    x1 = y1 = -1e300;
    for (const auto& s : series)
      for (std::size_t i = 0; i < s.x.size(); ++i) {
        if (!std::isfinite(s.x[i]) || !std::isfinite(s.y[i])) continue;
        x0 = std::min(x0, s.x[i]), x1 = std::max(x1, s.x[i]);
        y0 = std::min(y0, s.y[i]), y1 = std::max(y1, s.y[i]);
      }
    if (!(x1 > x0)) x1 = x0 + 1;
    if (!(y1 > y0)) y1 = y0 + 1;
    const double my = 0.05 * (y1 - y0);
    y0 -= my;
    y1 += my;
  }
  const int W = ax.width, H = ax.height, left = 90, right = 20, top = 50, bottom = 70;
  cv::Mat img(H, W, CV_8UC3, cv::Scalar(255, 255, 255));
  auto px = [&](double x, double y) {
    return cv::Point(static_cast<int>(std::lround(left + (x - x0) / (x1 - x0) * (W - left - right))),
                     static_cast<int>(std::lround(H - bottom - (y - y0) / (y1 - y0) * (H - top - bottom))));
  };
  const cv::Scalar black(0, 0, 0), grid(225, 225, 225);
  const int font = cv::FONT_HERSHEY_SIMPLEX;
  const double xs = tickStep(x1 - x0, 8), ys = tickStep(y1 - y0, 6);
  for (double x = std::ceil(x0 / xs) * xs; x <= x1 + 1e-9 * xs; x += xs) {
    cv::line(img, px(x, y0), px(x, y1), grid, 1);
    const std::string t = label(x, xs);
    cv::putText(img, t, px(x, y0) + cv::Point(-6 * int(t.size()) / 2, 22), font, 0.5, black, 1, cv::LINE_AA);
  }
  for (double y = std::ceil(y0 / ys) * ys; y <= y1 + 1e-9 * ys; y += ys) {
    cv::line(img, px(x0, y), px(x1, y), grid, 1);
    const std::string t = label(y, ys);
    cv::putText(img, t, px(x0, y) + cv::Point(-10 - 9 * int(t.size()), 5), font, 0.5, black, 1, cv::LINE_AA);
  }
  cv::rectangle(img, px(x0, y1), px(x1, y0), black, 1);
  cv::putText(img, ax.title, cv::Point(left, 32), font, 0.7, black, 1, cv::LINE_AA);
  cv::putText(img, ax.x_label, cv::Point(left + (W - left - right) / 2 - 4 * int(ax.x_label.size()), H - 20), font, 0.6,
              black, 1, cv::LINE_AA);
  cv::Mat ylab(24, 12 * int(ax.y_label.size()) + 10, CV_8UC3, cv::Scalar(255, 255, 255));
  cv::putText(ylab, ax.y_label, cv::Point(4, 18), font, 0.6, black, 1, cv::LINE_AA);
  cv::rotate(ylab, ylab, cv::ROTATE_90_COUNTERCLOCKWISE);
  const int ly = std::max(0, (H - ylab.rows) / 2);
  if (ylab.rows <= H) ylab.copyTo(img(cv::Rect(8, ly, ylab.cols, ylab.rows)));
  cv::Mat plot = img(cv::Rect(left, top, W - left - right, H - top - bottom));
  const cv::Point offset(left, top);
  for (const auto& s : series) {
    for (std::size_t i = 0; i < s.x.size(); ++i) {
      if (!std::isfinite(s.x[i]) || !std::isfinite(s.y[i])) continue;
      const cv::Point p = px(s.x[i], s.y[i]) - offset;
      if (s.markers) cv::circle(plot, p, 5, bgr(s.rgb), 2, cv::LINE_AA);
      if (s.line && i > 0 && std::isfinite(s.x[i - 1]) && std::isfinite(s.y[i - 1]))
        cv::line(plot, px(s.x[i - 1], s.y[i - 1]) - offset, p, bgr(s.rgb), 2, cv::LINE_AA);
    }
  }
  int row = 0;
  for (const auto& s : series) {
    const cv::Point at(left + 15, top + 22 + 22 * row++);
    if (s.line) cv::line(img, at + cv::Point(0, -5), at + cv::Point(28, -5), bgr(s.rgb), 2, cv::LINE_AA);
    if (s.markers) cv::circle(img, at + cv::Point(14, -5), 5, bgr(s.rgb), 2, cv::LINE_AA);
    cv::putText(img, s.label, at + cv::Point(36, 0), font, 0.5, black, 1, cv::LINE_AA);
  }
  save(path, img);
}

void writeParticleSnapshot(const std::string& path, const std::vector<double>& x, const std::vector<double>& y,
                           const std::vector<double>& value, const std::vector<bool>& gray, double radius_m,
                           std::array<double, 4> w, double px_per_m, double v_min, double v_max,
                           const std::string& title, const std::string& value_label,
                           const std::vector<PlotCurve>& curves) {
  const int bar = 70, head = 36;
  const int W = std::max(200, static_cast<int>(std::lround((w[1] - w[0]) * px_per_m)));
  const int H = std::max(100, static_cast<int>(std::lround((w[3] - w[2]) * px_per_m)));
  cv::Mat img(H + head, W + bar, CV_8UC3, cv::Scalar(255, 255, 255));
  const int r = std::max(1, static_cast<int>(std::lround(radius_m * px_per_m)));
  for (std::size_t i = 0; i < x.size(); ++i) {
    const cv::Point p(static_cast<int>(std::lround((x[i] - w[0]) * px_per_m)),
                      head + static_cast<int>(std::lround((w[3] - y[i]) * px_per_m)));
    const cv::Scalar c = gray[i] ? cv::Scalar(150, 150, 150) : diverging((value[i] - v_min) / (v_max - v_min));
    cv::circle(img, p, r, c, cv::FILLED, cv::LINE_AA);
  }
  for (const PlotCurve& c : curves)
    for (std::size_t i = 1; i < c.x.size(); ++i) {
      auto at = [&](std::size_t k) {
        return cv::Point(static_cast<int>(std::lround((c.x[k] - w[0]) * px_per_m)),
                         head + static_cast<int>(std::lround((w[3] - c.y[k]) * px_per_m)));
      };
      cv::line(img, at(i - 1), at(i), bgr(c.rgb), c.thickness, cv::LINE_AA);
    }
  const cv::Scalar black(0, 0, 0);
  cv::putText(img, title, cv::Point(8, 24), cv::FONT_HERSHEY_SIMPLEX, 0.6, black, 1, cv::LINE_AA);
  const int bx = W + 15, by0 = head + 20, by1 = head + H - 20;
  for (int yy = by0; yy <= by1; ++yy)
    cv::line(img, cv::Point(bx, yy), cv::Point(bx + 15, yy), diverging(double(by1 - yy) / std::max(1, by1 - by0)));
  char buf[64];
  std::snprintf(buf, sizeof buf, "%.3g", v_max);
  cv::putText(img, buf, cv::Point(bx - 5, by0 - 6), cv::FONT_HERSHEY_SIMPLEX, 0.4, black, 1, cv::LINE_AA);
  std::snprintf(buf, sizeof buf, "%.3g", v_min);
  cv::putText(img, buf, cv::Point(bx - 5, by1 + 14), cv::FONT_HERSHEY_SIMPLEX, 0.4, black, 1, cv::LINE_AA);
  cv::putText(img, value_label, cv::Point(bx - 10, head + H / 2), cv::FONT_HERSHEY_SIMPLEX, 0.35, black, 1,
              cv::LINE_AA);
  save(path, img);
}

}  // namespace millsim::io
