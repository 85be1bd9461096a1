// Classical charge segmentation (see charge_segmentation.hpp for the method and its parameters).
#include "millsim/vision/charge_segmentation.hpp"

#include <algorithm>
#include <cmath>
#include <opencv2/imgproc.hpp>
#include <stdexcept>
#include <vector>

#include "vision/cv_convert.hpp"

namespace millsim::vision {
namespace {

int oddPixels(double mm, double ppmm) { return 2 * std::max(1, static_cast<int>(std::lround(0.5 * mm * ppmm))) + 1; }

std::vector<float> valuesUnder(const cv::Mat& f, const cv::Mat& mask) {
  std::vector<float> v;
  v.reserve(static_cast<std::size_t>(f.total()));
  for (int r = 0; r < f.rows; ++r) {
    const float* fr = f.ptr<float>(r);
    const std::uint8_t* mr = mask.ptr<std::uint8_t>(r);
    for (int c = 0; c < f.cols; ++c)
      if (mr[c]) v.push_back(fr[c]);
  }
  return v;
}

// Gaussian smoothing at large sigma, done on a reduced copy (the fields are smooth by design).
cv::Mat smoothLarge(const cv::Mat& f, double sigma_px) {
  const double factor = std::max(1.0, sigma_px / 4.0);
  cv::Mat small, out;
  cv::resize(f, small, cv::Size(), 1.0 / factor, 1.0 / factor, cv::INTER_AREA);
  cv::GaussianBlur(small, small, cv::Size(0, 0), sigma_px / factor, 0, cv::BORDER_REPLICATE);
  cv::resize(small, out, f.size(), 0, 0, cv::INTER_LINEAR);
  return out;
}

// Normalised convolution: smoothed f over the pixels where w = 1, filled in elsewhere.
cv::Mat classField(const cv::Mat& g, const cv::Mat& w, double sigma_px, double fallback) {
  cv::Mat num = smoothLarge(g.mul(w), sigma_px);
  cv::Mat den = smoothLarge(w, sigma_px);
  cv::Mat out(g.size(), CV_32F);
  for (int r = 0; r < g.rows; ++r) {
    const float* n = num.ptr<float>(r);
    const float* d = den.ptr<float>(r);
    float* o = out.ptr<float>(r);
    for (int c = 0; c < g.cols; ++c) o[c] = d[c] > 1e-3f ? n[c] / d[c] : static_cast<float>(fallback);
  }
  return out;
}

double meanWhere(const cv::Mat& g, const cv::Mat& w) {
  const double n = cv::sum(w)[0];
  return n > 0 ? cv::sum(g.mul(w))[0] / n : 0.0;
}

cv::Mat ellipse(double mm, double ppmm) {
  const int k = oddPixels(2.0 * mm, ppmm);
  return cv::getStructuringElement(cv::MORPH_ELLIPSE, cv::Size(k, k));
}

}  // namespace

double otsuThreshold(const std::vector<float>& values) {
  if (values.empty()) return 0.0;
  std::vector<float> s = values;
  const std::size_t k = std::min(s.size() - 1, static_cast<std::size_t>(0.995 * (s.size() - 1)));
  std::nth_element(s.begin(), s.begin() + k, s.end());
  const double hi = s[k];
  const double lo = *std::min_element(values.begin(), values.end());
  if (!(hi > lo)) return lo;
  constexpr int kBins = 256;
  std::vector<double> hist(kBins, 0.0);
  for (float v : values) {
    const int b = std::clamp(static_cast<int>((v - lo) / (hi - lo) * kBins), 0, kBins - 1);
    hist[b] += 1.0;
  }
  double total = 0, sum_all = 0;
  for (int b = 0; b < kBins; ++b) {
    total += hist[b];
    sum_all += b * hist[b];
  }
  double w0 = 0, sum0 = 0, best = -1;
  int best_b = 0;
  for (int b = 0; b < kBins - 1; ++b) {
    w0 += hist[b];
    sum0 += b * hist[b];
    const double w1 = total - w0;
    if (w0 <= 0 || w1 <= 0) continue;
    const double m0 = sum0 / w0, m1 = (sum_all - sum0) / w1;
    const double between = w0 * w1 * (m0 - m1) * (m0 - m1);
    if (between > best) {
      best = between;
      best_b = b;
    }
  }
  return lo + (best_b + 1.0) / kBins * (hi - lo);
}

ImageU8 segmentCharge(const ImageRgb& view, const ImageU8& mask_img, double ppmm, const SegmentationOptions& opt) {
  if (view.width != mask_img.width || view.height != mask_img.height || view.width <= 0)
    throw std::invalid_argument("segmentCharge: view and mask must be non-empty and of equal size");
  if (!(ppmm > 0.0) || !(opt.texture_window_mm > 0.0) || !(opt.illumination_sigma_mm > 0.0) || opt.close_mm < 0.0 ||
      opt.open_mm < 0.0 || opt.denoise_sigma_px < 0.0 || opt.dark_offset < 0.0)
    throw std::invalid_argument("segmentCharge: scale, window and sigma must be positive, radii >= 0");
  cv::Mat gray, g;
  cv::cvtColor(detail::toBgr(view), gray, cv::COLOR_BGR2GRAY);
  gray.convertTo(g, CV_32F);
  if (opt.denoise_sigma_px > 0.0) cv::GaussianBlur(g, g, cv::Size(0, 0), opt.denoise_sigma_px);
  const cv::Mat mask = detail::toMat(mask_img) > 0;
  cv::Mat m;
  mask.convertTo(m, CV_32F, 1.0 / 255.0);

  cv::Mat charge;  // 8U, 255 = charge
  if (opt.mode == ChargeMode::Balls) {
    const int w = oddPixels(opt.texture_window_mm, ppmm);
    cv::Mat s1, s2, n;
    cv::boxFilter(g.mul(m), s1, CV_32F, cv::Size(w, w), cv::Point(-1, -1), false);
    cv::boxFilter(g.mul(g).mul(m), s2, CV_32F, cv::Size(w, w), cv::Point(-1, -1), false);
    cv::boxFilter(m, n, CV_32F, cv::Size(w, w), cv::Point(-1, -1), false);
    cv::Mat contrast(g.size(), CV_32F, cv::Scalar(0));
    for (int r = 0; r < g.rows; ++r) {
      const float* a = s1.ptr<float>(r);
      const float* b = s2.ptr<float>(r);
      const float* c = n.ptr<float>(r);
      float* o = contrast.ptr<float>(r);
      for (int col = 0; col < g.cols; ++col) {
        if (c[col] < 1.0f) continue;
        const double mean = a[col] / c[col];
        const double var = std::max(0.0, b[col] / c[col] - mean * mean);
        o[col] = static_cast<float>(std::sqrt(var) / (mean + opt.dark_offset));
      }
    }
    const double t = opt.texture_threshold > 0.0 ? opt.texture_threshold : otsuThreshold(valuesUnder(contrast, mask));
    charge = (contrast > t) & mask;
  } else {
    if (opt.intensity_threshold > 0.0) {
      charge = (opt.charge_brighter ? (g > opt.intensity_threshold) : (g < opt.intensity_threshold)) & mask;
    } else {
      const double t0 = otsuThreshold(valuesUnder(g, mask));
      cv::Mat is_charge = (opt.charge_brighter ? (g > t0) : (g < t0)) & mask;
      const double sigma = opt.illumination_sigma_mm * ppmm;
      for (int round = 0; round < 3; ++round) {
        cv::Mat wc, wb;
        is_charge.convertTo(wc, CV_32F, 1.0 / 255.0);
        wb = m - wc;
        const cv::Mat c_field = classField(g, wc, sigma, meanWhere(g, wc));
        const cv::Mat b_field = classField(g, wb, sigma, meanWhere(g, wb));
        const cv::Mat mid = 0.5 * (c_field + b_field);
        is_charge = (opt.charge_brighter ? (g > mid) : (g < mid)) & mask;
      }
      charge = is_charge;
    }
  }

  if (opt.close_mm > 0.0) cv::morphologyEx(charge, charge, cv::MORPH_CLOSE, ellipse(opt.close_mm, ppmm));
  if (opt.open_mm > 0.0) cv::morphologyEx(charge, charge, cv::MORPH_OPEN, ellipse(opt.open_mm, ppmm));
  charge &= mask;

  // Components: keep those at least min_component_fraction of the largest.
  cv::Mat labels, stats, centroids;
  const int n = cv::connectedComponentsWithStats(charge, labels, stats, centroids, 8, CV_32S);
  int largest = 0;
  for (int i = 1; i < n; ++i) largest = std::max(largest, stats.at<int>(i, cv::CC_STAT_AREA));
  std::vector<std::uint8_t> keep(static_cast<std::size_t>(std::max(n, 1)), 0);
  for (int i = 1; i < n; ++i)
    keep[i] = stats.at<int>(i, cv::CC_STAT_AREA) >= opt.min_component_fraction * largest ? 255 : 0;
  for (int r = 0; r < charge.rows; ++r) {
    const int* l = labels.ptr<int>(r);
    std::uint8_t* o = charge.ptr<std::uint8_t>(r);
    for (int c = 0; c < charge.cols; ++c) o[c] = keep[l[c]];
  }

  // Holes: background not connected to the outside of the drum.
  cv::Mat padded;
  cv::copyMakeBorder(charge, padded, 1, 1, 1, 1, cv::BORDER_CONSTANT, cv::Scalar(0));
  cv::floodFill(padded, cv::Point(0, 0), cv::Scalar(128));
  const cv::Mat holes = padded(cv::Rect(1, 1, charge.cols, charge.rows)) == 0;
  charge |= holes;
  charge &= mask;
  return detail::toImageU8(charge);
}

}  // namespace millsim::vision
