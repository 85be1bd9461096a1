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
// that differs). A ball that leaves its drum fails that case alone (its summary says why, its
// balls rest) and the others go on. A diverged solver step (NaN, a ball thrown past any
// bound) stops every case still running (they share the solver) with core::SimulationError
// naming the case and its ball; each case's summary.json says why.
//
// What a summary gives as the ensemble's, not its case's: wall_time_s, neighbour_rebuilds and
// the memory report.
std::vector<RunSummary> runEnsemble(const EnsembleSpec& spec);

// The checks runEnsemble makes first, for callers that load their cases long before they run
// them (calibrate, sweep): throws core::InputError naming the case and the field that differs,
// or the option (single precision: positions reach K/2 slab lengths from the origin, where a
// float resolves ~2.4e-7 m for 18 drums, 10x coarser than in one drum alone).
void checkEnsembleCases(const std::vector<scene::Scene>& scenes, const RunOptions& run);

}  // namespace millsim::sim
