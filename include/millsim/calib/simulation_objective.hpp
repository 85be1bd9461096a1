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
#include "millsim/scene/scene.hpp"
#include "millsim/sim/simulation.hpp"

namespace millsim::calib {

struct SimulationObjectiveConfig {
  std::vector<std::string> labels;      // diameters as given ("300", "400", "500")
  std::vector<std::string> case_paths;  // one case file per diameter
  std::vector<double> measured_deg;     // measured angle per diameter
  std::vector<std::string> overrides;   // "--set" strings for every run
  sim::RunOptions run;                  // backend, precision, threads (write_outputs forced false)
  std::string runs_dir;                 // where the per-run JSON goes; empty: none
  // Every run of a batch (candidates x diameters) in one DEM solver (sim::runEnsemble): on a
  // GPU the batch is one launch per stage instead of one run at a time. Each run keeps its own
  // time step (the same runs as alone); a diverged solver step (which stops the shared solver)
  // makes the batch run again one candidate at a time; each
  // evaluation's wall_s is its share of the batch's wall time.
  bool ensemble = false;
};

class SimulationObjective : public Objective {
 public:
  // Loads every case once with the overrides (and e, mu set) so a bad case, --set or diameter
  // fails here with core::InputError, before any simulation.
  explicit SimulationObjective(SimulationObjectiveConfig config);

  Evaluation evaluate(const Candidate& c) const override;
  std::vector<Evaluation> evaluateAll(const std::vector<Candidate>& cs) const override;
  bool batched() const override { return m_config.ensemble; }
  std::vector<std::string> labels() const override { return m_config.labels; }
  std::string signature() const override;

 private:
  // The scene of diameter i with (e, mu) set.
  scene::Scene sceneFor(std::size_t i, const Candidate& c) const;
  // OUT/runs/<index>_<D>.json of one run, when runs_dir is set.
  void writeRunJson(const Candidate& c, std::size_t i, const sim::RunSummary& summary) const;
  SimulationObjectiveConfig m_config;
};

// "cases/ball_mill_{D}_balls.xml" with {D} replaced by the label.
std::string expandCaseTemplate(const std::string& pattern, const std::string& label);

}  // namespace millsim::calib
