#pragma once
// The two ways of choosing the next candidates from everything evaluated so far.
//   PaperProposer  (--method paper): the argmin of the thin-plate-spline interpolant of the
//                  SSEs (Doroszek et al. 2024, section 3.9).
//   GpProposer     (--method bo):    the argmax of the expected improvement of a Gaussian
//                  process fitted to the SSEs.
// A batch of k > 1 candidates (--parallel k) is built one at a time, each chosen point added to
// the data with the surrogate's own prediction as its value ("kriging believer", Ginsbourger
// et al. 2010) so the next one goes elsewhere; for k = 1 that is the plain method.
// surface() is the surrogate SSE the map (sse_map.hpp) draws: the interpolant or the GP mean.
#include <memory>
#include <string>
#include <vector>

#include "millsim/calib/param_box.hpp"
#include "millsim/calib/surface_search.hpp"

namespace millsim::calib {

struct DataPoint {
  Point2 x;  // unit coordinates
  double sse = 0;
};

class Proposer {
 public:
  virtual ~Proposer() = default;
  // `data`: successful evaluations; `avoid`: every evaluated point, failed ones included.
  virtual std::vector<Point2> propose(const std::vector<DataPoint>& data, const std::vector<Point2>& avoid,
                                      int count) const = 0;
  // Surrogate SSE over the unit square from `data` (for the map and the reported optimum).
  virtual std::vector<double> surface(const std::vector<DataPoint>& data, const std::vector<Point2>& at) const = 0;
  // Position in `data` of the point to report as the result: the lowest SSE (paper), or the
  // lowest GP mean among the evaluated points (bo: with noisy SSEs the lowest observation is
  // often a lucky draw, the posterior mean averages its neighbours).
  virtual int recommend(const std::vector<DataPoint>& data) const;
  virtual std::string name() const = 0;
};

class PaperProposer : public Proposer {
 public:
  explicit PaperProposer(SearchOptions search = {}) : m_search(search) {}
  std::vector<Point2> propose(const std::vector<DataPoint>& data, const std::vector<Point2>& avoid,
                              int count) const override;
  std::vector<double> surface(const std::vector<DataPoint>& data, const std::vector<Point2>& at) const override;
  std::string name() const override { return "paper"; }

 private:
  SearchOptions m_search;
};

class GpProposer : public Proposer {
 public:
  // min_nugget (default 1e-4): floor of the fitted noise, relative to the SSE variance.
  explicit GpProposer(SearchOptions search = {}, double min_nugget = 1e-4)
      : m_search(search), m_min_nugget(min_nugget) {}
  std::vector<Point2> propose(const std::vector<DataPoint>& data, const std::vector<Point2>& avoid,
                              int count) const override;
  std::vector<double> surface(const std::vector<DataPoint>& data, const std::vector<Point2>& at) const override;
  int recommend(const std::vector<DataPoint>& data) const override;
  std::string name() const override { return "bo"; }

 private:
  SearchOptions m_search;
  double m_min_nugget;
};

// "paper" or "bo"; throws std::invalid_argument otherwise.
std::unique_ptr<Proposer> makeProposer(const std::string& method, const SearchOptions& search = {});

}  // namespace millsim::calib
