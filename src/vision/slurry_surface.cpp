// Automatic slurry free-surface points (see slurry_surface.hpp).
#include "millsim/vision/slurry_surface.hpp"

#include <algorithm>
#include <cmath>
#include <opencv2/imgproc.hpp>
#include <stdexcept>

#include "millsim/vision/charge_segmentation.hpp"
#include "millsim/vision/mill_view.hpp"
#include "vision/cv_convert.hpp"

namespace millsim::vision {
namespace {

cv::Mat disc(double mm, double ppmm) {
  const int k = 2 * std::max(1, static_cast<int>(std::lround(mm * ppmm))) + 1;
  return cv::getStructuringElement(cv::MORPH_ELLIPSE, cv::Size(k, k));
}

double median(std::vector<float> v) {
  if (v.empty()) return 0.0;
  std::nth_element(v.begin(), v.begin() + v.size() / 2, v.end());
  return v[v.size() / 2];
}

}  // namespace

std::vector<SurfacePoint> slurrySurfacePoints(const ImageRgb& view, const ImageU8& mask_img, double R, double ppmm,
                                              const SlurryOptions& opt, int frame) {
  if (view.width != mask_img.width || view.height != mask_img.height || view.width <= 0)
    throw std::invalid_argument("slurrySurfacePoints: view and mask must be non-empty and of equal size");
  if (!(ppmm > 0.0) || !(R > 0.0) || !(opt.point_spacing_mm > 0.0) || !(opt.seed_radius_mm > 0.0) ||
      opt.seed_depth <= 0.0 || opt.seed_depth >= 1.0)
    throw std::invalid_argument(
        "slurrySurfacePoints: scale, radius and spacing must be positive, seed_depth in (0, 1)");
  cv::Mat bgr;
  detail::toBgr(view).convertTo(bgr, CV_32FC3);
  if (opt.denoise_sigma_px > 0.0) cv::GaussianBlur(bgr, bgr, cv::Size(0, 0), opt.denoise_sigma_px);
  const cv::Mat mask = detail::toMat(mask_img) > 0;
  const int w = view.width, h = view.height;

  // Chromaticity planes.
  cv::Mat cr(h, w, CV_32F), cg(h, w, CV_32F);
  for (int r = 0; r < h; ++r) {
    const cv::Vec3f* p = bgr.ptr<cv::Vec3f>(r);
    for (int c = 0; c < w; ++c) {
      const float s = p[c][0] + p[c][1] + p[c][2] + 3.0f;  // +3: black pixels are not a colour
      cr.at<float>(r, c) = (p[c][2] + 1.0f) / s;
      cg.at<float>(r, c) = (p[c][1] + 1.0f) / s;
    }
  }
  const int seed_col = static_cast<int>(std::lround(mmToViewCol(0.0, R, ppmm)));
  const int seed_row = static_cast<int>(std::lround(mmToViewRow(-opt.seed_depth * R, R, ppmm)));
  const int sr = std::max(1, static_cast<int>(std::lround(opt.seed_radius_mm * ppmm)));
  std::vector<float> vr, vg;
  for (int r = seed_row - sr; r <= seed_row + sr; ++r)
    for (int c = seed_col - sr; c <= seed_col + sr; ++c)
      if (r >= 0 && c >= 0 && r < h && c < w && mask.at<std::uint8_t>(r, c) &&
          (r - seed_row) * (r - seed_row) + (c - seed_col) * (c - seed_col) <= sr * sr) {
        vr.push_back(cr.at<float>(r, c));
        vg.push_back(cg.at<float>(r, c));
      }
  if (vr.empty()) return {};
  const double r0 = median(vr), g0 = median(vg);
  cv::Mat dist(h, w, CV_32F);
  std::vector<float> inside;
  for (int r = 0; r < h; ++r)
    for (int c = 0; c < w; ++c) {
      const float d = static_cast<float>(std::hypot(cr.at<float>(r, c) - r0, cg.at<float>(r, c) - g0));
      dist.at<float>(r, c) = d;
      if (mask.at<std::uint8_t>(r, c)) inside.push_back(d);
    }
  const double t = opt.colour_threshold > 0.0 ? opt.colour_threshold : otsuThreshold(inside);

  cv::Mat slurry = (dist < t) & mask;
  if (opt.close_mm > 0.0) cv::morphologyEx(slurry, slurry, cv::MORPH_CLOSE, disc(opt.close_mm, ppmm));
  if (opt.open_mm > 0.0) cv::morphologyEx(slurry, slurry, cv::MORPH_OPEN, disc(opt.open_mm, ppmm));
  slurry &= mask;
  cv::Mat labels;
  cv::connectedComponents(slurry, labels, 8, CV_32S);
  // The component under the seed; if the seed pixel itself was opened away, the commonest label
  // in the seed disc.
  int seed_label = labels.at<int>(seed_row, seed_col);
  if (seed_label == 0) {
    std::vector<int> count;
    for (int r = std::max(0, seed_row - sr); r <= std::min(h - 1, seed_row + sr); ++r)
      for (int c = std::max(0, seed_col - sr); c <= std::min(w - 1, seed_col + sr); ++c) {
        const int l = labels.at<int>(r, c);
        if (l >= static_cast<int>(count.size())) count.resize(l + 1, 0);
        if (l > 0) ++count[l];
      }
    for (int l = 1; l < static_cast<int>(count.size()); ++l)
      if (count[l] > 0 && (seed_label == 0 || count[l] > count[seed_label])) seed_label = l;
  }
  if (seed_label == 0) return {};
  cv::Mat region = labels == seed_label;
  cv::Mat padded;
  cv::copyMakeBorder(region, padded, 1, 1, 1, 1, cv::BORDER_CONSTANT, cv::Scalar(0));
  cv::floodFill(padded, cv::Point(0, 0), cv::Scalar(128));
  region |= padded(cv::Rect(1, 1, w, h)) == 0;

  std::vector<SurfacePoint> pts;
  const double step = opt.point_spacing_mm;
  for (double x = -R + 0.5 * step; x < R; x += step) {
    const int col = static_cast<int>(std::lround(mmToViewCol(x, R, ppmm)));
    if (col < 0 || col >= w) continue;
    int top = -1;
    for (int r = 0; r < h; ++r)
      if (region.at<std::uint8_t>(r, col)) {
        top = r;
        break;
      }
    // The rows just above the surface must be analysed drum, not the rim.
    if (top < 3 || !mask.at<std::uint8_t>(top - 3, col)) continue;
    // Sub-pixel: colours mix linearly across a blurred edge, so along the column the projection
    // p = (c - c_above) . D / |D|^2, D = c_below - c_above, with c_above / c_below the mean
    // colours 4-10 rows above / below, is the slurry's share of the pixel; the surface is where
    // p = 1/2, found by linear interpolation, nearest to the region's top. (A threshold of the
    // chromaticity distance would sit on the darker side of a blurred edge.)
    double row = top - 0.5;
    cv::Vec3d above(0, 0, 0), below(0, 0, 0);
    int na = 0, nb = 0;
    for (int r = top - 10; r <= top - 4; ++r)
      if (r >= 0 && mask.at<std::uint8_t>(r, col)) {
        above += cv::Vec3d(bgr.at<cv::Vec3f>(r, col));
        ++na;
      }
    for (int r = top + 4; r <= top + 10; ++r)
      if (r < h && region.at<std::uint8_t>(r, col)) {
        below += cv::Vec3d(bgr.at<cv::Vec3f>(r, col));
        ++nb;
      }
    if (na > 0 && nb > 0) {
      above /= na;
      below /= nb;
      const cv::Vec3d D = below - above;
      const double dd = D.dot(D);
      if (dd > 100.0) {  // colours at least 10 levels apart
        auto share = [&](int r) { return (cv::Vec3d(bgr.at<cv::Vec3f>(r, col)) - above).dot(D) / dd; };
        double best_gap = 1e9;
        for (int r = std::max(1, top - 4); r <= std::min(h - 1, top + 4); ++r) {
          const double p0 = share(r - 1), p1 = share(r);
          if (p0 < 0.5 && p1 >= 0.5) {
            const double rho = (r - 1) + (0.5 - p0) / (p1 - p0);
            if (std::abs(rho - top) < best_gap) {
              best_gap = std::abs(rho - top);
              row = rho;
            }
          }
        }
      }
    }
    pts.push_back({viewColToMm(col, R, ppmm), viewRowToMm(row, R, ppmm), frame});
  }
  return pts;
}

}  // namespace millsim::vision
