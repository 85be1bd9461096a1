#pragma once
// Binary front view of simulated balls (Doroszek et al. 2024, section 3.8.2, Figure 17 left):
// the sphere positions of a sampled time step are drawn as discs into an image of the same
// scale as the camera frames, so simulation and recording go through the same heat-map and
// angle-of-repose analysis (angle_of_repose.hpp).
#include <vector>

#include "millsim/vision/image.hpp"

namespace millsim::vision {

// Discs (centres cx, cy and radii in metres, y up) into a width_m x height_m window whose lower
// left corner is (x_min, y_min). The image is round(width_m * 1000 * ppmm) x
// round(height_m * 1000 * ppmm) pixels; the centre of pixel (col, row) is at
//   x = x_min + (col + 0.5) / ppmm / 1000,  y = y_min + height_m - (row + 0.5) / ppmm / 1000,
// and the pixel is 255 if that centre lies inside any disc (else 0). Each disc is rasterised
// over its bounding box only, so the cost is the covered area, not discs x image.
// For a 3-D charge pass the radius of the sphere's section with the viewing plane, or the full
// radius for a front (projected) view. Throws std::invalid_argument for mismatched sizes,
// a non-positive scale or window.
ImageU8 renderDiscs(const std::vector<double>& cx, const std::vector<double>& cy,
                    const std::vector<double>& radius, double x_min, double y_min,
                    double width_m, double height_m, double pixels_per_mm);

}  // namespace millsim::vision
