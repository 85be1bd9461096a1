#pragma once
// The normalised front view of the mill (Doroszek et al. 2024, section 3.7, Figure 8: "centering
// frames, resizing to match actual dimensions, and applying a mask to obscure everything outside
// the mill"), and the same view for simulated frames: a square image of the drum's INNER circle
// at a fixed scale, gravity pointing straight down, the charge lifted on the left.
//
// View pixel (col, row) has its centre at mill coordinates (millimetres, origin on the drum axis,
// x to the right, y up)
//   x = -R + (col + 0.5) / ppmm,   y = R - (row + 0.5) / ppmm,   R = inner radius,
// which is exactly the window that render_discs.hpp draws simulated balls into (FrontViewAngle),
// so a video and a simulation give heat maps of the same size and scale.
//
// One affine warp does centring, scaling, the tilt correction and the optional mirror:
//   frame point = centre + s_frame * Rot(tilt) * (mirror ? -x : x, y)   (frame y axis flipped),
// with s_frame = outline radius in pixels / (diameter_mm / 2). The tilt is the camera's roll: a
// level line appears in the frame rising to the right by tilt_deg (counter-clockwise positive).
// It is given by the user: the drum is round and its lifters turn, so nothing in the picture
// shows where "down" is except the charge itself, which is what is being measured.
#include <array>

#include "millsim/vision/image.hpp"
#include "millsim/vision/mill_detection.hpp"

namespace millsim::vision {

struct ViewOptions {
  double pixels_per_mm = 2.0;  // scale of the view (the simulation's front view uses the same)
  double diameter_mm = 300.0;  // real diameter of the detected outline (paper: external diameter)
  double wall_mm = 4.0;        // outline to inner drum surface (paper: inner diameter 8 mm smaller)
  double tilt_deg = 0.0;       // camera roll, counter-clockwise positive (see above)
  bool mirror = false;         // flip left-right, for a drum filmed turning the other way
  double margin_mm = 6.0;      // ring inside the inner wall left out of the analysis mask: lifters
                               // (paper: 5 mm) and reflections on the rim
};

class MillView {
 public:
  // Throws std::invalid_argument when the options give no view (non-positive sizes, wall too thick).
  MillView(const MillCircle& circle, const ViewOptions& options);

  int size() const { return m_size; }                      // width = height in pixels
  double innerRadiusMm() const { return m_inner_radius; }  // R
  double frameScale() const { return m_frame_scale; }      // frame pixels per mm
  const ViewOptions& options() const { return m_options; }
  const MillCircle& circle() const { return m_circle; }

  // The view of a frame (bilinear; frames larger than the view are smoothed first so that
  // downscaling does not alias). Pixels outside the frame are black.
  ImageRgb apply(const ImageRgb& frame) const;
  // 255 inside the analysed disc (radius R - margin), 0 elsewhere.
  const ImageU8& mask() const { return m_mask; }

  // Affine map from view pixel coordinates to frame pixel coordinates, row-major 2 x 3:
  // (u, v) = A (col, row, 1), pixel centres at integer coordinates in both images.
  const std::array<double, 6>& viewToFrame() const { return m_view_to_frame; }
  // Frame pixel -> mill millimetres (x right, y up), and back.
  void frameToMm(double u, double v, double& x_mm, double& y_mm) const;
  void mmToFrame(double x_mm, double y_mm, double& u, double& v) const;

 private:
  MillCircle m_circle;
  ViewOptions m_options;
  double m_inner_radius = 0.0;
  double m_frame_scale = 0.0;
  int m_size = 0;
  std::array<double, 6> m_view_to_frame{};
  ImageU8 m_mask;
};

// Mill millimetres <-> view pixel coordinates (pixel centres at integers) for a view of
// inner radius R and scale ppmm; the convention above.
inline double viewColToMm(double col, double R, double ppmm) { return -R + (col + 0.5) / ppmm; }
inline double viewRowToMm(double row, double R, double ppmm) { return R - (row + 0.5) / ppmm; }
inline double mmToViewCol(double x_mm, double R, double ppmm) { return (x_mm + R) * ppmm - 0.5; }
inline double mmToViewRow(double y_mm, double R, double ppmm) { return (R - y_mm) * ppmm - 0.5; }

}  // namespace millsim::vision
