#pragma once
// The calibration loop shared by both methods (Doroszek et al. 2024, section 3.9):
//   1. `initial` space-filling candidates (initial_design.hpp);
//   2. repeatedly: the proposer's next candidate(s) from all successful evaluations so far;
//   3. stop when `patience` successive candidates after the initial ones brought no
//      improvement (SSE not strictly below the best so far), or after `max_evals` evaluations.
// With parallel = k, k candidates are evaluated at once on k threads (the initial design at
// once, then batches of k from the proposer), or, for a batched objective (an ensemble), in one
// evaluateAll call; with R MPI ranks, batches of k R, each rank taking
// every R-th candidate, the results gathered on every rank. Each finished evaluation goes to the
// journal at once; on start the journal's rows are taken as done, so a resumed calibration
// re-evaluates nothing (an initial candidate whose index is in the journal is skipped, the
// proposals continue from the journal's data). With parallel = 1 and the same objective a
// resumed calibration takes exactly the steps an uninterrupted one would have taken.
#include <functional>
#include <memory>
#include <string>
#include <vector>

#include "millsim/calib/journal.hpp"
#include "millsim/calib/objective.hpp"
#include "millsim/calib/param_box.hpp"
#include "millsim/calib/proposer.hpp"
#include "millsim/core/rank_group.hpp"

namespace millsim::calib {

struct CalibrationOptions {
  ParamBox box;               // e in [0.30, 0.55], mu in [0.30, 0.70] (paper)
  std::string method = "bo";  // "bo" (GP + expected improvement) | "paper" (thin-plate argmin)
  int initial = 6;            // space-filling initial candidates (paper: 6)
  int patience = 3;           // successive candidates without improvement that stop it (paper: 3)
  int max_evals = 40;         // evaluations in all, initial ones and journal rows included
  int parallel = 1;           // candidates evaluated at once (threads, or one ensemble), per rank
  // MPI ranks (null: one process). Each rank evaluates its share of every batch (batches of
  // parallel x ranks candidates); rank 0 alone should be given the journal.
  const core::RankGroup* ranks = nullptr;
  std::uint64_t seed = 1;     // of the initial design
  SearchOptions search;       // proposal search (grid 101, exclusion 0.02 of the box)
};

struct CalibrationState {
  std::vector<Evaluation> evaluations;  // in index order
  int best = -1;                        // position in `evaluations` of the lowest SSE (ok ones)
  int since_improvement = 0;            // successive candidates after the initial ones without improvement
  int resumed = 0;                      // evaluations taken from the journal
  int evaluated = 0;                    // evaluations run in this session
};

struct CalibrationResult {
  CalibrationState state;
  int recommended = -1;         // position in state.evaluations of the result (Proposer::recommend)
  double recommended_mean = 0;  // the surrogate's SSE there (bo: GP mean; paper: the observed SSE)
  std::string stop_reason;      // "patience" | "max_evals" | "no candidate left"
  Point2 surrogate_min{0, 0};   // argmin of the final surrogate on the surface grid, physical (e, mu)
  double surrogate_min_sse = 0;
  int surface_n = 101;  // the final surrogate on an n x n grid over the box (sse_map.hpp layout)
  std::vector<double> surface;
  double wall_s = 0;
};

// Called after each finished evaluation (under a lock: one call at a time), for progress lines.
using ProgressCallback = std::function<void(const Evaluation&, const CalibrationState&)>;

class Calibrator {
 public:
  // Throws std::invalid_argument for options out of range (initial < 3, patience < 1,
  // max_evals < initial, parallel < 1, an empty box, an unknown method).
  Calibrator(const Objective& objective, CalibrationOptions options);

  // `journal` may be null (nothing stored, nothing resumed). Rethrows the first exception an
  // evaluation throws, after the evaluations already finished are in the journal.
  CalibrationResult run(Journal* journal, const ProgressCallback& progress = {});

  const Proposer& proposer() const { return *m_proposer; }
  const CalibrationOptions& options() const { return m_options; }

  // The stop-rule bookkeeping over evaluations in index order (exposed for tests): best and
  // the count of successive non-improving candidates after the first `initial`.
  static void updateState(CalibrationState& state, int initial);

  // Successful evaluations as surrogate data in unit coordinates.
  std::vector<DataPoint> data(const std::vector<Evaluation>& evaluations) const;

 private:
  const Objective& m_objective;
  CalibrationOptions m_options;
  std::unique_ptr<Proposer> m_proposer;
};

}  // namespace millsim::calib
