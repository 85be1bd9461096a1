#pragma once
// Synthetic recordings of a lab mill's front window with a KNOWN answer, to test the vision
// pipeline (src/vision) the way real footage would stress it (issue 7):
// - a drum: rim ring (the outline the detection finds), dark back plate with bolt heads and
//   lifters that turn with the drum;
// - a charge with a known surface: a ball bed (two layers of shaded steel discs with specular
//   highlights, dark gaps) or a dry ore bed (granular texture, rough surface, some balls)
//   under a straight surface falling to the right at surface_angle_deg; or slurry under a known
//   quadratic y = c0 + c1 x + c2 x^2 (mm, origin on the drum axis, y up) that each frame
//   perturbs by a random level, slope and two waves of random phase (zero mean: the curve is
//   the mean surface a long recording converges to), balls carried up the left side above
//   the pool and droplets on the window;
// - nuisance: camera roll (tilt_deg), mill off the frame centre, lighting gradient and
//   vignetting, fixed glare on the window, linear motion blur, Gaussian sensor noise, JPEG
//   round trip, and the lossy codec of the video container the caller picks.
// Each frame is rendered at 2x and averaged down (anti-aliased edges), deterministic in (seed,
// frame index). Ball placement is random sequential addition, drawn anew in every frame: 100
// frames of a real mill are seconds apart, so their ball arrangements are unrelated.
#include <array>
#include <opencv2/core.hpp>
#include <string>

namespace millsim::synth {

enum class Content { Balls, Dry, Slurry };

struct MillScene {
  Content content = Content::Balls;
  int width = 520;  // frame size, pixels
  int height = 480;
  double px_per_mm = 1.45;    // camera scale
  double centre_dx_px = 9.0;  // mill centre relative to the frame centre
  double centre_dy_px = -6.0;
  double diameter_mm = 300.0;  // outer rim (the outline)
  double wall_mm = 4.0;        // rim width: inner radius = diameter/2 - wall
  double tilt_deg = 0.0;       // camera roll, counter-clockwise on screen
  // Charge.
  double surface_angle_deg = 40.0;   // balls/dry: surface falls to the right at this angle
  double surface_offset_mm = -58.0;  // signed distance of the surface from the axis along its upward normal
  std::array<double, 3> slurry{-30.0, -0.16, 0.0009};  // slurry: mean surface coefficients
  double wave_amplitude_mm = 2.0;                      // slurry: first wave (a second one of half the amplitude)
  double wave_length_mm = 110.0;
  double level_jitter_mm = 1.5;  // slurry: sd of the frame's level about the mean surface
  double slope_jitter = 0.008;   // slurry: sd of the frame's extra slope
  double ball_d_min_mm = 15.0;   // ball diameters, uniform (paper, 300 mm drum: 15-35 mm)
  double ball_d_max_mm = 35.0;
  int lifters = 8;  // paper: eight 5 mm lifters
  double lifter_height_mm = 5.0;
  double lifter_width_mm = 10.0;
  double drum_step_deg = 11.3;  // drum turn between frames
  // Nuisance.
  double noise_sigma = 5.0;     // gray levels
  double motion_blur_px = 5.0;  // length of the blur kernel; 0: none
  double motion_blur_dir_deg = 20.0;
  double light_gradient = 0.35;  // brightness changes by this fraction across the frame
  double light_dir_deg = -30.0;
  double vignetting = 0.25;  // brightness loss at the frame corners
  bool glare = true;
  int jpeg_quality = 0;  // JPEG round trip of every frame; 0: none
  unsigned seed = 1;
};

// Frame `index` (BGR, 8 bit, width x height).
cv::Mat renderFrame(const MillScene& scene, int index);

// Inner drum radius, mm.
double innerRadiusMm(const MillScene& scene);
// The slurry's mean surface at x (mm).
double trueSlurryY(const MillScene& scene, double x_mm);
// Where the mean slurry surface meets the inner drum wall (x_left < x_right), by bisection.
std::array<double, 2> slurrySpanMm(const MillScene& scene);
// Mill centre and outline radius in frame pixels.
std::array<double, 3> trueCircle(const MillScene& scene);

// `frames` frames as a video; fourcc e.g. "mp4v" (.mp4) or "MJPG" (.avi). Throws
// std::runtime_error if OpenCV cannot write it.
void writeVideo(const MillScene& scene, int frames, const std::string& path, const std::string& fourcc,
                double fps = 30.0);
// `frames` frames as dir/frame_0001.<ext> ... (ext "png" or "jpg").
void writeImages(const MillScene& scene, int frames, const std::string& dir, const std::string& ext);

}  // namespace millsim::synth
