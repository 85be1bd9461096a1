// The PNG plots (io::writeLinePlot): drawn with OpenCV, written through libpng (not OpenCV's
// codecs, which the engines' binaries do not link). The file must read back at the asked size
// with each series in its own colour: a red line must come out brighter than a blue one (any
// luma weighs red above blue: Rec. 709 0.2126 vs 0.0722), which a swapped channel order fails.
#include <gtest/gtest.h>

#include <algorithm>
#include <filesystem>
#include <stdexcept>
#include <string>

#include "millsim/io/plot_png.hpp"
#include "millsim/vision/png_io.hpp"

namespace millsim {
namespace {

TEST(PlotPng, LinePlotReadsBackWithItsSizeAndColours) {
  const std::string path = (std::filesystem::temp_directory_path() / "millsim_test_plot.png").string();
  io::PlotAxes axes;
  axes.title = "two lines";
  axes.x_min = 0, axes.x_max = 1, axes.y_min = 0, axes.y_max = 1;
  axes.width = 640, axes.height = 480;
  io::PlotSeries red{"red", {0.0, 1.0}, {0.25, 0.25}, {255, 0, 0}};
  io::PlotSeries blue{"blue", {0.0, 1.0}, {0.75, 0.75}, {0, 0, 255}};
  io::writeLinePlot(path, axes, {red, blue});

  const vision::ImageU8 img = vision::readPngGray(path);
  ASSERT_EQ(img.width, 640);
  ASSERT_EQ(img.height, 480);
  // Plot rows of the two horizontal lines: y = 0.25 is nearer the bottom, y = 0.75 the top.
  // Darkest pixel of each row band in the middle third of the width (the lines, not the grid).
  auto darkest = [&](int y_lo, int y_hi) {
    int v = 255;
    for (int y = y_lo; y < y_hi; ++y)
      for (int x = img.width / 3; x < 2 * img.width / 3; ++x) v = std::min(v, int(img.pixels[y * img.width + x]));
    return v;
  };
  const int lower = darkest(img.height / 2, img.height - 80), upper = darkest(60, img.height / 2);
  EXPECT_LT(upper, 120) << "the blue line is missing";
  EXPECT_LT(lower, 200) << "the red line is missing";
  EXPECT_GT(lower, upper + 10) << "red must be brighter than blue in gray (channel order)";
  std::filesystem::remove(path);
}

TEST(PlotPng, UnwritablePathThrows) {
  io::PlotAxes axes;
  EXPECT_THROW(io::writeLinePlot("/nonexistent_dir_millsim/plot.png", axes, {{"a", {0, 1}, {0, 1}}}),
               std::runtime_error);
}

}  // namespace
}  // namespace millsim
