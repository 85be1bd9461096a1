#pragma once
// Conversions between millsim::vision images and cv::Mat. Internal to libmillsim: OpenCV is a
// private dependency, so no public header names a cv type; each step converts at its boundary
// (a 600 x 600 frame costs about a megabyte of copying, nothing next to decoding it).
// Colour order: public ImageRgb is R, G, B; OpenCV works in B, G, R.
#include <cstring>
#include <opencv2/core.hpp>
#include <opencv2/imgproc.hpp>
#include <stdexcept>
#include <string>

#include "millsim/vision/image.hpp"
#include "millsim/vision/png_io.hpp"

namespace millsim::vision::detail {

static_assert(sizeof(Rgb) == 3, "Rgb must be three packed bytes to alias an 8UC3 buffer");

inline cv::Mat toMat(const ImageU8& img) {
  cv::Mat m(img.height, img.width, CV_8UC1);
  if (!img.pixels.empty()) std::memcpy(m.data, img.pixels.data(), img.pixels.size());
  return m;
}

inline cv::Mat toMat(const ImageF& img) {
  cv::Mat m(img.height, img.width, CV_32FC1);
  if (!img.pixels.empty()) std::memcpy(m.data, img.pixels.data(), img.pixels.size() * sizeof(float));
  return m;
}

// RGB image -> BGR 8UC3 Mat.
inline cv::Mat toBgr(const ImageRgb& img) {
  cv::Mat rgb(img.height, img.width, CV_8UC3);
  if (!img.pixels.empty()) std::memcpy(rgb.data, img.pixels.data(), img.pixels.size() * 3);
  cv::Mat bgr;
  cv::cvtColor(rgb, bgr, cv::COLOR_RGB2BGR);
  return bgr;
}

inline ImageU8 toImageU8(const cv::Mat& m) {
  if (m.type() != CV_8UC1) throw std::invalid_argument("toImageU8: expected an 8-bit one-channel image");
  cv::Mat c = m.isContinuous() ? m : m.clone();
  ImageU8 img(c.cols, c.rows);
  if (!img.pixels.empty()) std::memcpy(img.pixels.data(), c.data, img.pixels.size());
  return img;
}

inline ImageF toImageF(const cv::Mat& m) {
  cv::Mat f;
  m.convertTo(f, CV_32F);
  ImageF img(f.cols, f.rows);
  if (!img.pixels.empty()) std::memcpy(img.pixels.data(), f.data, img.pixels.size() * sizeof(float));
  return img;
}

// BGR (or gray, expanded) Mat -> RGB image.
inline ImageRgb toImageRgb(const cv::Mat& m) {
  cv::Mat rgb;
  if (m.channels() == 1) {
    cv::cvtColor(m, rgb, cv::COLOR_GRAY2RGB);
  } else if (m.channels() == 4) {
    cv::cvtColor(m, rgb, cv::COLOR_BGRA2RGB);
  } else {
    cv::cvtColor(m, rgb, cv::COLOR_BGR2RGB);
  }
  if (rgb.depth() != CV_8U) rgb.convertTo(rgb, CV_8U);
  ImageRgb img(rgb.cols, rgb.rows);
  if (!img.pixels.empty()) std::memcpy(img.pixels.data(), rgb.data, img.pixels.size() * 3);
  return img;
}

// A drawn BGR (or gray) Mat as PNG, through libpng (png_io.cpp) rather than cv::imwrite: only the
// video input needs OpenCV's codecs, so the engines' binaries (GPU tests and benchmarks, which
// write plots) do not pull in imgcodecs and its image-format libraries (~120 MiB with GDAL).
inline void writePngBgr(const std::string& path, const cv::Mat& m) { writePng(path, toImageRgb(m)); }

}  // namespace millsim::vision::detail
