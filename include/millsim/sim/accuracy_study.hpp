#pragma once
// `millsim study accuracy`: what accuracy costs in time. Runs one-factor-at-a-time matrices of
// settings on reference problems and records, per run, the error against the reference and the
// wall time, so a user can pick a setting on the Pareto front of (wall time, error).
//
// Problems:
// - dam_break_2d: the Martin & Moyce dam break (cases/dam_break_2d.xml geometry) to T = 2.5;
//   error = mean |Z_sim - Z_data| / Z_data over M&M's points with T <= 2.5 (raw: no time
//   shift). Axes: dp, kernel, density diffusion, integrator, CFL, precision.
// - hertz_impact: a 15 mm steel ball hitting a wall at 1 m/s (the drum's material, e = 0.39);
//   error = |e_measured - e| / e (exact damping: the law gives e exactly in the dt -> 0 limit).
//   Axes: time-step divisor
//   N (dt = t_c / N), Young's modulus (the reduced-stiffness question), precision.
// - drum_300: the shipped 300 mm mill, balls only (cases/ball_mill_300_balls.xml, 12 s; --quick:
//   4 s); error = |angle of repose - angle at t_c/200 (quick: t_c/100)| in degrees (the finest setting as the
//   reference, as no analytic angle exists); a second charge seed shows the noise floor.
//   Axes: time-step divisor, Young's modulus, precision, ball representation (sphere / DCDEM).
// - wet_drum_angle, wet_drum_slurry: the small wet mill (cases/wet_drum_small.xml, 1.6 s), one
//   run giving two rows (--only takes "wet_drum"): the balls' angle of repose (error in degrees)
//   and the fitted slurry curve (error = RMS distance in mm between its curve and the
//   reference's over the central half of the drum, |x| <= D/4), both against the finest dp
//   (4 mm; quick: 7.5 mm); a second charge seed shows the noise floor. Axes: SPH spacing dp,
//   ball representation (sphere / DCDEM).
// --quick keeps each axis to its cheapest levels (CI smoke test).
#include <string>
#include <vector>

namespace millsim::sim {

struct StudyRow {
  std::string problem, axis, setting;
  double error = 0;           // relative (dam break, impact) or degrees (drum)
  double value = 0;           // the measured quantity (drum: angle of repose, deg; slurry: curve at x = 0, mm)
  std::vector<double> curve;  // wet_drum_slurry: the fitted y = c0 + c1 x + c2 x^2 (mm); else empty
  double wall_s = 0;
  double simulated_s = 0;
  long long particles = 0, steps = 0;
  std::string backend = "omp";
};

// only: "" (everything), "PROBLEM" or "PROBLEM:AXIS" (e.g. "drum_300:representation").
std::vector<StudyRow> runAccuracyStudy(bool quick, const std::string& source_dir, const std::string& only = "");

// The errors measured against a reference row of the same problem (drum_300, wet_drum_*):
// |angle - the reference's angle|, or the slurry curves' RMS distance (NaN without a reference).
void fillReferenceErrors(std::vector<StudyRow>& rows);

// RMS distance (mm) between two slurry curves y = c0 + c1 x + c2 x^2 over |x| <= half_width_mm.
double slurryCurveDistance(const std::vector<double>& a, const std::vector<double>& b, double half_width_mm);

// Rows of an earlier study with fresh ones: a fresh row replaces the one with the same problem,
// axis and setting, or joins its problem's rows; the reference-based errors are recomputed.
std::vector<StudyRow> mergeStudyRows(std::vector<StudyRow> base, const std::vector<StudyRow>& fresh);

// OUT/accuracy_cost.csv and one Pareto plot per problem (OUT/pareto_<problem>.png).
void writeAccuracyStudy(const std::vector<StudyRow>& rows, const std::string& out_dir);

// The rows of an accuracy_cost.csv written by writeAccuracyStudy (to redraw its plots without
// rerunning the study). Throws core::InputError (file:line) on a malformed row.
std::vector<StudyRow> readAccuracyStudy(const std::string& csv);

// Indices of the rows of one problem on the Pareto front (no other row is both faster and
// more accurate), sorted by wall time.
std::vector<std::size_t> paretoFront(const std::vector<StudyRow>& rows, const std::string& problem);

}  // namespace millsim::sim
