#pragma once
// Every shipped case on two engines (tests/gpu: CUDA against OpenMP), over a short stretch of
// its own motion: series.csv column by column, row by row. Short, because two correct runs whose
// sums differ only in order drift apart exponentially once a granular bed or a splash takes over
// (support/ensemble_cases.hpp measures it: 1e-6 of the work by 0.2 s of a drum); each stretch
// below ends before that. Outputs that only cost time (fields, checkpoints, frames) are off.
#include <algorithm>
#include <cmath>
#include <ostream>
#include <string>
#include <vector>

#include "support/case_run.hpp"

namespace millsim::testing {

struct CaseStretch {
  std::string name;
  std::vector<std::string> overrides;
};

// gtest names a parameter by it (instead of dumping its bytes).
inline void PrintTo(const CaseStretch& c, std::ostream* os) { *os << c.name; }

inline std::vector<CaseStretch> everyCaseStretch() {
  const std::vector<std::string> quiet{"output.fields_every=0", "output.checkpoint_every=0"};
  auto with = [&](std::vector<std::string> v) {
    v.insert(v.end(), quiet.begin(), quiet.end());
    return v;
  };
  // Drums: 0.1 s of the charge falling and the piston packing it. Wet drums: the pour at 0.05 s
  // (after a shortened packing: with 0.1 s of it, a 1e-14 change of gravity already moved the
  // drum torque by 3e-9), then 5 ms of coupled steps. SPH: the first 0.02-0.05 s of the flow.
  // Stirred mills: 50 steps from the lattice, the stirrer turning.
  const std::vector<std::string> drum{"time.end=0.1", "angle_of_repose.enabled=false"};
  const std::vector<std::string> wet{"compaction.duration=0.05", "drum.start_time=0.05", "time.end=0.055",
                                     "output.series_every=0.001", "angle_of_repose.enabled=false"};
  const std::vector<std::string> stirred{"time.end=3e-5", "output.series_every=5e-6"};
  return {{"minimal_drum", with(drum)},
          {"ball_mill_300_balls", with(drum)},
          {"ball_mill_400_balls", with(drum)},
          {"ball_mill_500_balls", with(drum)},
          {"wet_drum_small", with(wet)},
          {"ball_mill_500_wet", with(wet)},
          {"dam_break_2d", with({"time.end=0.05"})},
          {"dam_break_3d", with({"time.end=0.02"})},
          {"hydrostatic_2d", with({"time.end=0.05"})},
          {"sloshing_tank_2d", with({"time.end=0.05"})},
          {"stirred_mill_ls1_small", with(stirred)},
          {"stirred_mill_ls1", with(stirred)}};
}

struct SeriesDifference {
  std::string column;   // the column with the largest difference
  double relative = 0;  // |a - b| / (largest |value| of the column over the run), at worst
  std::size_t rows = 0;
};

// Largest difference between two series.csv of the same case. Each column is scaled by its
// largest magnitude over both runs (a front position, a torque, a speed against its own size),
// except energies (columns in J), which share the largest energy of the run: a budget residual
// is a difference of large terms and is judged against the energy that flows. Wall-clock
// columns are not physics and are skipped.
inline SeriesDifference compareSeries(const CaseOutput& a, const CaseOutput& b) {
  auto isEnergy = [](const std::string& n) { return n.size() > 2 && n.compare(n.size() - 2, 2, "_J") == 0; };
  double energy_scale = 0;
  for (const CaseOutput* run : {&a, &b})
    for (const auto& [name, col] : run->series)
      if (isEnergy(name))
        for (double v : col) energy_scale = std::max(energy_scale, std::abs(v));
  SeriesDifference d;
  for (const auto& [name, col] : a.series) {
    if (name.rfind("wall_time", 0) == 0) continue;
    const auto it = b.series.find(name);
    if (it == b.series.end() || it->second.size() != col.size()) {
      d.column = name + " (missing or of another length)";
      d.relative = 1e300;
      return d;
    }
    double scale = isEnergy(name) ? energy_scale : 0;
    for (std::size_t i = 0; i < col.size() && !isEnergy(name); ++i)
      scale = std::max({scale, std::abs(col[i]), std::abs(it->second[i])});
    d.rows = std::max(d.rows, col.size());
    if (scale == 0) continue;
    for (std::size_t i = 0; i < col.size(); ++i) {
      const double r = std::abs(col[i] - it->second[i]) / scale;
      if (!(r <= d.relative)) {  // NaN counts as the worst
        d.relative = std::isnan(r) ? 1e300 : r;
        d.column = name;
      }
    }
  }
  return d;
}

}  // namespace millsim::testing
