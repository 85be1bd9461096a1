// Normalised mill view: one affine warp from the frame (see mill_view.hpp).
#include "millsim/vision/mill_view.hpp"

#include <cmath>
#include <opencv2/imgproc.hpp>
#include <stdexcept>

#include "vision/cv_convert.hpp"

namespace millsim::vision {
namespace {
constexpr double kPi = 3.14159265358979323846;
}

MillView::MillView(const MillCircle& circle, const ViewOptions& opt) : m_circle(circle), m_options(opt) {
  if (!(opt.pixels_per_mm > 0.0) || !(opt.diameter_mm > 0.0) || !(opt.wall_mm >= 0.0) || !(opt.margin_mm >= 0.0))
    throw std::invalid_argument(
        "mill view: pixels_per_mm and diameter_mm must be positive, wall_mm and margin_mm >= 0");
  if (!(circle.radius_px > 0.0)) throw std::invalid_argument("mill view: the mill circle has no radius");
  m_inner_radius = 0.5 * opt.diameter_mm - opt.wall_mm;
  if (!(m_inner_radius - opt.margin_mm > 0.0))
    throw std::invalid_argument("mill view: wall_mm + margin_mm leave nothing of the drum");
  m_frame_scale = circle.radius_px / (0.5 * opt.diameter_mm);
  m_size = static_cast<int>(std::lround(2.0 * m_inner_radius * opt.pixels_per_mm));

  // view (col, row) -> mm: x = -R + (col + .5)/p, y = R - (row + .5)/p; mirror: x -> -x;
  // camera roll t (counter-clockwise on screen): (xi, yi) = Rot(t) (x, y);
  // frame: u = cx + s xi, v = cy - s yi.
  const double p = opt.pixels_per_mm, R = m_inner_radius, s = m_frame_scale;
  const double t = opt.tilt_deg * kPi / 180.0;
  const double ct = std::cos(t), st = std::sin(t);
  const double mx = opt.mirror ? -1.0 : 1.0;
  // x = mx * (a_c col + b_c), y = a_r row + b_r
  const double a_c = mx / p, b_c = mx * (-R + 0.5 / p);
  const double a_r = -1.0 / p, b_r = R - 0.5 / p;
  // xi = ct x - st y ; yi = st x + ct y
  // u = cx + s (ct (a_c col + b_c) - st (a_r row + b_r))
  // v = cy - s (st (a_c col + b_c) + ct (a_r row + b_r))
  m_view_to_frame = {s * ct * a_c,  -s * st * a_r, circle.cx_px + s * (ct * b_c - st * b_r),
                     -s * st * a_c, -s * ct * a_r, circle.cy_px - s * (st * b_c + ct * b_r)};

  m_mask = ImageU8(m_size, m_size, 0);
  const double rm = R - opt.margin_mm;
  for (int row = 0; row < m_size; ++row) {
    const double y = viewRowToMm(row, R, p);
    for (int col = 0; col < m_size; ++col) {
      const double x = viewColToMm(col, R, p);
      if (x * x + y * y < rm * rm) m_mask.at(col, row) = 255;
    }
  }
}

void MillView::frameToMm(double u, double v, double& x_mm, double& y_mm) const {
  const double t = m_options.tilt_deg * kPi / 180.0;
  const double xi = (u - m_circle.cx_px) / m_frame_scale, yi = -(v - m_circle.cy_px) / m_frame_scale;
  // Undo the roll: (x, y) = Rot(-t) (xi, yi).
  x_mm = std::cos(t) * xi + std::sin(t) * yi;
  y_mm = -std::sin(t) * xi + std::cos(t) * yi;
  if (m_options.mirror) x_mm = -x_mm;
}

void MillView::mmToFrame(double x_mm, double y_mm, double& u, double& v) const {
  const double t = m_options.tilt_deg * kPi / 180.0;
  const double x = m_options.mirror ? -x_mm : x_mm;
  const double xi = std::cos(t) * x - std::sin(t) * y_mm, yi = std::sin(t) * x + std::cos(t) * y_mm;
  u = m_circle.cx_px + m_frame_scale * xi;
  v = m_circle.cy_px - m_frame_scale * yi;
}

ImageRgb MillView::apply(const ImageRgb& frame) const {
  cv::Mat src = detail::toBgr(frame);
  // Frame pixels per view pixel; above ~1.5 bilinear sampling would skip pixels and alias.
  const double shrink = m_frame_scale / m_options.pixels_per_mm;
  if (shrink > 1.5) cv::GaussianBlur(src, src, cv::Size(0, 0), 0.5 * shrink);
  const cv::Mat A = (cv::Mat_<double>(2, 3) << m_view_to_frame[0], m_view_to_frame[1], m_view_to_frame[2],
                     m_view_to_frame[3], m_view_to_frame[4], m_view_to_frame[5]);
  cv::Mat out;
  cv::warpAffine(src, out, A, cv::Size(m_size, m_size), cv::INTER_LINEAR | cv::WARP_INVERSE_MAP, cv::BORDER_CONSTANT,
                 cv::Scalar(0, 0, 0));
  return detail::toImageRgb(out);
}

}  // namespace millsim::vision
