// Angle of repose of a recording: frames -> view -> masks -> the shared heat-map pipeline.
#include "millsim/vision/video_angle.hpp"

#include <cstdio>
#include <stdexcept>

#include "millsim/vision/angle_overlay.hpp"
#include "millsim/vision/heatmap.hpp"

namespace millsim::vision {

MillView locateMill(const FrameSequence& seq, const MillDetectionOptions& detection, const ViewOptions& view) {
  if (seq.frames.empty()) throw std::invalid_argument("vision: no frames");
  return MillView(detectMill(meanFrame(seq.frames), detection), view);
}

VideoAngleResult measureVideoAngle(const FrameSequence& seq, const VideoAngleOptions& options) {
  const MillView view = locateMill(seq, options.detection, options.view);
  AngleOptions angle_opt = options.angle;
  angle_opt.pixels_per_mm = options.view.pixels_per_mm;
  const double ppmm = angle_opt.pixels_per_mm;

  VideoAngleResult out;
  out.circle = view.circle();
  HeatmapAccumulator acc;
  const std::size_t middle = seq.frames.size() / 2;
  for (std::size_t k = 0; k < seq.frames.size(); ++k) {
    const ImageRgb v = view.apply(seq.frames[k]);
    ImageU8 m = segmentCharge(v, view.mask(), ppmm, options.segmentation);
    acc.add(m);
    if (k == middle) {
      out.view = v;
      out.mask = std::move(m);
    }
  }
  out.frames = acc.frames();
  out.heat = acc.heatmap();
  out.angle = angleFromHeatmap(out.heat, angle_opt);

  OverlayLayout layout;
  layout.view_to_image = view.viewToFrame();
  const double r_in = view.innerRadiusMm() * ppmm;
  layout.circle_radii_px = {r_in + options.view.wall_mm * ppmm, r_in - options.view.margin_mm * ppmm};
  char caption[96];
  std::snprintf(caption, sizeof caption, "%d frames, %s, tilt %.1f deg", out.frames,
                options.segmentation.mode == ChargeMode::Balls ? "balls" : "dry", options.view.tilt_deg);
  layout.caption = caption;
  out.overlay = drawAngleOverlay(seq.frames[middle], out.angle, ppmm, layout);
  return out;
}

}  // namespace millsim::vision
