#pragma once
// OUT/sse_map.png, the calibration's picture in the manner of the paper's Figure 20: the
// surrogate SSE over the (e, mu) box as a heat map (green low to red high, square-root scale),
// contour lines at levels evenly spaced on that scale, every evaluated candidate marked (initial ones as squares, later ones as
// circles, failed ones as crosses) and the best one as a star, axis ticks and labels, and a
// colour bar with its SSE scale. Drawn with OpenCV.
#include <string>
#include <vector>

#include "millsim/calib/objective.hpp"
#include "millsim/calib/param_box.hpp"

namespace millsim::calib {

struct SseMapOptions {
  int size_px = 420;  // plot area, square
  int levels = 10;    // contour levels
  std::string title = "SSE of the angles of repose [deg^2]";
};

// `surface` holds the surrogate on an n x n grid over the unit square, row-major with e along
// the row (index = j * n + i: u = i / (n - 1), v = j / (n - 1)). Throws std::runtime_error when
// the file cannot be written.
void writeSseMap(const std::string& path, const ParamBox& box, const std::vector<double>& surface, int n,
                 const std::vector<Evaluation>& evaluations, int initial, int best, const SseMapOptions& options = {});

}  // namespace millsim::calib
