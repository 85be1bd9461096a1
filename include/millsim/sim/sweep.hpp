#pragma once
// `millsim sweep`: one case run over every combination of the values given for some of its
// settings (a full factorial grid), e.g. restitution x friction x mill diameter. The runs are
// independent: with several MPI ranks (mpirun) rank r takes runs r, r + R, r + 2R, ...; within a
// rank `parallel` runs go side by side on threads. Every rank ends with every run's result.
#include <functional>
#include <string>
#include <vector>

#include "millsim/core/rank_group.hpp"
#include "millsim/sim/simulation.hpp"

namespace millsim::sim {

struct SweepAxis {
  std::string path;                 // a case setting, as for --set ("dem.restitution")
  std::vector<std::string> values;  // as written by the user (passed to --set unchanged)
};

struct SweepSpec {
  std::string case_path;
  std::vector<std::string> sets;  // applied to every run, before the axis values
  std::vector<SweepAxis> axes;    // the first varies slowest
  RunOptions run;                 // out_dir: the sweep's folder; run k writes to out_dir/run_<k>
  int parallel = 1;               // runs side by side per rank (threads)
  // A rank's runs as one ensemble in one DEM solver (ensemble_run.hpp; balls-only drum cases):
  // each run's folder gets summary.json, series.csv and the angle images, no fields or
  // checkpoint; a diverged solver step (which stops the shared solver) runs them again alone.
  bool ensemble = false;
};

struct SweepRow {
  int index = 0;
  std::vector<std::string> values;  // one per axis
  std::string out_dir;
  std::string status = "not run";  // ok | failed
  std::string error;
  double angle_deg = 0;  // NaN when not measured
  double power_W = 0, torque_Nm = 0, simulated_s = 0, wall_s = 0;
  double budget_residual = 0;  // energy budget residual / work put in (NaN when no work went in)
  long long steps = 0, sph_excluded = 0;
};

// The grid's --set lists in run order (the case's own settings first). Loads every run's case
// once, so a bad path or value fails before anything runs (core::InputError, file and field).
std::vector<std::vector<std::string>> sweepSettings(const SweepSpec& spec);

// Runs the sweep; a run that goes unstable is a row with status "failed" and its cause, the
// others go on. `progress` is called on each rank for that rank's runs as they finish.
std::vector<SweepRow> runSweep(const SweepSpec& spec, const core::RankGroup* ranks = nullptr,
                               const std::function<void(const SweepRow&)>& progress = {});

// OUT/sweep.csv: index, one column per axis, status, angle_of_repose_deg, power_W, torque_Nm,
// budget_residual (of the work in), simulated_s, steps, sph_excluded, wall_s, out_dir, error.
void writeSweepCsv(const std::vector<SweepRow>& rows, const std::vector<SweepAxis>& axes, const std::string& path);

}  // namespace millsim::sim
