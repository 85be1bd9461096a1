#pragma once
// Small PNG plots for what a person would rather look at than read: x-y line plots with
// markers, axes, ticks, labels and a legend (validation curves, convergence), and particle
// snapshots of a 2D (or projected 3D) SPH run coloured by a value. Drawn with OpenCV, written
// with libpng (vision/png_io).
#include <array>
#include <cstddef>
#include <string>
#include <vector>

namespace millsim::io {

struct PlotSeries {
  std::string label;
  std::vector<double> x, y;
  std::array<int, 3> rgb{0, 0, 0};
  bool line = true;      // joined by a line
  bool markers = false;  // a circle at each point
};

// The k-th colour of the palette several runs in one plot cycle through (matplotlib's first six).
inline std::array<int, 3> seriesColour(std::size_t k) {
  static constexpr std::array<std::array<int, 3>, 6> palette{
      {{31, 119, 180}, {214, 39, 40}, {44, 160, 44}, {148, 103, 189}, {255, 127, 14}, {23, 190, 207}}};
  return palette[k % palette.size()];
}

struct PlotAxes {
  std::string title, x_label, y_label;
  double x_min = 0, x_max = 0, y_min = 0, y_max = 0;  // equal min/max: from the data
  int width = 900, height = 600;
};

// Throws std::runtime_error when the file cannot be written.
void writeLinePlot(const std::string& path, const PlotAxes& axes, const std::vector<PlotSeries>& series);

// Particles at (x, y) (m) drawn as discs of radius_m, coloured by value on a blue-red scale
// over [v_min, v_max]; particles with gray[i] true are drawn gray (walls). Window [x0, x1] x
// [y0, y1] at px_per_m, with a title and a colour bar.
// `curves` (optional): polylines in metres drawn on top, e.g. a fitted surface and its band.
struct PlotCurve {
  std::vector<double> x, y;
  std::array<int, 3> rgb{0, 0, 0};
  int thickness = 2;
};
void writeParticleSnapshot(const std::string& path, const std::vector<double>& x, const std::vector<double>& y,
                           const std::vector<double>& value, const std::vector<bool>& gray, double radius_m,
                           std::array<double, 4> window, double px_per_m, double v_min, double v_max,
                           const std::string& title, const std::string& value_label,
                           const std::vector<PlotCurve>& curves = {});

}  // namespace millsim::io
