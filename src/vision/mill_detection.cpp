// Mill outline detection: Hough circle, then least-squares refinement (see mill_detection.hpp).
#include "millsim/vision/mill_detection.hpp"

#include <algorithm>
#include <cmath>
#include <opencv2/imgproc.hpp>
#include <sstream>
#include <stdexcept>
#include <vector>

#include "millsim/core/error.hpp"
#include "vision/cv_convert.hpp"

namespace millsim::vision {
namespace {

constexpr double kPi = 3.14159265358979323846;

struct Pt {
  double x, y;
};

// Kasa fit: minimise sum (x^2 + y^2 + D x + E y + F)^2, linear in D, E, F.
bool fitCircle(const std::vector<Pt>& p, double& cx, double& cy, double& r) {
  if (p.size() < 3) return false;
  // Centre the points first so the normal equations are well conditioned.
  double mx = 0, my = 0;
  for (const Pt& q : p) {
    mx += q.x;
    my += q.y;
  }
  mx /= p.size();
  my /= p.size();
  double suu = 0, svv = 0, suv = 0, suuu = 0, svvv = 0, suvv = 0, svuu = 0;
  for (const Pt& q : p) {
    const double u = q.x - mx, v = q.y - my;
    suu += u * u;
    svv += v * v;
    suv += u * v;
    suuu += u * u * u;
    svvv += v * v * v;
    suvv += u * v * v;
    svuu += v * u * u;
  }
  // [suu suv; suv svv] [uc; vc] = 0.5 [suuu + suvv; svvv + svuu]
  const double det = suu * svv - suv * suv;
  if (std::abs(det) < 1e-12) return false;
  const double b1 = 0.5 * (suuu + suvv), b2 = 0.5 * (svvv + svuu);
  const double uc = (b1 * svv - b2 * suv) / det;
  const double vc = (suu * b2 - suv * b1) / det;
  cx = uc + mx;
  cy = vc + my;
  r = std::sqrt(uc * uc + vc * vc + (suu + svv) / p.size());
  return std::isfinite(r);
}

double bilinear(const cv::Mat& img, double x, double y) {
  const int x0 = static_cast<int>(std::floor(x)), y0 = static_cast<int>(std::floor(y));
  if (x0 < 0 || y0 < 0 || x0 + 1 >= img.cols || y0 + 1 >= img.rows) return std::nan("");
  const double fx = x - x0, fy = y - y0;
  const float* r0 = img.ptr<float>(y0);
  const float* r1 = img.ptr<float>(y0 + 1);
  return (1 - fy) * ((1 - fx) * r0[x0] + fx * r0[x0 + 1]) + fy * ((1 - fx) * r1[x0] + fx * r1[x0 + 1]);
}

void refine(const cv::Mat& gray, MillCircle& c, double band) {
  cv::Mat g;
  gray.convertTo(g, CV_32F);
  cv::GaussianBlur(g, g, cv::Size(0, 0), 1.2);
  const double r_lo = c.radius_px * (1.0 - band), r_hi = c.radius_px * (1.0 + band);
  const double step = 0.5;
  const int rays = 360;
  // Every ray's edge peaks (local maxima of |dI/dr| of at least a quarter of the ray's largest).
  struct Peak {
    double r;
  };
  std::vector<std::vector<Peak>> peaks(rays);
  std::vector<double> prof;
  int valid_rays = 0;
  for (int k = 0; k < rays; ++k) {
    const double th = 2.0 * kPi * k / rays;
    const double ux = std::cos(th), uy = std::sin(th);
    prof.clear();
    bool inside = true;
    for (double r = r_lo - step; r <= r_hi + step + 1e-9; r += step) {
      const double v = bilinear(g, c.cx_px + r * ux, c.cy_px + r * uy);
      if (std::isnan(v)) {
        inside = false;
        break;
      }
      prof.push_back(v);
    }
    if (!inside || prof.size() < 5) continue;
    std::vector<double> d(prof.size(), 0.0);
    double dmax = 0.0;
    for (std::size_t i = 1; i + 1 < prof.size(); ++i) {
      d[i] = std::abs(prof[i + 1] - prof[i - 1]) / (2 * step);
      dmax = std::max(dmax, d[i]);
    }
    if (!(dmax > 2.0)) continue;  // no edge on this ray (occluded or featureless): leave it out
    ++valid_rays;
    for (std::size_t i = 2; i + 2 < d.size(); ++i) {
      if (d[i] >= 0.25 * dmax && d[i] > d[i - 1] && d[i] >= d[i + 1]) {
        // Parabola through the three samples for the sub-sample peak.
        const double den = d[i - 1] - 2 * d[i] + d[i + 1];
        const double off = std::abs(den) > 1e-12 ? 0.5 * (d[i - 1] - d[i + 1]) / den : 0.0;
        peaks[k].push_back({r_lo - step + (static_cast<double>(i) + std::clamp(off, -0.5, 0.5)) * step});
      }
    }
  }
  if (valid_rays < rays / 4) return;  // too little outline visible: keep Hough
  // Circular edges are peaks at the same radius on many rays: count, per 0.5 px radius bin, the
  // rays with a peak within +-1 px, and take the outermost bin seen by at least 40 % of the rays.
  const int bins = static_cast<int>(std::ceil((r_hi - r_lo) / step)) + 1;
  std::vector<int> support(bins, 0);
  for (int b = 0; b < bins; ++b) {
    const double rb = r_lo + b * step;
    for (const auto& list : peaks)
      for (const Peak& p : list)
        if (std::abs(p.r - rb) <= 1.0) {
          ++support[b];
          break;
        }
  }
  int chosen = -1;
  for (int b = bins - 1; b >= 0; --b) {
    if (support[b] < 0.4 * valid_rays) continue;
    // Walk to the top of this support peak.
    while (b > 0 && support[b - 1] > support[b]) --b;
    chosen = b;
    break;
  }
  if (chosen < 0) return;
  const double r_edge = r_lo + chosen * step;
  std::vector<Pt> pts;
  for (int k = 0; k < rays; ++k) {
    const double th = 2.0 * kPi * k / rays;
    double best = -1.0;
    for (const Peak& p : peaks[k])
      if (std::abs(p.r - r_edge) <= 2.0 && (best < 0 || std::abs(p.r - r_edge) < std::abs(best - r_edge))) best = p.r;
    if (best > 0) pts.push_back({c.cx_px + best * std::cos(th), c.cy_px + best * std::sin(th)});
  }
  if (static_cast<int>(pts.size()) < rays / 4) return;
  double cx = c.cx_px, cy = c.cy_px, r = c.radius_px;
  std::vector<Pt> use = pts;
  for (int iter = 0; iter < 4; ++iter) {
    if (!fitCircle(use, cx, cy, r)) return;
    std::vector<double> res;
    for (const Pt& q : pts) res.push_back(std::abs(std::hypot(q.x - cx, q.y - cy) - r));
    std::vector<double> sorted = res;
    std::nth_element(sorted.begin(), sorted.begin() + sorted.size() / 2, sorted.end());
    const double sigma = std::max(0.5, 1.4826 * sorted[sorted.size() / 2]);
    use.clear();
    for (std::size_t i = 0; i < pts.size(); ++i)
      if (res[i] <= 3.0 * sigma) use.push_back(pts[i]);
    if (use.size() < 3) return;
  }
  if (!fitCircle(use, cx, cy, r)) return;
  double ss = 0;
  for (const Pt& q : use) ss += std::pow(std::hypot(q.x - cx, q.y - cy) - r, 2);
  // A refinement that walks away from the Hough circle locked onto something else: keep Hough.
  if (std::hypot(cx - c.cx_px, cy - c.cy_px) > band * c.radius_px || std::abs(r - c.radius_px) > band * c.radius_px)
    return;
  c.cx_px = cx;
  c.cy_px = cy;
  c.radius_px = r;
  c.refined = true;
  c.edge_points = static_cast<int>(use.size());
  c.residual_px = std::sqrt(ss / use.size());
}

}  // namespace

ImageRgb meanFrame(const std::vector<ImageRgb>& frames, int max_frames) {
  if (frames.empty()) throw std::invalid_argument("meanFrame: no frames");
  const int n = std::min<int>(static_cast<int>(frames.size()), std::max(1, max_frames));
  const ImageRgb& f0 = frames.front();
  std::vector<double> acc(f0.pixels.size() * 3, 0.0);
  for (int k = 0; k < n; ++k) {
    // Spread the chosen frames over the sequence rather than taking the first n.
    const ImageRgb& f = frames[static_cast<std::size_t>(k) * frames.size() / n];
    if (f.width != f0.width || f.height != f0.height) throw std::invalid_argument("meanFrame: frames differ in size");
    for (std::size_t i = 0; i < f.pixels.size(); ++i) {
      acc[3 * i] += f.pixels[i].r;
      acc[3 * i + 1] += f.pixels[i].g;
      acc[3 * i + 2] += f.pixels[i].b;
    }
  }
  ImageRgb out(f0.width, f0.height);
  for (std::size_t i = 0; i < out.pixels.size(); ++i) {
    out.pixels[i] = {static_cast<std::uint8_t>(std::lround(acc[3 * i] / n)),
                     static_cast<std::uint8_t>(std::lround(acc[3 * i + 1] / n)),
                     static_cast<std::uint8_t>(std::lround(acc[3 * i + 2] / n))};
  }
  return out;
}

MillCircle detectMill(const ImageRgb& frame, const MillDetectionOptions& opt) {
  if (frame.width <= 0 || frame.height <= 0) throw std::invalid_argument("detectMill: empty frame");
  if (!(opt.radius_tolerance > 0.0) || !(opt.refine_band > 0.0) || opt.min_votes < 1 ||
      !(opt.max_radius_fraction > opt.min_radius_fraction) || !(opt.min_radius_fraction > 0.0))
    throw std::invalid_argument("detectMill: bad options (tolerances, band and radius fractions must be positive)");
  cv::Mat gray;
  cv::cvtColor(detail::toBgr(frame), gray, cv::COLOR_BGR2GRAY);

  const double half_short = 0.5 * std::min(frame.width, frame.height);
  double r_min = opt.min_radius_fraction * half_short, r_max = opt.max_radius_fraction * half_short;
  if (opt.expected_radius_px > 0.0) {
    r_min = opt.expected_radius_px * (1.0 - opt.radius_tolerance);
    r_max = opt.expected_radius_px * (1.0 + opt.radius_tolerance);
  }
  const double scale = std::min(1.0, 640.0 / std::max(frame.width, frame.height));
  cv::Mat small;
  if (scale < 1.0)
    cv::resize(gray, small, cv::Size(), scale, scale, cv::INTER_AREA);
  else
    small = gray;
  cv::GaussianBlur(small, small, cv::Size(0, 0), 2.0);

  std::vector<cv::Vec3f> circles;
  const int lo = std::max(1, static_cast<int>(std::floor(r_min * scale)));
  const int hi = std::max(lo + 1, static_cast<int>(std::ceil(r_max * scale)));
  for (int votes = 120; votes >= opt.min_votes && circles.empty(); votes = votes * 3 / 4) {
    cv::HoughCircles(small, circles, cv::HOUGH_GRADIENT, 1.0, std::max(small.cols, small.rows), opt.canny_high, votes,
                     lo, hi);
  }
  if (circles.empty()) {
    std::ostringstream m;
    m.precision(0);
    m << std::fixed << "no mill outline found: no circle of radius " << r_min << "-" << r_max << " px in the "
      << frame.width << "x" << frame.height << " frame (check --diameter-mm/--radius-px, or that the whole drum rim is "
      << "in the picture)";
    throw core::InputError(m.str());
  }
  MillCircle c;
  c.cx_px = circles[0][0] / scale;
  c.cy_px = circles[0][1] / scale;
  c.radius_px = circles[0][2] / scale;
  if (opt.refine) refine(gray, c, opt.refine_band);
  return c;
}

}  // namespace millsim::vision
