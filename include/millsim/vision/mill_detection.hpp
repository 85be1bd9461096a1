#pragma once
// Finding the mill in a frame (Doroszek et al. 2024, section 3.7, Figure 7: "mill outline
// detection via the Hough Circle Transform"). Two stages:
// 1. Hough circle transform (OpenCV HOUGH_GRADIENT) on a blurred, at most 640 px wide copy, with
//    the radius searched in a range from the expected radius or, without one, from the frame size.
// 2. Refinement at full resolution: along 360 rays from the Hough centre the radial intensity
//    derivative is sampled within +-band of the Hough radius; on each ray the OUTERMOST peak of
//    at least half the ray's strongest is the outline (a drum rim has an inner and an outer edge;
//    taking the outer one on every ray keeps the radius from jumping between them). A circle is
//    fitted to those points by algebraic least squares (Kasa), points further than 3 robust
//    standard deviations (1.4826 MAD, at least 0.5 px) are dropped and the fit repeated.
//    This gives the centre and radius to a fraction of a pixel; the Hough stage alone is good to
//    about a pixel at the working resolution, which would shift a slurry curve by ~0.5 mm.
// The outline is the outer edge of the drum as seen by the camera; its real diameter is the
// user's `diameter_mm` (the paper's 300/400/500 mm external diameters).
#include "millsim/vision/image.hpp"

namespace millsim::vision {

struct MillDetectionOptions {
  // Expected outline radius in frame pixels; > 0 narrows the Hough search to
  // [1 - radius_tolerance, 1 + radius_tolerance] times it. 0: automatic.
  double expected_radius_px = 0.0;
  double radius_tolerance = 0.15;
  // Automatic search range, as fractions of half the shorter frame side.
  double min_radius_fraction = 0.45;
  double max_radius_fraction = 1.05;
  double canny_high = 100.0;  // upper Canny threshold of the Hough stage (lower = half of it)
  int min_votes = 20;         // smallest accumulator count accepted (tried from 120 down to this)
  double refine_band = 0.08;  // refinement searches radius * (1 -+ band) around the Hough circle
  bool refine = true;         // false: the Hough circle as it is
};

struct MillCircle {
  double cx_px = 0.0;  // centre, frame pixel coordinates (column, row; pixel centres at integers)
  double cy_px = 0.0;
  double radius_px = 0.0;
  bool refined = false;      // the least-squares stage succeeded
  int edge_points = 0;       // rays that contributed to the final fit
  double residual_px = 0.0;  // rms distance of those points from the circle
};

// Throws core::InputError ("no mill outline found ...") when no circle of the searched radius
// range is in the frame, std::invalid_argument for an empty frame or bad options.
MillCircle detectMill(const ImageRgb& frame, const MillDetectionOptions& options);

// Pixel-wise mean of frames of equal size: the drum outline is still while the charge and the
// lifters move, so the mean of a few sampled frames is a clean picture for the detection.
ImageRgb meanFrame(const std::vector<ImageRgb>& frames, int max_frames = 16);

}  // namespace millsim::vision
