#pragma once
// The slurry surface as a quadratic curve with its 95 % confidence band (Doroszek et al. 2024,
// section 3.7.3 steps 2-4 and section 3.8.2; Figures 19, 22, 23): points (automatic,
// slurry_surface.hpp, or picked by hand and read from a CSV) -> robust quadratic fit
// (quadratic_fit.hpp; points further than outlier_sigmas robust standard deviations from the
// curve, 1.4826 MAD of the residuals, are dropped and the fit repeated until none is) ->
// the curve and band as CSV. Points of one frame are grouped for the band (see
// quadratic_fit.hpp); hand-picked points (frame -1) are independent.
#include <string>
#include <vector>

#include "millsim/vision/quadratic_fit.hpp"
#include "millsim/vision/slurry_surface.hpp"

namespace millsim::vision {

class MillView;

struct SlurryCurve {
  QuadraticFit fit;
  std::vector<SurfacePoint> used;      // points of the final fit
  std::vector<SurfacePoint> rejected;  // outliers
  double x_min_mm = 0.0;               // span of the used points
  double x_max_mm = 0.0;
};

// Throws std::runtime_error ("slurry curve: only N surface points ...") with fewer than 8 points.
SlurryCurve fitSlurryCurve(const std::vector<SurfacePoint>& points, double outlier_sigmas, double confidence);

// Picked points. Header "x_mm,y_mm" (mill coordinates: origin on the drum axis, y up) or
// "x_px,y_px" (pixels of the original frame; needs `view` to convert, which corrects the tilt
// and mirror too); an optional third column "frame" groups points by frame. Lines starting
// with '#' are skipped. Throws core::InputError ("file:line: ...") for a missing file, an
// unknown header, a malformed number, or pixel points without a view.
std::vector<SurfacePoint> readSurfacePointsCsv(const std::string& path, const MillView* view);

// x_mm,y_fit_mm,y_low_mm,y_high_mm (pointwise band), y_low_simultaneous_mm,
// y_high_simultaneous_mm (simultaneous band) every step_mm over [x_min, x_max]. Throws core::InputError
// if the file cannot be written.
void writeSlurryCurveCsv(const std::string& path, const SlurryCurve& curve, double step_mm = 1.0);
// x_mm,y_mm,frame,used of every point.
void writeSurfacePointsCsv(const std::string& path, const SlurryCurve& curve);

}  // namespace millsim::vision
