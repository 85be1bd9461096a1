#include "millsim/vision/render_discs.hpp"

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <stdexcept>

namespace millsim::vision {

ImageU8 renderDiscs(const std::vector<double>& cx, const std::vector<double>& cy,
                    const std::vector<double>& radius, double x_min, double y_min,
                    double width_m, double height_m, double pixels_per_mm) {
  if (cx.size() != cy.size() || cx.size() != radius.size()) {
    throw std::invalid_argument("renderDiscs: cx, cy and radius differ in length");
  }
  if (!(pixels_per_mm > 0.0) || !(width_m > 0.0) || !(height_m > 0.0) ||
      !std::isfinite(pixels_per_mm * width_m * height_m)) {
    throw std::invalid_argument("renderDiscs: scale and window size must be positive");
  }
  const double s = pixels_per_mm * 1000.0;  // pixels per metre
  const int w = static_cast<int>(std::lround(width_m * s));
  const int h = static_cast<int>(std::lround(height_m * s));
  ImageU8 img(w, h, 0);
  if (w == 0 || h == 0) return img;
  const double y_top = y_min + height_m;

  // Clamp in double before converting: a disc far outside the window must not overflow int.
  auto clampIndex = [](double v, int n) {
    return static_cast<int>(std::clamp(v, -1.0, static_cast<double>(n)));
  };
  for (std::size_t i = 0; i < cx.size(); ++i) {
    const double r = radius[i];
    if (!(r > 0.0) || !std::isfinite(cx[i]) || !std::isfinite(cy[i])) continue;
    // Pixel centres inside the bounding box: (col + 0.5) / s in [cx - r - x_min, cx + r - x_min].
    const int c0 = std::max(0, clampIndex(std::ceil((cx[i] - r - x_min) * s - 0.5), w));
    const int c1 = std::min(w - 1, clampIndex(std::floor((cx[i] + r - x_min) * s - 0.5), w));
    const int r0 = std::max(0, clampIndex(std::ceil((y_top - (cy[i] + r)) * s - 0.5), h));
    const int r1 = std::min(h - 1, clampIndex(std::floor((y_top - (cy[i] - r)) * s - 0.5), h));
    const double r2 = r * r;
    for (int row = r0; row <= r1; ++row) {
      const double dy = (y_top - (row + 0.5) / s) - cy[i];
      for (int col = c0; col <= c1; ++col) {
        const double dx = (x_min + (col + 0.5) / s) - cx[i];
        if (dx * dx + dy * dy < r2) img.at(col, row) = 255;
      }
    }
  }
  return img;
}

}  // namespace millsim::vision
