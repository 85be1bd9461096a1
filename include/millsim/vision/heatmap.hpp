#pragma once
// Heat map of the ball charge (Doroszek et al. 2024, section 3.7.1 step 2 and section 3.8.2):
// the binary charge masks of N frames are accumulated and each pixel gets the fraction of frames
// in which it is covered. Thresholding that map keeps the most frequent position of the charge
// and drops balls that a lifter throws into the air in a minority of frames.
#include <cstdint>
#include <vector>

#include "millsim/vision/image.hpp"

namespace millsim::vision {

class HeatmapAccumulator {
 public:
  // Counts the nonzero pixels of `mask` as covered by the charge. The first mask fixes the image
  // size; a later mask of another size throws std::invalid_argument.
  void add(const ImageU8& mask);

  int frames() const { return m_frames; }

  // Fraction (0..1) of the added frames in which each pixel was covered. Before any add(): an
  // empty (0 x 0) image, since no size is known yet.
  ImageF heatmap() const;

  // Raw per-pixel counts, and the inverse: what a checkpoint stores so a restarted run keeps the
  // frames it already took.
  int width() const { return m_width; }
  int height() const { return m_height; }
  const std::vector<std::uint32_t>& counts() const { return m_counts; }
  void restore(int width, int height, int frames, std::vector<std::uint32_t> counts);

 private:
  int m_width = 0;
  int m_height = 0;
  int m_frames = 0;
  std::vector<std::uint32_t> m_counts;
};

}  // namespace millsim::vision
