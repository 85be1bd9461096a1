// The SSE map picture (paper Figure 20 style), drawn with OpenCV (see header).
#include "millsim/calib/sse_map.hpp"

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <opencv2/imgproc.hpp>

#include "vision/cv_convert.hpp"

namespace millsim::calib {

namespace {

constexpr int kLeft = 95, kTop = 45, kBottom = 82, kBarGap = 28, kBarWidth = 22, kRight = 75;
const cv::Scalar kBlack(0, 0, 0), kWhite(255, 255, 255), kGrey(90, 90, 90);
constexpr int kFont = cv::FONT_HERSHEY_SIMPLEX;

// Green (low) -> yellow -> red (high), as in the paper; BGR.
cv::Vec3b colour(double t) {
  t = std::clamp(t, 0.0, 1.0);
  if (t < 0.5) {
    const double s = t / 0.5;
    return cv::Vec3b(30, static_cast<uchar>(160 + 70 * s), static_cast<uchar>(40 + 200 * s));
  }
  const double s = (t - 0.5) / 0.5;
  return cv::Vec3b(30, static_cast<uchar>(230 - 200 * s), static_cast<uchar>(240 - 30 * s));
}

// Bilinear value of the n x n grid at unit coordinates.
double sample(const std::vector<double>& s, int n, double u, double v) {
  const double x = std::clamp(u, 0.0, 1.0) * (n - 1), y = std::clamp(v, 0.0, 1.0) * (n - 1);
  const int i = std::min(static_cast<int>(x), n - 2), j = std::min(static_cast<int>(y), n - 2);
  const double fx = x - i, fy = y - j;
  const auto at = [&](int a, int b) { return s[static_cast<std::size_t>(b) * n + a]; };
  return (1 - fy) * ((1 - fx) * at(i, j) + fx * at(i + 1, j)) + fy * ((1 - fx) * at(i, j + 1) + fx * at(i + 1, j + 1));
}

std::string fmt(const char* f, double v) {
  char buf[32];
  std::snprintf(buf, sizeof buf, f, v);
  return buf;
}

void text(cv::Mat& img, const std::string& s, cv::Point at, double scale, int align = 0, int thickness = 1) {
  int base = 0;
  const cv::Size sz = cv::getTextSize(s, kFont, scale, thickness, &base);
  if (align == 1) at.x -= sz.width / 2;  // centred
  if (align == 2) at.x -= sz.width;      // right-aligned
  cv::putText(img, s, at, kFont, scale, kBlack, thickness, cv::LINE_AA);
}

void star(cv::Mat& img, cv::Point c, int r) {
  std::vector<cv::Point> p;
  for (int k = 0; k < 10; ++k) {
    const double a = -std::acos(-1.0) / 2 + k * std::acos(-1.0) / 5, rr = k % 2 ? 0.45 * r : r;
    p.emplace_back(c.x + static_cast<int>(std::lround(rr * std::cos(a))),
                   c.y + static_cast<int>(std::lround(rr * std::sin(a))));
  }
  cv::fillPoly(img, std::vector<std::vector<cv::Point>>{p}, cv::Scalar(230, 60, 20), cv::LINE_AA);
  cv::polylines(img, std::vector<std::vector<cv::Point>>{p}, true, kWhite, 1, cv::LINE_AA);
}

}  // namespace

void writeSseMap(const std::string& path, const ParamBox& box, const std::vector<double>& surface, int n,
                 const std::vector<Evaluation>& evaluations, int initial, int best, const SseMapOptions& options) {
  if (n < 2 || surface.size() != static_cast<std::size_t>(n) * n)
    throw std::invalid_argument("writeSseMap: surface must hold n x n values");
  const int S = options.size_px;
  const int W = kLeft + S + kBarGap + kBarWidth + kRight, H = kTop + S + kBottom;
  cv::Mat img(H, W, CV_8UC3, cv::Scalar(255, 255, 255));

  // Colour scale: from the lowest surrogate value (not below 0, an SSE cannot be) to the
  // highest SSE evaluated, so the region explored spans the whole scale.
  double lo = 1e300, hi = -1e300;
  for (double v : surface)
    if (std::isfinite(v)) lo = std::min(lo, v);
  for (const Evaluation& ev : evaluations)
    if (ev.ok) hi = std::max(hi, ev.sse);
  lo = std::max(0.0, lo);
  if (!(hi > lo)) hi = lo + 1;

  // Square-root scale: SSEs span orders of magnitude (a far corner is 100x the optimum), and on
  // a linear scale the whole basin would be one colour.
  const double rlo = std::sqrt(lo), rhi = std::sqrt(hi);
  const auto scale = [&](double v) { return (std::sqrt(std::max(v, 0.0)) - rlo) / (rhi - rlo); };
  const auto unscale = [&](double t) { return (rlo + t * (rhi - rlo)) * (rlo + t * (rhi - rlo)); };
  cv::Mat field(S, S, CV_64F);
  for (int py = 0; py < S; ++py)
    for (int px = 0; px < S; ++px) {
      const double v = sample(surface, n, px / (S - 1.0), 1.0 - py / (S - 1.0));
      field.at<double>(py, px) = v;
      img.at<cv::Vec3b>(kTop + py, kLeft + px) = std::isfinite(v) ? colour(scale(v)) : cv::Vec3b(200, 200, 200);
    }
  // Contours at evenly spaced levels: boundaries of {value < level}.
  cv::Mat roi = img(cv::Rect(kLeft, kTop, S, S));
  for (int k = 1; k < options.levels; ++k) {
    const double level = unscale(static_cast<double>(k) / options.levels);
    cv::Mat below = field < level;
    std::vector<std::vector<cv::Point>> contours;
    cv::findContours(below, contours, cv::RETR_LIST, cv::CHAIN_APPROX_NONE);
    // Leave out the frame of the plot (a region touching the border closes along it).
    for (auto& c : contours) {
      std::vector<cv::Point> inner;
      for (const auto& p : c) {
        const bool edge = p.x <= 0 || p.y <= 0 || p.x >= S - 1 || p.y >= S - 1;
        if (!edge) inner.push_back(p);
        if (edge || &p == &c.back()) {
          if (inner.size() > 2) cv::polylines(roi, inner, false, kGrey, 1, cv::LINE_AA);
          inner.clear();
        }
      }
    }
  }
  cv::rectangle(img, cv::Rect(kLeft - 1, kTop - 1, S + 2, S + 2), kBlack, 1);

  // Evaluated candidates: initial squares, later circles, failed crosses, numbered in order.
  const auto toPixel = [&](double e, double mu) {
    const Point2 u = box.toUnit(e, mu);
    return cv::Point(kLeft + static_cast<int>(std::lround(u[0] * (S - 1))),
                     kTop + static_cast<int>(std::lround((1 - u[1]) * (S - 1))));
  };
  for (std::size_t i = 0; i < evaluations.size(); ++i) {
    const Evaluation& ev = evaluations[i];
    const cv::Point p = toPixel(ev.candidate.e, ev.candidate.mu);
    if (!ev.ok) {
      cv::drawMarker(img, p, kBlack, cv::MARKER_TILTED_CROSS, 10, 2, cv::LINE_AA);
    } else if (ev.candidate.index < initial) {
      cv::rectangle(img, cv::Rect(p.x - 4, p.y - 4, 9, 9), kWhite, cv::FILLED);
      cv::rectangle(img, cv::Rect(p.x - 4, p.y - 4, 9, 9), kBlack, 1);
    } else {
      cv::circle(img, p, 4, kWhite, cv::FILLED, cv::LINE_AA);
      cv::circle(img, p, 4, kBlack, 1, cv::LINE_AA);
    }
    text(img, std::to_string(ev.candidate.index + 1), p + cv::Point(6, -5), 0.33);
  }
  if (best >= 0 && best < static_cast<int>(evaluations.size())) {
    const Evaluation& b = evaluations[best];
    star(img, toPixel(b.candidate.e, b.candidate.mu), 11);
  }

  // Axes: five intervals each, labels.
  for (int k = 0; k <= 5; ++k) {
    const int x = kLeft + static_cast<int>(std::lround(k / 5.0 * (S - 1)));
    const int y = kTop + static_cast<int>(std::lround((1 - k / 5.0) * (S - 1)));
    cv::line(img, {x, kTop + S}, {x, kTop + S + 5}, kBlack, 1);
    text(img, fmt("%.3f", box.e_min + k / 5.0 * (box.e_max - box.e_min)), {x, kTop + S + 20}, 0.42, 1);
    cv::line(img, {kLeft - 6, y}, {kLeft, y}, kBlack, 1);
    text(img, fmt("%.3f", box.mu_min + k / 5.0 * (box.mu_max - box.mu_min)), {kLeft - 9, y + 5}, 0.42, 2);
  }
  text(img, "coefficient of restitution e", {kLeft + S / 2, kTop + S + 48}, 0.55, 1);
  {
    const std::string label = "coefficient of kinetic friction mu";
    int base = 0;
    const cv::Size sz = cv::getTextSize(label, kFont, 0.55, 1, &base);
    cv::Mat t(sz.height + base + 6, sz.width + 6, CV_8UC3, kWhite);
    cv::putText(t, label, {3, sz.height + 3}, kFont, 0.55, kBlack, 1, cv::LINE_AA);
    cv::Mat r;
    cv::rotate(t, r, cv::ROTATE_90_COUNTERCLOCKWISE);
    const int x0 = 8, y0 = std::max(0, kTop + S / 2 - r.rows / 2);
    r.copyTo(img(cv::Rect(x0, y0, r.cols, std::min(r.rows, H - y0))));
  }
  text(img, options.title, {kLeft + S / 2, 28}, 0.55, 1);

  // Colour bar.
  const int bx = kLeft + S + kBarGap;
  for (int py = 0; py < S; ++py)
    cv::line(img, {bx, kTop + py}, {bx + kBarWidth - 1, kTop + py}, cv::Scalar(colour(1.0 - py / (S - 1.0))), 1);
  cv::rectangle(img, cv::Rect(bx - 1, kTop - 1, kBarWidth + 2, S + 2), kBlack, 1);
  for (int k = 0; k <= 5; ++k) {
    const int y = kTop + static_cast<int>(std::lround((1 - k / 5.0) * (S - 1)));
    cv::line(img, {bx + kBarWidth, y}, {bx + kBarWidth + 5, y}, kBlack, 1);
    const double v = unscale(k / 5.0);
    text(img, fmt(v < 10 ? "%.2f" : "%.1f", v), {bx + kBarWidth + 8, y + 5}, 0.42);
  }
  text(img, "SSE (sqrt scale)", {bx + kBarWidth / 2 + 10, kTop - 8}, 0.38, 1);
  text(img, "squares: initial candidates, circles: later ones (numbered in order), x: failed, star: best",
       {kLeft + S / 2, kTop + S + 70}, 0.36, 1);

  vision::detail::writePngBgr(path, img);
}

}  // namespace millsim::calib
