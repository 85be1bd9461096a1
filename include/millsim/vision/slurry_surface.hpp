#pragma once
// Free-surface points of the slurry in one normalised view (mill_view.hpp). The paper picked
// them by hand in a GUI (Doroszek et al. 2024, section 3.7.3, Figure 14); this is the automatic
// route, a classical colour model:
//   the slurry's colour is the median chromaticity (r, g) = (R, G) / (R + G + B) of a disc of
//   seed_radius_mm at (0, -seed_depth * R) (the bottom of the drum is under slurry in wet
//   milling); each pixel's distance to it in chromaticity is thresholded (Otsu over the drum,
//   or colour_threshold > 0); closing and opening (close_mm, open_mm) and the connected
//   component holding the seed give the slurry region, holes filled (submerged balls);
//   in every column point_spacing_mm apart, the top of that region is the surface, refined
//   to a fraction of a pixel where the colour profile is half way between the mean colours
//   4-10 pixels above and below (colours mix linearly across a blurred edge, so that is where
//   the pixel is half slurry; the chromaticity threshold itself would sit on the darker side).
// Chromaticity is unchanged by the brightness of the light, so a lighting gradient does not move
// the surface. A slurry of the same hue as the empty drum is invisible to it: use picked points
// (slurry_curve.hpp, readSurfacePointsCsv) for such footage, as the paper did.
// Columns where the region reaches the analysed circle's rim (the surface meets the wall) are
// left out.
#include <vector>

#include "millsim/vision/image.hpp"

namespace millsim::vision {

struct SurfacePoint {
  double x_mm = 0.0;  // mill coordinates: origin on the drum axis, x right, y up
  double y_mm = 0.0;
  int frame = 0;  // which frame it came from (-1: picked by hand, independent)
};

struct SlurryOptions {
  double seed_depth = 0.75;       // seed at y = -seed_depth * R below the axis
  double seed_radius_mm = 8.0;    // radius of the disc the slurry colour is taken from
  double denoise_sigma_px = 1.5;  // Gaussian pre-smoothing of the colour image; 0: none
  double colour_threshold = 0.0;  // chromaticity distance threshold; 0: Otsu over the drum
  double point_spacing_mm = 4.0;  // columns sampled for surface points
  double close_mm = 3.0;          // closing radius of the slurry region; 0: none
  double open_mm = 3.0;           // opening radius (splashes, droplets on the window); 0: none
  double outlier_sigmas = 3.5;    // curve fit: points further than this many robust sd are dropped
  double confidence = 0.95;       // of the curve's band
};

// Points of one view (`mask` 255 = analysed disc, R = inner radius in mm). `frame` labels them.
std::vector<SurfacePoint> slurrySurfacePoints(const ImageRgb& view, const ImageU8& mask, double inner_radius_mm,
                                              double pixels_per_mm, const SlurryOptions& options, int frame);

}  // namespace millsim::vision
