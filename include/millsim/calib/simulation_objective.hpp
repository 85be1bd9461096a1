#pragma once
// The real objective: for a candidate (e, mu) run the case of each diameter with
// dem.restitution = e and dem.friction = mu (plus the user's --set overrides, which apply to
// every run) and compare the simulated angles of repose with the measured ones. The runs of
// one candidate are sequential; a calibration runs several candidates at once (--parallel), so
// each run uses `run.threads` OpenMP threads (default 1) and writes no HDF5 (HDF5 is not
// thread-safe): only a small JSON per run, OUT/runs/<index>_<D>.json, when runs_dir is set.
#include <string>
#include <vector>

#include "millsim/calib/objective.hpp"
#include "millsim/sim/simulation.hpp"

namespace millsim::calib {

struct SimulationObjectiveConfig {
  std::vector<std::string> labels;      // diameters as given ("300", "400", "500")
  std::vector<std::string> case_paths;  // one case file per diameter
  std::vector<double> measured_deg;     // measured angle per diameter
  std::vector<std::string> overrides;   // "--set" strings for every run
  sim::RunOptions run;                  // backend, precision, threads (write_outputs forced false)
  std::string runs_dir;                 // where the per-run JSON goes; empty: none
};

class SimulationObjective : public Objective {
 public:
  // Loads every case once with the overrides (and e, mu set) so a bad case, --set or diameter
  // fails here with core::InputError, before any simulation.
  explicit SimulationObjective(SimulationObjectiveConfig config);

  Evaluation evaluate(const Candidate& c) const override;
  std::vector<std::string> labels() const override { return m_config.labels; }
  std::string signature() const override;

 private:
  SimulationObjectiveConfig m_config;
};

// "cases/ball_mill_{D}_balls.xml" with {D} replaced by the label.
std::string expandCaseTemplate(const std::string& pattern, const std::string& label);

}  // namespace millsim::calib
