#pragma once
// The picture that shows an angle-of-repose measurement (Doroszek et al. 2024, Figure 12:
// "visualization of detected line over one of the frames"), drawn the same way for a video and
// for a simulation: on a background image (a video frame, or the heat map in colour) the drum
// circles (cyan), the outline of the thresholded heat map (yellow), the edge points the line was
// fitted to (orange), the fitted line (white, 3 px), the highest point (green cross) and
// "41.7 +/- 0.2 deg" with OpenCV's Hershey font at the top left.
// The measurement lives in view coordinates (angle_of_repose.hpp: x = col / ppmm, y up); an
// affine map view pixel -> background pixel places it on any picture, e.g. the original frame
// through MillView::viewToFrame(), or the identity for the view itself.
#include <array>
#include <string>
#include <vector>

#include "millsim/vision/angle_of_repose.hpp"
#include "millsim/vision/image.hpp"

namespace millsim::vision {

struct OverlayLayout {
  std::array<double, 6> view_to_image{1, 0, 0, 0, 1, 0};  // (u, v) = A (col, row, 1)
  std::vector<double> circle_radii_px;                    // circles about the view centre, radii in view pixels
  std::string caption;                                    // second text line (e.g. "100 frames, balls"); empty: none
};

// Heat map (0..1) in a blue -> red colour map, uncovered pixels black.
ImageRgb heatmapColour(const ImageF& heat);

// The overlay on a copy of `background`. `r.processed` must be the view-sized processed map.
ImageRgb drawAngleOverlay(const ImageRgb& background, const AngleResult& r, double ppmm, const OverlayLayout& layout);

// The overlay on the heat map itself (the simulation's angle_overlay.png): heatmapColour(heat)
// as background, the drum's inner circle, identity placement.
ImageRgb renderAngleOverlay(const ImageF& heat, const AngleResult& r, double ppmm);

}  // namespace millsim::vision
