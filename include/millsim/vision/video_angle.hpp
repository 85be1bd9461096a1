#pragma once
// Dynamic angle of repose from a recording (Doroszek et al. 2024, sections 3.7, 3.7.1, 3.7.2):
//   N evenly spaced frames (frame_source.hpp) -> mill outline on their mean (mill_detection.hpp)
//   -> each frame centred, scaled to pixels_per_mm, tilt-corrected, masked (mill_view.hpp)
//   -> charge mask per frame (charge_segmentation.hpp)
//   -> heat map, threshold, smoothing, top edge, regression from 60 mm right of the highest
//      point (heatmap.hpp, angle_of_repose.hpp: the SAME code `millsim run` applies to the
//      discs of its simulated balls, front_view_angle.hpp).
#include <vector>

#include "millsim/vision/angle_of_repose.hpp"
#include "millsim/vision/charge_segmentation.hpp"
#include "millsim/vision/frame_source.hpp"
#include "millsim/vision/mill_detection.hpp"
#include "millsim/vision/mill_view.hpp"

namespace millsim::vision {

struct VideoAngleOptions {
  MillDetectionOptions detection;
  ViewOptions view;                  // view.pixels_per_mm also sets angle.pixels_per_mm
  SegmentationOptions segmentation;  // segmentation.mode: balls or dry
  AngleOptions angle;                // threshold 0.5, smoothing 5 px, fit from 60 mm (paper)
};

struct VideoAngleResult {
  AngleResult angle;
  MillCircle circle;  // detected outline in frame pixels
  int frames = 0;     // frames in the heat map
  ImageF heat;        // view-sized heat map (fraction of frames covered)
  ImageRgb overlay;   // drawAngleOverlay on the middle sampled frame, in its own pixels
  ImageRgb view;      // the middle frame's normalised view
  ImageU8 mask;       // its charge mask
};

// The mill located on the mean of the frames, and the view built from it.
MillView locateMill(const FrameSequence& seq, const MillDetectionOptions& detection, const ViewOptions& view);

// Throws core::InputError for "no mill outline", std::runtime_error when no surface can be
// measured (the message of angleFromHeatmap), std::invalid_argument for bad options.
VideoAngleResult measureVideoAngle(const FrameSequence& seq, const VideoAngleOptions& options);

}  // namespace millsim::vision
