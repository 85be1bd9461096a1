#pragma once
// Writers for what a run leaves in OUT/: series.csv (one row per series interval, flushed so a
// crash loses nothing written), summary.json, and the progress line on a terminal.
#include <chrono>
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <limits>
#include <map>
#include <nlohmann/json.hpp>
#include <string>
#include <vector>

#include "dem/dem_engine.hpp"
#include "millsim/io/fields_writer.hpp"
#include "millsim/sim/simulation.hpp"

namespace millsim::sim {

class SeriesWriter {
 public:
  // append: a run resumed at resume_time (from a checkpoint) continues the file. Rows at or after
  // resume_time, written by the earlier run past its last checkpoint, are dropped first: the
  // resumed run writes them again, and time stays increasing down the file (no resume_time:
  // every row is kept).
  SeriesWriter(const std::filesystem::path& path, const std::vector<std::string>& columns, bool append,
               double resume_time = std::numeric_limits<double>::infinity());
  void row(const std::vector<double>& values);

 private:
  std::ofstream m_out;
};

// The fields every summary.json opens with (case, status, backend, times, steps, dt).
nlohmann::ordered_json summaryHead(const RunSummary& s, const std::string& case_name, const std::string& case_source);
// Bytes by array group, plus "total".
nlohmann::ordered_json memoryJson(const std::map<std::string, std::size_t>& memory);
// Through a temporary file and a rename: a reader never sees half a file.
void writeJsonFile(const std::filesystem::path& path, const nlohmann::ordered_json& j);
// A fields snapshot with positions and velocities (3 per particle); callers add their arrays.
io::FieldFrame fieldFrame(double t, long long step, const std::vector<double>& pos, const std::vector<double>& vel);
// A DEM snapshot: positions, velocities, angular velocities, radii and the energy each particle
// has dissipated (drum and stirred runs).
io::FieldFrame demFieldFrame(double t, long long step, const dem::DemHostState& s);

// Status, simulated time, steps and wall time since wall0, at the end of a run loop.
void markRunEnd(RunSummary& s, const std::string& status, double t, long long steps,
                std::chrono::steady_clock::time_point wall0);

void writeSummaryJson(const std::filesystem::path& path, const RunSummary& s, const std::vector<std::string>& stages,
                      const std::map<std::string, std::size_t>& memory, const std::string& case_name,
                      const std::string& case_source);

// A run loop stopped by a SimulationError: the summary is marked "failed" with the cause and,
// when outputs are on, summary.json is written (the fields and series already written stay).
void recordFailedRun(RunSummary& s, const std::string& error, double t, long long steps,
                     std::chrono::steady_clock::time_point wall0, const std::filesystem::path* summary_json,
                     const std::map<std::string, std::size_t>& memory, const std::string& case_name,
                     const std::string& case_source);

// The DEM energy state of the summary (kinetic, potential, dissipated, wall work, elastic).
void fillDemEnergy(RunSummary& s, double kinetic, double potential, double dissipated, double work_in, double elastic);

// The pace of a run for its ETA: an average over the last minutes, not since the start, because
// runs change pace by orders of magnitude between phases (the wet mill's 2 s of dry compaction
// take seconds, its 10 s of coupled rotation hours: a whole-run average read 22 min left when 2 h
// were). Averaged is the pace, wall seconds per simulated second, not its inverse: a fast burst
// then weighs little instead of dominating. Exponential weights by wall time, time constant tau.
class ProgressPace {
 public:
  explicit ProgressPace(double tau_s = 120.0) : m_tau(tau_s) {}
  // A sample at wall time `wall_s` (any origin, increasing) of simulated time t after `steps`.
  void sample(double wall_s, double t, long long steps);
  // Wall seconds left to reach t_end at the current pace; 0 until the run has moved.
  double etaSeconds(double t_end) const;
  // Steps per wall second: the inverse of the average wall time per step, same weights.
  double stepsPerSecond() const { return m_step_s > 0 ? 1.0 / m_step_s : 0.0; }

 private:
  double m_tau;
  bool m_started = false, m_moved = false;
  double m_wall = 0, m_t = 0;
  long long m_steps = 0;
  double m_pace = 0, m_step_s = 0;
};

// Progress of a run on stderr. On a terminal one line rewritten in place at most every 0.5 s:
// "\r t = 3.200 / 12.000 s   27%  41200 steps/s  ETA 21:05"; into a file or pipe (nohup, a batch
// job's log) a new line every 60 s, so an hours-long run shows it is alive and when it will end.
class ProgressLine {
 public:
  ProgressLine(bool enabled, double t_end);
  void update(double t, long long steps);
  void finish();

 private:
  bool m_enabled;
  bool m_terminal;
  double m_t_end;
  std::chrono::steady_clock::time_point m_start, m_last;
  ProgressPace m_pace;
  bool m_first = true;
};

// " t = 3.200 / 12.000 s   27%  41200 steps/s  ETA 21:05" (ETA as m:ss below an hour, h:mm:ss
// above; "--" until the run has moved).
std::string progressText(double t, double t_end, double steps_per_s, double eta_s);

}  // namespace millsim::sim
