#pragma once
// Dynamic angle of repose of a ball charge seen from the front of a rotating drum, after
// Doroszek et al. 2024, section 3.7.1 (steps 2-4, Figures 10-12) and section 3.8.2 (the same
// flow applied to simulated ball positions, Figure 17):
//   binary charge masks of N frames -> heat map (fraction of frames covered) -> threshold ->
//   smoothing -> top edge (highest white pixel of each image column) -> highest edge point ->
//   least squares on the edge points from 60 mm right of the highest point -> angle.
// The drum turns so the charge is lifted on the LEFT: the free surface falls from upper left to
// lower right, and that angle is reported as positive, angle = atan(-slope), slope = dy/dx with
// y pointing up (image rows point down and are converted).
#include <vector>

#include "millsim/vision/image.hpp"

namespace millsim::vision {

struct AngleOptions {
  double pixels_per_mm = 2.0;  // image scale (the frames are resized to real dimensions first)
  double threshold = 0.5;      // heat-map pixel is charge if covered in MORE than this fraction
  int smoothing_px = 5;        // half-width of the box filter (window 2*s+1 pixels); 0: none
  double fit_offset_mm = 60.0;  // fit starts this far right of the highest point (paper: 60 mm)
  double fit_length_mm = 0.0;   // fit window length; <= 0: up to the last column with an edge
  int min_points = 5;           // fewer edge points in the window is an error (at least 3 used)
};

struct AngleResult {
  double angle_deg = 0.0;   // positive for a surface falling to the right
  double stderr_deg = 0.0;  // standard error of the slope, propagated through atan
  int points_used = 0;
  double slope = 0.0;      // y_up_mm = slope * x_mm + intercept, with
  double intercept = 0.0;  // x_mm = column / ppmm, y_up_mm = (height - 1 - row) / ppmm
  double highest_x_mm = 0.0;
  double highest_y_mm = 0.0;
  std::vector<double> fit_x_mm, fit_y_mm;  // the edge points the line was fitted to
  ImageU8 processed;                       // thresholded + smoothed map, 0 or 255
};

// Ordinary least squares y = slope * x + intercept with the textbook standard error of the
// slope, sqrt(SSR / (n - 2) / Sxx). Throws std::invalid_argument for mismatched sizes, fewer
// than 3 points or all x equal.
struct LineFit {
  double slope = 0.0;
  double intercept = 0.0;
  double slope_stderr = 0.0;
};
LineFit fitLine(const std::vector<double>& x, const std::vector<double>& y);

// The pipeline on a heat map (values 0..1). Smoothing: a box filter of half-width
// smoothing_px is applied to the thresholded (0/1) map and the result re-thresholded at 0.5,
// i.e. a majority filter: it removes isolated specks and fills pinholes between balls while a
// straight surface stays where it is (a symmetric window on a half-plane is half covered).
// Near the image border the window is clipped to the image, so the border does not erode the
// charge. If several columns share the highest edge row the leftmost is taken (the lifted side).
// Throws std::invalid_argument for bad options or an empty map, and std::runtime_error
// ("angle of repose: only N surface points in the fit window ...") when fewer than
// max(min_points, 3) edge points lie in the fit window.
AngleResult angleFromHeatmap(const ImageF& heat, const AngleOptions& opt);

// Heat map of `masks` (nonzero = charge; all the same size) followed by angleFromHeatmap.
AngleResult angleFromMasks(const std::vector<ImageU8>& masks, const AngleOptions& opt);

// The picture of a result (renderAngleOverlay, drawAngleOverlay) is in angle_overlay.hpp.

}  // namespace millsim::vision
