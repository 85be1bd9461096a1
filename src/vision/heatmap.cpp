#include "millsim/vision/heatmap.hpp"

#include <stdexcept>
#include <string>

namespace millsim::vision {

void HeatmapAccumulator::add(const ImageU8& mask) {
  if (m_frames == 0) {
    m_width = mask.width;
    m_height = mask.height;
    m_counts.assign(mask.pixels.size(), 0);
  } else if (mask.width != m_width || mask.height != m_height) {
    throw std::invalid_argument("heat map: mask " + std::to_string(m_frames) + " is " +
                                std::to_string(mask.width) + "x" + std::to_string(mask.height) +
                                " but the first mask is " + std::to_string(m_width) + "x" +
                                std::to_string(m_height));
  }
  if (mask.pixels.size() != m_counts.size()) {
    throw std::invalid_argument("heat map: mask pixel buffer does not match its width x height");
  }
  for (std::size_t i = 0; i < m_counts.size(); ++i) {
    if (mask.pixels[i] != 0) ++m_counts[i];
  }
  ++m_frames;
}

ImageF HeatmapAccumulator::heatmap() const {
  if (m_frames == 0) return ImageF{};
  ImageF heat(m_width, m_height, 0.0f);
  const double inv = 1.0 / m_frames;
  for (std::size_t i = 0; i < m_counts.size(); ++i) {
    heat.pixels[i] = static_cast<float>(m_counts[i] * inv);
  }
  return heat;
}

void HeatmapAccumulator::restore(int width, int height, int frames, std::vector<std::uint32_t> counts) {
  if (counts.size() != static_cast<std::size_t>(width) * static_cast<std::size_t>(height))
    throw std::invalid_argument("heat map restore: counts do not match the image size");
  m_width = width;
  m_height = height;
  m_frames = frames;
  m_counts = std::move(counts);
}

}  // namespace millsim::vision
