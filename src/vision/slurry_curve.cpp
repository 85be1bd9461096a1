// Robust quadratic slurry curve, picked-point CSV input, curve CSV output (see slurry_curve.hpp).
#include "millsim/vision/slurry_curve.hpp"

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <fstream>
#include <sstream>
#include <stdexcept>

#include "millsim/core/error.hpp"
#include "millsim/vision/mill_view.hpp"

namespace millsim::vision {
namespace {

std::vector<std::string> splitCsv(const std::string& line) {
  std::vector<std::string> out;
  std::stringstream ss(line);
  std::string cell;
  while (std::getline(ss, cell, ',')) {
    const auto b = cell.find_first_not_of(" \t\r");
    const auto e = cell.find_last_not_of(" \t\r");
    out.push_back(b == std::string::npos ? std::string() : cell.substr(b, e - b + 1));
  }
  return out;
}

}  // namespace

SlurryCurve fitSlurryCurve(const std::vector<SurfacePoint>& points, double outlier_sigmas, double confidence) {
  if (points.size() < 8) {
    throw std::runtime_error("slurry curve: only " + std::to_string(points.size()) +
                             " surface points (need 8); is the slurry visible, and is its colour unlike the drum's?");
  }
  if (!(outlier_sigmas > 0.0)) throw std::invalid_argument("slurry curve: outlier_sigmas must be positive");
  std::vector<char> keep(points.size(), 1);
  SlurryCurve c;
  for (int iter = 0; iter < 20; ++iter) {
    std::vector<double> x, y;
    std::vector<int> g;
    for (std::size_t i = 0; i < points.size(); ++i) {
      if (!keep[i]) continue;
      x.push_back(points[i].x_mm);
      y.push_back(points[i].y_mm);
      // Hand-picked points (frame < 0) are each their own group, i.e. independent.
      g.push_back(points[i].frame >= 0 ? points[i].frame : -1 - static_cast<int>(i));
    }
    const bool grouped = std::any_of(points.begin(), points.end(), [](const SurfacePoint& p) { return p.frame >= 0; });
    c.fit = fitQuadratic(x, y, grouped ? g : std::vector<int>{}, confidence);
    std::vector<double> res(points.size());
    std::vector<double> abs_kept;
    for (std::size_t i = 0; i < points.size(); ++i) {
      res[i] = points[i].y_mm - c.fit.value(points[i].x_mm);
      if (keep[i]) abs_kept.push_back(std::abs(res[i]));
    }
    std::nth_element(abs_kept.begin(), abs_kept.begin() + abs_kept.size() / 2, abs_kept.end());
    const double sigma = std::max(1e-6, 1.4826 * abs_kept[abs_kept.size() / 2]);
    bool changed = false;
    for (std::size_t i = 0; i < points.size(); ++i) {
      const char k = std::abs(res[i]) <= outlier_sigmas * sigma ? 1 : 0;
      changed |= (k != keep[i]);
      keep[i] = k;
    }
    if (!changed) break;
    if (std::count(keep.begin(), keep.end(), 1) < 8)
      throw std::runtime_error("slurry curve: fewer than 8 points agree with a quadratic surface");
  }
  c.used.clear();
  c.rejected.clear();
  for (std::size_t i = 0; i < points.size(); ++i) (keep[i] ? c.used : c.rejected).push_back(points[i]);
  c.x_min_mm = c.x_max_mm = c.used.front().x_mm;
  for (const SurfacePoint& p : c.used) {
    c.x_min_mm = std::min(c.x_min_mm, p.x_mm);
    c.x_max_mm = std::max(c.x_max_mm, p.x_mm);
  }
  return c;
}

std::vector<SurfacePoint> readSurfacePointsCsv(const std::string& path, const MillView* view) {
  std::ifstream in(path);
  if (!in) throw core::InputError(path + ": cannot open the points file");
  std::string line;
  int lineno = 0;
  bool have_header = false, pixels = false, has_frame = false;
  std::vector<SurfacePoint> pts;
  while (std::getline(in, line)) {
    ++lineno;
    if (line.empty() || line[0] == '#' || line.find_first_not_of(" \t\r") == std::string::npos) continue;
    const std::vector<std::string> cells = splitCsv(line);
    if (!have_header) {
      if (cells.size() >= 2 && cells[0] == "x_mm" && cells[1] == "y_mm") {
        pixels = false;
      } else if (cells.size() >= 2 && cells[0] == "x_px" && cells[1] == "y_px") {
        pixels = true;
        if (!view)
          throw core::InputError(path, lineno,
                                 "points in frame pixels (x_px,y_px) need the video or images "
                                 "to find the mill; give --video or --images, or use x_mm,y_mm");
      } else {
        throw core::InputError(path, lineno, "expected a header x_mm,y_mm[,frame] or x_px,y_px[,frame]");
      }
      has_frame = cells.size() >= 3 && cells[2] == "frame";
      have_header = true;
      continue;
    }
    if (cells.size() < 2) throw core::InputError(path, lineno, "expected two numbers");
    double a = 0, b = 0;
    int frame = -1;
    try {
      std::size_t pa = 0, pb = 0;
      a = std::stod(cells[0], &pa);
      b = std::stod(cells[1], &pb);
      if (pa != cells[0].size() || pb != cells[1].size() || !std::isfinite(a) || !std::isfinite(b))
        throw std::invalid_argument("trailing");
      if (has_frame && cells.size() >= 3) frame = std::stoi(cells[2]);
    } catch (const std::exception&) {
      throw core::InputError(path, lineno, "not a number: '" + line + "'");
    }
    SurfacePoint p;
    if (pixels) {
      view->frameToMm(a, b, p.x_mm, p.y_mm);
    } else {
      p.x_mm = a;
      p.y_mm = b;
    }
    p.frame = frame;
    pts.push_back(p);
  }
  if (!have_header) throw core::InputError(path + ": empty points file");
  return pts;
}

void writeSlurryCurveCsv(const std::string& path, const SlurryCurve& c, double step_mm) {
  if (!(step_mm > 0.0)) throw std::invalid_argument("writeSlurryCurveCsv: step must be positive");
  std::ofstream out(path);
  if (!out) throw core::InputError(path + ": cannot write");
  out << "x_mm,y_fit_mm,y_low_mm,y_high_mm,y_low_simultaneous_mm,y_high_simultaneous_mm\n";
  char buf[128];
  const int n = static_cast<int>(std::floor((c.x_max_mm - c.x_min_mm) / step_mm + 1e-9));
  for (int i = 0; i <= n; ++i) {
    const double x = std::min(c.x_max_mm, c.x_min_mm + i * step_mm);
    const double y = c.fit.value(x), hw = c.fit.halfWidth(x), hs = c.fit.simultaneousHalfWidth(x);
    std::snprintf(buf, sizeof buf, "%.3f,%.4f,%.4f,%.4f,%.4f,%.4f\n", x, y, y - hw, y + hw, y - hs, y + hs);
    out << buf;
  }
}

void writeSurfacePointsCsv(const std::string& path, const SlurryCurve& c) {
  std::ofstream out(path);
  if (!out) throw core::InputError(path + ": cannot write");
  out << "x_mm,y_mm,frame,used\n";
  char buf[128];
  for (const auto* list : {&c.used, &c.rejected})
    for (const SurfacePoint& p : *list) {
      std::snprintf(buf, sizeof buf, "%.4f,%.4f,%d,%d\n", p.x_mm, p.y_mm, p.frame, list == &c.used ? 1 : 0);
      out << buf;
    }
}

}  // namespace millsim::vision
