#include "sim/run_outputs.hpp"

#include <unistd.h>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <fstream>
#include <iomanip>
#include <nlohmann/json.hpp>
#include <sstream>

#include "millsim/core/error.hpp"

namespace millsim::sim {

namespace {

// Keeps the header and the rows whose time (first column) is before t, through a temporary file
// and a rename. Times are printed with 9 significant digits, so a row at t itself may read a
// hair off it.
void dropRowsFrom(const std::filesystem::path& path, double t) {
  std::ifstream in(path);
  std::string line, kept;
  const double cut = t - 1e-8 * std::max(1.0, std::abs(t));
  bool header = true;
  while (std::getline(in, line)) {
    if (!header && !line.empty() && std::strtod(line.c_str(), nullptr) >= cut) break;
    kept += line + "\n";
    header = false;
  }
  in.close();
  const std::filesystem::path tmp = path.string() + ".tmp";
  std::ofstream out(tmp, std::ios::out | std::ios::trunc);
  out << kept;
  out.close();
  if (!out) throw core::InputError(tmp.string() + ": cannot write the series file");
  std::filesystem::rename(tmp, path);
}

}  // namespace

SeriesWriter::SeriesWriter(const std::filesystem::path& path, const std::vector<std::string>& columns, bool append,
                           double resume_time) {
  const bool fresh = !append || !std::filesystem::exists(path);
  if (!fresh) dropRowsFrom(path, resume_time);
  m_out.open(path, fresh ? std::ios::out : std::ios::app);
  if (!m_out) throw core::InputError(path.string() + ": cannot write the series file");
  if (fresh) {
    for (std::size_t i = 0; i < columns.size(); ++i) m_out << (i ? "," : "") << columns[i];
    m_out << "\n";
  }
  m_out << std::setprecision(9);
}

void SeriesWriter::row(const std::vector<double>& values) {
  for (std::size_t i = 0; i < values.size(); ++i) m_out << (i ? "," : "") << values[i];
  m_out << "\n";
  m_out.flush();
}

nlohmann::ordered_json summaryHead(const RunSummary& s, const std::string& case_name, const std::string& case_source) {
  nlohmann::ordered_json j;
  j["case"] = case_name;
  j["case_source"] = case_source;
  j["status"] = s.status;
  if (!s.error.empty()) j["error"] = s.error;
  j["backend"] = s.backend;
  j["precision"] = s.precision;
  j["threads"] = s.threads;
  j["wall_time_s"] = s.wall_time_s;
  j["simulated_time_s"] = s.simulated_time_s;
  j["steps"] = s.steps;
  j["dt_s"] = s.dt;
  return j;
}

nlohmann::ordered_json memoryJson(const std::map<std::string, std::size_t>& memory) {
  nlohmann::ordered_json mem;
  std::size_t total = 0;
  for (const auto& [k, v] : memory) {
    mem[k] = v;
    total += v;
  }
  mem["total"] = total;
  return mem;
}

void writeJsonFile(const std::filesystem::path& path, const nlohmann::ordered_json& j) {
  const auto tmp = path.string() + ".tmp";
  {
    std::ofstream out(tmp);
    out << j.dump(2) << "\n";
  }
  std::filesystem::rename(tmp, path);
}

void markRunEnd(RunSummary& s, const std::string& status, double t, long long steps,
                std::chrono::steady_clock::time_point wall0) {
  s.status = status;
  s.simulated_time_s = t;
  s.steps = steps;
  s.wall_time_s = std::chrono::duration<double>(std::chrono::steady_clock::now() - wall0).count();
}

void recordFailedRun(RunSummary& s, const std::string& error, double t, long long steps,
                     std::chrono::steady_clock::time_point wall0, const std::filesystem::path* summary_json,
                     const std::map<std::string, std::size_t>& memory, const std::string& case_name,
                     const std::string& case_source) {
  s.error = error;
  markRunEnd(s, "failed", t, steps, wall0);
  if (summary_json) writeSummaryJson(*summary_json, s, {}, memory, case_name, case_source);
}

void fillDemEnergy(RunSummary& s, double kinetic, double potential, double dissipated, double work_in, double elastic) {
  s.energy_kinetic = kinetic;
  s.energy_potential = potential;
  s.energy_dissipated = dissipated;
  s.energy_work_in = work_in;
  s.energy_elastic = elastic;
}

void writeSummaryJson(const std::filesystem::path& path, const RunSummary& s, const std::vector<std::string>& stages,
                      const std::map<std::string, std::size_t>& memory, const std::string& case_name,
                      const std::string& case_source) {
  nlohmann::ordered_json j = summaryHead(s, case_name, case_source);
  j["neighbour_rebuilds"] = s.neighbour_rebuilds;
  j["particles"] = {{"dem_spheres", s.particles}, {"sph", 0}};
  j["charge_mass_kg"] = s.charge_mass_kg;
  j["stages"] = stages;
  j["memory_bytes"] = memoryJson(memory);
  if (s.angle_valid) {
    j["angle_of_repose_deg"] = s.angle_of_repose_deg;
    j["angle_of_repose_stderr_deg"] = s.angle_stderr_deg;
  } else {
    j["angle_of_repose_deg"] = nullptr;
    if (!s.angle_error.empty()) j["angle_error"] = s.angle_error;
  }
  j["angle_frames"] = s.angle_frames;
  j["angle_points"] = s.angle_points;
  j["power_W"] = s.power_W;
  j["torque_Nm"] = s.torque_Nm;
  j["omega_rad_s"] = s.omega_rad_s;
  j["energy"] = {{"kinetic_J", s.energy_kinetic},       {"potential_J", s.energy_potential},
                 {"dissipated_J", s.energy_dissipated}, {"work_in_J", s.energy_work_in},
                 {"elastic_J", s.energy_elastic},       {"budget_residual_J", s.energy_residual}};
  if (s.sph_particles > 0) {
    j["particles"]["sph"] = s.sph_particles;
    j["wet_mill"] = {
        {"sph_steps", s.sph_steps},
        {"sph_excluded", s.sph_excluded},
        {"slurry_kinetic_J", s.slurry_kinetic},
        {"slurry_potential_J", s.slurry_potential},
        {"slurry_frames", s.slurry_frames},
        {"slurry_curve_mm", s.slurry_valid ? nlohmann::ordered_json(s.slurry_coef) : nlohmann::ordered_json()}};
    if (!s.slurry_error.empty()) j["wet_mill"]["slurry_error"] = s.slurry_error;
  }
  writeJsonFile(path, j);
}

io::FieldFrame fieldFrame(double t, long long step, const std::vector<double>& pos, const std::vector<double>& vel) {
  io::FieldFrame f;
  f.time = t;
  f.step = step;
  f.count = pos.size() / 3;
  f.position.assign(pos.begin(), pos.end());
  f.arrays.push_back({"velocity", 3, std::vector<float>(vel.begin(), vel.end())});
  return f;
}

io::FieldFrame demFieldFrame(double t, long long step, const dem::DemHostState& s) {
  io::FieldFrame f = fieldFrame(t, step, s.pos, s.vel);
  f.arrays.push_back({"angular_velocity", 3, std::vector<float>(s.omega.begin(), s.omega.end())});
  f.arrays.push_back({"radius", 1, std::vector<float>(s.radius.begin(), s.radius.end())});
  f.arrays.push_back({"dissipated_energy", 1, std::vector<float>(s.dissipated.begin(), s.dissipated.end())});
  return f;
}

ProgressLine::ProgressLine(bool enabled, double t_end)
    : m_enabled(enabled), m_terminal(enabled && isatty(STDERR_FILENO)), m_t_end(t_end) {
  m_start = m_last = std::chrono::steady_clock::now();
}

std::string progressText(double t, double t_end, double steps_per_s, double eta_s) {
  char eta[32] = "--";
  if (eta_s > 0 && std::isfinite(eta_s)) {
    const long long e = std::llround(eta_s);
    if (e >= 3600)
      std::snprintf(eta, sizeof eta, "%lld:%02lld:%02lld", e / 3600, e / 60 % 60, e % 60);
    else
      std::snprintf(eta, sizeof eta, "%lld:%02lld", e / 60, e % 60);
  }
  char line[160];
  std::snprintf(line, sizeof line, " t = %.3f / %.3f s  %3.0f%%  %.0f steps/s  ETA %s", t, t_end,
                100 * t / std::max(1e-300, t_end), steps_per_s, eta);
  return line;
}

void ProgressPace::sample(double wall_s, double t, long long steps) {
  if (!m_started) {
    m_started = true;
    m_wall = wall_s, m_t = t, m_steps = steps;
    return;
  }
  const double dwall = wall_s - m_wall, dt = t - m_t;
  // An interval in which the run has not moved has no pace yet: it joins the next one.
  if (dwall <= 0 || dt <= 0 || steps <= m_steps) return;
  const double pace = dwall / dt, step_s = dwall / static_cast<double>(steps - m_steps);
  const double w = m_moved ? 1.0 - std::exp(-dwall / m_tau) : 1.0;
  m_pace += w * (pace - m_pace);
  m_step_s += w * (step_s - m_step_s);
  m_moved = true;
  m_wall = wall_s, m_t = t, m_steps = steps;
}

double ProgressPace::etaSeconds(double t_end) const { return m_moved ? std::max(0.0, t_end - m_t) * m_pace : 0.0; }

void ProgressLine::update(double t, long long steps) {
  if (!m_enabled) return;
  const auto now = std::chrono::steady_clock::now();
  const double wall = std::chrono::duration<double>(now - m_start).count();
  // The first call starts the pace's clock; later ones feed it at the line's own cadence.
  if (m_first) {
    m_first = false;
    m_pace.sample(wall, t, steps);
    return;
  }
  if (std::chrono::duration<double>(now - m_last).count() < (m_terminal ? 0.5 : 60.0)) return;
  m_last = now;
  m_pace.sample(wall, t, steps);
  const std::string text = progressText(t, m_t_end, m_pace.stepsPerSecond(), m_pace.etaSeconds(m_t_end));
  if (m_terminal)
    std::fprintf(stderr, "\r%s   ", text.c_str());
  else
    std::fprintf(stderr, "progress:%s\n", text.c_str());
  std::fflush(stderr);
}

void ProgressLine::finish() {
  if (m_terminal) std::fprintf(stderr, "\n");
}

}  // namespace millsim::sim
