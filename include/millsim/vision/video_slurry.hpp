#pragma once
// Slurry free-surface curve from a recording (Doroszek et al. 2024, section 3.7.3):
//   N evenly spaced frames -> mill outline -> normalised views (as video_angle.hpp) ->
//   surface points of every view (slurry_surface.hpp), or points picked by hand ->
//   robust quadratic fit with its 95 % band (slurry_curve.hpp) -> overlay picture.
#include <string>
#include <vector>

#include "millsim/vision/frame_source.hpp"
#include "millsim/vision/mill_detection.hpp"
#include "millsim/vision/mill_view.hpp"
#include "millsim/vision/slurry_curve.hpp"

namespace millsim::vision {

struct VideoSlurryOptions {
  MillDetectionOptions detection;
  ViewOptions view;
  SlurryOptions slurry;
};

struct SlurryMeasurement {
  SlurryCurve curve;
  MillCircle circle;
  int frames = 0;    // frames that gave points
  ImageRgb overlay;  // on the middle frame (or a blank view for points alone)
};

// Automatic points from the frames. Throws as locateMill and fitSlurryCurve do.
SlurryMeasurement measureVideoSlurry(const FrameSequence& seq, const VideoSlurryOptions& options);

// The overlay of a curve: points used (orange), outliers (grey), the fitted curve (white), the
// pointwise band (light blue), the simultaneous band (thin, darker blue), the drum circles
// (cyan) and the equation. `mm_to_image` is the affine map
// from mill millimetres (x right, y up) to image pixels, row-major 2 x 3.
ImageRgb drawSlurryOverlay(const ImageRgb& background, const SlurryCurve& curve,
                           const std::array<double, 6>& mm_to_image, const std::vector<double>& circle_radii_mm);

// mm -> frame pixels of a view, and mm -> pixels of a blank square view of radius R at ppmm.
std::array<double, 6> millToFrameAffine(const MillView& view);
std::array<double, 6> millToViewAffine(double inner_radius_mm, double pixels_per_mm);

}  // namespace millsim::vision
