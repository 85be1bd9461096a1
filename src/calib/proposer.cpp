// Next candidates: thin-plate argmin (paper) or GP expected improvement (bo), batches by the
// kriging believer (see the header).
#include "millsim/calib/proposer.hpp"

#include <algorithm>
#include <cmath>
#include <limits>
#include <stdexcept>

#include "millsim/calib/gaussian_process.hpp"
#include "millsim/calib/thin_plate_spline.hpp"

namespace millsim::calib {

namespace {

// When no surrogate can be built (fewer than 3 successful points, or all on a line): the point
// of the box farthest from everything evaluated.
Point2 farthestPoint(const std::vector<Point2>& avoid, const SearchOptions& search) {
  SearchOptions s = search;
  s.exclusion = 0;
  const auto negDistance = [&avoid](const Point2& x) {
    double d = std::numeric_limits<double>::infinity();
    for (const Point2& p : avoid) d = std::min(d, std::hypot(x[0] - p[0], x[1] - p[1]));
    return avoid.empty() ? 0.0 : -d;
  };
  return minimiseSurface(negDistance, avoid, s).x;
}

void split(const std::vector<DataPoint>& data, std::vector<Point2>& x, std::vector<double>& y) {
  for (const DataPoint& d : data) {
    x.push_back(d.x);
    y.push_back(d.sse);
  }
}

}  // namespace

int Proposer::recommend(const std::vector<DataPoint>& data) const {
  int best = -1;
  for (std::size_t i = 0; i < data.size(); ++i)
    if (best < 0 || data[i].sse < data[best].sse) best = static_cast<int>(i);
  return best;
}

std::vector<Point2> PaperProposer::propose(const std::vector<DataPoint>& data, const std::vector<Point2>& avoid,
                                           int count) const {
  std::vector<Point2> x, chosen, blocked = avoid;
  std::vector<double> y;
  split(data, x, y);
  for (int k = 0; k < count; ++k) {
    Point2 next;
    try {
      const ThinPlateSpline tps(x, y);
      const SearchResult r = minimiseSurface([&tps](const Point2& p) { return tps(p); }, blocked, m_search);
      if (!r.found) break;
      next = r.x;
      y.push_back(tps(next));  // believer: the interpolant's own value
    } catch (const std::invalid_argument&) {
      next = farthestPoint(blocked, m_search);
      y.push_back(*std::max_element(y.begin(), y.end()));
    }
    x.push_back(next);
    blocked.push_back(next);
    chosen.push_back(next);
  }
  return chosen;
}

std::vector<double> PaperProposer::surface(const std::vector<DataPoint>& data, const std::vector<Point2>& at) const {
  std::vector<Point2> x;
  std::vector<double> y, out(at.size(), std::numeric_limits<double>::quiet_NaN());
  split(data, x, y);
  try {
    const ThinPlateSpline tps(x, y);
    for (std::size_t i = 0; i < at.size(); ++i) out[i] = tps(at[i]);
  } catch (const std::invalid_argument&) {
  }
  return out;
}

std::vector<Point2> GpProposer::propose(const std::vector<DataPoint>& data, const std::vector<Point2>& avoid,
                                        int count) const {
  std::vector<Point2> x, chosen, blocked = avoid;
  std::vector<double> y;
  split(data, x, y);
  if (x.size() < 3) {
    for (int k = 0; k < count; ++k) {
      chosen.push_back(farthestPoint(blocked, m_search));
      blocked.push_back(chosen.back());
    }
    return chosen;
  }
  const GaussianProcess fitted = GaussianProcess::fit(x, y, m_min_nugget);
  const GpHyper hyper = fitted.hyper();
  // Noisy data: the incumbent is the lowest posterior mean at an evaluated point, not the
  // lowest (possibly lucky) observation.
  double best = std::numeric_limits<double>::infinity();
  for (const Point2& p : x) best = std::min(best, fitted.mean(p));
  for (int k = 0; k < count; ++k) {
    const GaussianProcess gp = k == 0 ? fitted : GaussianProcess(x, y, hyper);
    const auto negEi = [&gp, best](const Point2& p) {
      return -expectedImprovement(gp.mean(p), std::sqrt(gp.variance(p)), best);
    };
    const SearchResult r = minimiseSurface(negEi, blocked, m_search);
    if (!r.found) break;
    x.push_back(r.x);
    y.push_back(gp.mean(r.x));  // kriging believer
    blocked.push_back(r.x);
    chosen.push_back(r.x);
  }
  return chosen;
}

std::vector<double> GpProposer::surface(const std::vector<DataPoint>& data, const std::vector<Point2>& at) const {
  std::vector<Point2> x;
  std::vector<double> y, out(at.size(), std::numeric_limits<double>::quiet_NaN());
  split(data, x, y);
  if (x.empty()) return out;
  const GaussianProcess gp = GaussianProcess::fit(x, y, m_min_nugget);
  for (std::size_t i = 0; i < at.size(); ++i) out[i] = gp.mean(at[i]);
  return out;
}

int GpProposer::recommend(const std::vector<DataPoint>& data) const {
  if (data.size() < 3) return Proposer::recommend(data);
  std::vector<Point2> x;
  std::vector<double> y;
  split(data, x, y);
  const GaussianProcess gp = GaussianProcess::fit(x, y, m_min_nugget);
  int best = 0;
  for (std::size_t i = 1; i < x.size(); ++i)
    if (gp.mean(x[i]) < gp.mean(x[best])) best = static_cast<int>(i);
  return best;
}

std::unique_ptr<Proposer> makeProposer(const std::string& method, const SearchOptions& search) {
  if (method == "paper") return std::make_unique<PaperProposer>(search);
  if (method == "bo") return std::make_unique<GpProposer>(search);
  throw std::invalid_argument("unknown calibration method '" + method + "' (paper | bo)");
}

}  // namespace millsim::calib
