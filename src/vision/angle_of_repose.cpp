#include "millsim/vision/angle_of_repose.hpp"

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <cstdio>
#include <limits>
#include <sstream>
#include <stdexcept>
#include <string>

#include "millsim/vision/heatmap.hpp"

namespace millsim::vision {
namespace {

constexpr double kPi = 3.14159265358979323846;
constexpr double kRadToDeg = 180.0 / kPi;

void checkOptions(const AngleOptions& opt) {
  if (!(opt.pixels_per_mm > 0.0) || !std::isfinite(opt.pixels_per_mm)) {
    throw std::invalid_argument("angle of repose: pixels_per_mm must be positive");
  }
  if (opt.smoothing_px < 0) {
    throw std::invalid_argument("angle of repose: smoothing_px must be >= 0");
  }
  if (!std::isfinite(opt.threshold) || !std::isfinite(opt.fit_offset_mm) ||
      !std::isfinite(opt.fit_length_mm)) {
    throw std::invalid_argument("angle of repose: threshold and fit window must be finite");
  }
}

// Majority filter on a 0/1 map via a summed-area table, so the cost does not grow with the
// window: box mean over the (clipped) window, white if more than half of it is white.
std::vector<std::uint8_t> majorityFilter(const std::vector<std::uint8_t>& bin, int w, int h,
                                         int s) {
  const std::size_t stride = static_cast<std::size_t>(w) + 1;
  std::vector<std::int64_t> sat(stride * (static_cast<std::size_t>(h) + 1), 0);
  for (int y = 0; y < h; ++y) {
    std::int64_t row_sum = 0;
    for (int x = 0; x < w; ++x) {
      row_sum += bin[static_cast<std::size_t>(y) * w + x];
      sat[(y + 1) * stride + (x + 1)] = sat[y * stride + (x + 1)] + row_sum;
    }
  }
  std::vector<std::uint8_t> out(bin.size(), 0);
  for (int y = 0; y < h; ++y) {
    const int y0 = std::max(0, y - s);
    const int y1 = std::min(h - 1, y + s);
    for (int x = 0; x < w; ++x) {
      const int x0 = std::max(0, x - s);
      const int x1 = std::min(w - 1, x + s);
      const std::int64_t count = sat[(y1 + 1) * stride + (x1 + 1)] - sat[y0 * stride + (x1 + 1)] -
                                 sat[(y1 + 1) * stride + x0] + sat[y0 * stride + x0];
      const std::int64_t area = static_cast<std::int64_t>(x1 - x0 + 1) * (y1 - y0 + 1);
      out[static_cast<std::size_t>(y) * w + x] = (2 * count > area) ? 1 : 0;
    }
  }
  return out;
}

// Row of the highest white pixel of each column, -1 where the column is empty.
std::vector<int> topEdge(const ImageU8& processed) {
  std::vector<int> top(static_cast<std::size_t>(processed.width), -1);
  for (int x = 0; x < processed.width; ++x) {
    for (int y = 0; y < processed.height; ++y) {
      if (processed.at(x, y) != 0) {
        top[x] = y;
        break;
      }
    }
  }
  return top;
}

std::string formatMm(double v) {
  char buf[32];
  std::snprintf(buf, sizeof buf, "%.1f", v);
  return buf;
}

}  // namespace

LineFit fitLine(const std::vector<double>& x, const std::vector<double>& y) {
  if (x.size() != y.size()) throw std::invalid_argument("fitLine: x and y differ in length");
  const std::size_t n = x.size();
  if (n < 3) throw std::invalid_argument("fitLine: need at least 3 points for a standard error");
  // Centred sums: the plain sum-of-products formula loses digits when x is far from 0.
  double mx = 0.0, my = 0.0;
  for (std::size_t i = 0; i < n; ++i) {
    mx += x[i];
    my += y[i];
  }
  mx /= static_cast<double>(n);
  my /= static_cast<double>(n);
  double sxx = 0.0, sxy = 0.0;
  for (std::size_t i = 0; i < n; ++i) {
    sxx += (x[i] - mx) * (x[i] - mx);
    sxy += (x[i] - mx) * (y[i] - my);
  }
  if (!(sxx > 0.0)) throw std::invalid_argument("fitLine: all x are equal");
  LineFit f;
  f.slope = sxy / sxx;
  f.intercept = my - f.slope * mx;
  double ssr = 0.0;
  for (std::size_t i = 0; i < n; ++i) {
    const double r = y[i] - (f.slope * x[i] + f.intercept);
    ssr += r * r;
  }
  f.slope_stderr = std::sqrt(ssr / static_cast<double>(n - 2) / sxx);
  return f;
}

AngleResult angleFromHeatmap(const ImageF& heat, const AngleOptions& opt) {
  checkOptions(opt);
  const int w = heat.width;
  const int h = heat.height;
  if (w <= 0 || h <= 0 || heat.pixels.size() != static_cast<std::size_t>(w) * h) {
    throw std::invalid_argument("angle of repose: empty or malformed heat map");
  }
  const double ppmm = opt.pixels_per_mm;

  // Threshold: strict '>' like OpenCV's THRESH_BINARY, so 0.5 means "covered in most frames".
  std::vector<std::uint8_t> bin(heat.pixels.size());
  for (std::size_t i = 0; i < bin.size(); ++i) bin[i] = heat.pixels[i] > opt.threshold ? 1 : 0;
  if (opt.smoothing_px > 0) bin = majorityFilter(bin, w, h, opt.smoothing_px);

  AngleResult r;
  r.processed = ImageU8(w, h, 0);
  for (std::size_t i = 0; i < bin.size(); ++i) r.processed.pixels[i] = bin[i] ? 255 : 0;

  const std::vector<int> top = topEdge(r.processed);
  int high_col = -1;
  int last_col = -1;
  for (int x = 0; x < w; ++x) {
    if (top[x] < 0) continue;
    if (high_col < 0 || top[x] < top[high_col]) high_col = x;  // strict: leftmost wins ties
    last_col = x;
  }
  const int required = std::max(opt.min_points, 3);
  if (high_col < 0) {
    throw std::runtime_error("angle of repose: only 0 surface points in the fit window (the "
                             "processed heat map is empty; lower the threshold?)");
  }
  auto toXmm = [ppmm](int col) { return col / ppmm; };
  auto toYmm = [ppmm, h](int row) { return (h - 1 - row) / ppmm; };
  r.highest_x_mm = toXmm(high_col);
  r.highest_y_mm = toYmm(top[high_col]);

  const double lo = r.highest_x_mm + opt.fit_offset_mm;
  const double hi = opt.fit_length_mm > 0.0 ? lo + opt.fit_length_mm
                                            : std::numeric_limits<double>::infinity();
  const double eps = 1e-9;  // the window ends are often exact multiples of a pixel
  for (int x = 0; x < w; ++x) {
    if (top[x] < 0) continue;
    const double xm = toXmm(x);
    if (xm < lo - eps || xm > hi + eps) continue;
    r.fit_x_mm.push_back(xm);
    r.fit_y_mm.push_back(toYmm(top[x]));
  }
  r.points_used = static_cast<int>(r.fit_x_mm.size());
  if (r.points_used < required) {
    std::ostringstream msg;
    msg << "angle of repose: only " << r.points_used << " surface points in the fit window ["
        << formatMm(lo) << ", " << (std::isfinite(hi) ? formatMm(hi) : std::string("end"))
        << "] mm (need " << required << "); highest point at x = " << formatMm(r.highest_x_mm)
        << " mm, last surface point at x = " << formatMm(toXmm(last_col))
        << " mm; reduce fit_offset_mm or check threshold/scale";
    throw std::runtime_error(msg.str());
  }

  const LineFit fit = fitLine(r.fit_x_mm, r.fit_y_mm);
  r.slope = fit.slope;
  r.intercept = fit.intercept;
  r.angle_deg = std::atan(-fit.slope) * kRadToDeg;
  // d(atan(-b))/db = -1 / (1 + b^2): first-order propagation of the slope's standard error.
  r.stderr_deg = fit.slope_stderr / (1.0 + fit.slope * fit.slope) * kRadToDeg;
  return r;
}

AngleResult angleFromMasks(const std::vector<ImageU8>& masks, const AngleOptions& opt) {
  if (masks.empty()) throw std::invalid_argument("angle of repose: no masks given");
  HeatmapAccumulator acc;
  for (const ImageU8& m : masks) acc.add(m);
  return angleFromHeatmap(acc.heatmap(), opt);
}

}  // namespace millsim::vision
