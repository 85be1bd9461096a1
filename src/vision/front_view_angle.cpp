#include "millsim/vision/front_view_angle.hpp"

#include <fstream>
#include <stdexcept>

#include "millsim/vision/angle_overlay.hpp"
#include "millsim/vision/png_io.hpp"
#include "millsim/vision/render_discs.hpp"

namespace millsim::vision {

FrontViewAngle::FrontViewAngle(double drum_diameter_m, const AngleOptions& options)
    : m_radius(0.5 * drum_diameter_m), m_options(options) {}

void FrontViewAngle::addFrame(const std::vector<double>& x, const std::vector<double>& y,
                              const std::vector<double>& radius) {
  m_heat.add(renderDiscs(x, y, radius, -m_radius, -m_radius, 2 * m_radius, 2 * m_radius, m_options.pixels_per_mm));
}

AngleResult FrontViewAngle::measure() const {
  if (m_heat.frames() < 2)
    throw std::runtime_error("angle of repose: " + std::to_string(m_heat.frames()) + " frame(s), need at least 2");
  return angleFromHeatmap(m_heat.heatmap(), m_options);
}

void FrontViewAngle::writeImages(const std::filesystem::path& dir, const AngleResult* result) const {
  if (m_heat.frames() == 0) return;
  const ImageF heat = m_heat.heatmap();
  ImageU8 gray(heat.width, heat.height);
  for (std::size_t k = 0; k < heat.pixels.size(); ++k) gray.pixels[k] = static_cast<std::uint8_t>(255.0f * heat.pixels[k]);
  writePng(dir / "heatmap.png", gray);
  if (!result) return;
  writePng(dir / "angle_overlay.png", renderAngleOverlay(heat, *result, m_options.pixels_per_mm));
  std::ofstream edge(dir / "angle_edge.csv");
  edge << "x_mm,y_mm\n";
  for (std::size_t k = 0; k < result->fit_x_mm.size(); ++k) edge << result->fit_x_mm[k] << "," << result->fit_y_mm[k] << "\n";
}

}  // namespace millsim::vision
