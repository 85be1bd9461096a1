#pragma once
// Dynamic angle of repose from particle positions seen from the front of a drum (paper section
// 3.8.2): each frame is rendered as a binary image of the balls' discs (drum axis = z, the frame
// covers [-R, R] x [-R, R]), frames are summed into a heat map, and the angle is measured by the
// same image pipeline as a video (angle_of_repose.hpp). Used by `millsim run` on its own frames
// and by `millsim angle-from-dumps` on another code's particle dumps, so both go through one path.
#include <filesystem>
#include <vector>

#include "millsim/vision/angle_of_repose.hpp"
#include "millsim/vision/heatmap.hpp"

namespace millsim::vision {

class FrontViewAngle {
 public:
  FrontViewAngle(double drum_diameter_m, const AngleOptions& options);

  void addFrame(const std::vector<double>& x, const std::vector<double>& y, const std::vector<double>& radius);
  int frames() const { return m_heat.frames(); }
  const HeatmapAccumulator& accumulator() const { return m_heat; }
  HeatmapAccumulator& accumulator() { return m_heat; }

  // Throws std::runtime_error when the surface cannot be measured (too few frames or points).
  AngleResult measure() const;
  // heatmap.png always; angle_overlay.png and angle_edge.csv when `result` is given.
  void writeImages(const std::filesystem::path& dir, const AngleResult* result) const;

 private:
  double m_radius;
  AngleOptions m_options;
  HeatmapAccumulator m_heat;
};

}  // namespace millsim::vision
