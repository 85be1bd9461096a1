#pragma once
// An ensemble: several balls-only drum cases advanced by ONE DEM solver, in the same kernels
// (issue 10). A calibration batch (3 diameters x K candidates of a few hundred balls each) is
// then one launch per stage on a GPU instead of 3K launch-bound runs; on the CPU it is one
// parallel loop over all their balls.
//
// Each case keeps what makes it itself: its drum (diameter, length, lifters, speed, compaction
// piston), its charge (fill, ball sizes, seed), its restitution and friction, its front view,
// series and output schedule. What one solver holds once must be the same in every case:
// Young's modulus and Poisson ratio, the damping model, the tangential law and its smoothing,
// gravity, the ball representation (spheres), time.end and the precision. Each case steps by
// its own time step (its own contact time), all in the same launches: a case with larger balls
// takes fewer steps and, once at its end, rests (its forces are no longer evaluated), so an
// ensemble does the work its runs would do alone.
//
// Each case's summary is what it would have been alone (angle of repose, power, energy budget
// over its own balls and drum), except the wall time, which is the ensemble's.
#include <string>
#include <vector>

#include "millsim/scene/scene.hpp"
#include "millsim/sim/simulation.hpp"

namespace millsim::sim {

struct EnsembleSpec {
  std::vector<scene::Scene> scenes;
  std::vector<std::string> out_dirs;  // one per scene (its summary.json, series.csv, angle images)
  RunOptions run;                     // backend, precision, threads, progress, write_outputs
};

// Throws core::InputError when the cases cannot share a solver (naming the case and the field
// that differs), core::SimulationError when the ensemble goes unstable (naming the case); a
// failure stops every case (they share the solver), and each case's summary.json says why.
std::vector<RunSummary> runEnsemble(const EnsembleSpec& spec);

// The check runEnsemble makes first, for callers that load their cases long before they run
// them (calibrate): throws core::InputError naming the case and the field that differs.
void checkEnsembleCases(const std::vector<scene::Scene>& scenes);

}  // namespace millsim::sim
