#pragma once
// What a calibration minimises: a candidate (restitution e, kinetic friction mu) -> the angle of
// repose at each diameter and the sum of squared errors (SSE) against the measured angles.
// The optimiser only sees this interface, so the same loop drives real simulations
// (simulation_objective.hpp) and cheap analytic functions with known minima (tests,
// analytic_objective.hpp).
#include <string>
#include <vector>

namespace millsim::calib {

// The parameters a calibration searches, in their physical units (both dimensionless).
struct Candidate {
  int index = 0;  // position in the proposal order (0-based), names the runs of this candidate
  double e = 0;   // coefficient of restitution
  double mu = 0;  // coefficient of kinetic (Coulomb) friction
};

struct Evaluation {
  Candidate candidate;
  std::vector<double> angles_deg;  // one per diameter of the objective (empty for analytic ones)
  double sse = 0;                  // sum of squared errors [deg^2]; meaningful only when ok
  bool ok = false;                 // false: a run failed (instability, no measurable surface)
  std::string error;               // why, when !ok
  double wall_s = 0;               // wall time of this evaluation
};

class Objective {
 public:
  virtual ~Objective() = default;
  // Must be safe to call from several threads at once (--parallel). Throws only for errors
  // that should stop the calibration (bad input); a failed simulation is an Evaluation with
  // ok = false.
  virtual Evaluation evaluate(const Candidate& c) const = 0;
  // Several candidates at once, results in their order. An objective that runs them together
  // (an ensemble in one solver: batched() true) overrides it, and the calibrator then hands it
  // a rank's whole share of a batch instead of one candidate per thread.
  virtual std::vector<Evaluation> evaluateAll(const std::vector<Candidate>& cs) const {
    std::vector<Evaluation> out;
    for (const Candidate& c : cs) out.push_back(evaluate(c));
    return out;
  }
  virtual bool batched() const { return false; }
  // Labels of the per-candidate values in angles_deg ("300", "400", ...), journal columns.
  virtual std::vector<std::string> labels() const { return {}; }
  // Everything that changes what evaluate() returns (measured angles, cases, overrides). The
  // journal stores it; a journal written for another signature is not resumed.
  virtual std::string signature() const = 0;
};

// SSE of simulated against measured angles (same length). Shared by every objective that
// compares angles, so the paper's definition lives in one place.
double sumSquaredErrors(const std::vector<double>& simulated, const std::vector<double>& measured);

}  // namespace millsim::calib
