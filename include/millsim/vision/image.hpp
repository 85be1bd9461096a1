#pragma once
// Minimal row-major image used by the angle-of-repose pipeline and the frame renderer.
// (The video pipeline of the vision issue adds OpenCV; this type converts to cv::Mat cheaply.)
#include <cstdint>
#include <vector>

namespace millsim::vision {

template <class T>
struct Image {
  int width = 0;
  int height = 0;
  std::vector<T> pixels;  // row 0 is the top of the picture

  Image() = default;
  Image(int w, int h, T fill = T{}) : width(w), height(h), pixels(static_cast<std::size_t>(w) * h, fill) {}
  T& at(int x, int y) { return pixels[static_cast<std::size_t>(y) * width + x]; }
  const T& at(int x, int y) const { return pixels[static_cast<std::size_t>(y) * width + x]; }
  bool inside(int x, int y) const { return x >= 0 && y >= 0 && x < width && y < height; }
};

using ImageU8 = Image<std::uint8_t>;
using ImageF = Image<float>;

struct Rgb {
  std::uint8_t r, g, b;
};
using ImageRgb = Image<Rgb>;

}  // namespace millsim::vision
