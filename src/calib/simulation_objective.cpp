// The simulation objective: one run per diameter with (e, mu) set, angles -> SSE (see header).
#include "millsim/calib/simulation_objective.hpp"

#include <chrono>
#include <cmath>
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <nlohmann/json.hpp>

#include "millsim/core/error.hpp"
#include "millsim/io/case_xml.hpp"
#include "millsim/sim/ensemble_run.hpp"

namespace millsim::calib {

namespace {

std::string number(double v) {
  char buf[40];
  std::snprintf(buf, sizeof buf, "%.17g", v);
  return buf;
}

std::vector<std::string> runOverrides(const std::vector<std::string>& user, double e, double mu) {
  std::vector<std::string> o = user;
  o.push_back("dem.restitution=" + number(e));
  o.push_back("dem.friction=" + number(mu));
  return o;
}

}  // namespace

std::string expandCaseTemplate(const std::string& pattern, const std::string& label) {
  std::string s = pattern;
  for (std::size_t at = s.find("{D}"); at != std::string::npos; at = s.find("{D}", at + label.size()))
    s.replace(at, 3, label);
  return s;
}

SimulationObjective::SimulationObjective(SimulationObjectiveConfig config) : m_config(std::move(config)) {
  const std::size_t n = m_config.labels.size();
  if (n == 0) throw core::InputError("calibrate: no diameters");
  if (m_config.case_paths.size() != n || m_config.measured_deg.size() != n)
    throw core::InputError("calibrate: one case and one measured angle per diameter are needed");
  for (const std::string& o : m_config.overrides)
    if (o.rfind("dem.restitution=", 0) == 0 || o.rfind("dem.friction=", 0) == 0)
      throw core::InputError("--set " + o +
                             ": restitution and friction are what calibrate searches; give their range "
                             "with --e-range / --mu-range");
  std::vector<scene::Scene> scenes;
  for (std::size_t i = 0; i < n; ++i) {
    const scene::Scene s = io::loadCaseFile(m_config.case_paths[i], runOverrides(m_config.overrides, 0.4, 0.5));
    scenes.push_back(s);
    if (!s.angle.enabled)
      throw core::InputError(m_config.case_paths[i],
                             s.element_lines.count("angle_of_repose") ? s.element_lines.at("angle_of_repose") : 0,
                             "calibrate needs the angle of repose: <angle_of_repose enabled=\"true\">");
  }
  if (m_config.ensemble) sim::checkEnsembleCases(scenes, m_config.run);
  m_config.run.write_outputs = false;
  m_config.run.progress = false;
  if (!m_config.runs_dir.empty()) std::filesystem::create_directories(m_config.runs_dir);
}

std::string SimulationObjective::signature() const {
  std::string s = "simulation;precision=" + m_config.run.precision;
  for (std::size_t i = 0; i < m_config.labels.size(); ++i)
    s += ";" + m_config.labels[i] + ":" + m_config.case_paths[i] + "=" + number(m_config.measured_deg[i]);
  for (const std::string& o : m_config.overrides) s += ";set " + o;
  return s;
}

scene::Scene SimulationObjective::sceneFor(std::size_t i, const Candidate& c) const {
  return io::loadCaseFile(m_config.case_paths[i], runOverrides(m_config.overrides, c.e, c.mu));
}

void SimulationObjective::writeRunJson(const Candidate& c, std::size_t i, const sim::RunSummary& summary) const {
  if (m_config.runs_dir.empty()) return;
  nlohmann::ordered_json j;
  j["index"] = c.index;
  j["e"] = c.e;
  j["mu"] = c.mu;
  j["diameter"] = m_config.labels[i];
  j["case"] = m_config.case_paths[i];
  j["status"] = summary.status;
  j["error"] = summary.error;
  j["angle_of_repose_deg"] = summary.angle_valid ? nlohmann::json(summary.angle_of_repose_deg) : nlohmann::json();
  j["angle_stderr_deg"] = summary.angle_stderr_deg;
  j["angle_frames"] = summary.angle_frames;
  j["angle_points"] = summary.angle_points;
  j["particles"] = summary.particles;
  j["steps"] = summary.steps;
  j["wall_time_s"] = summary.wall_time_s;
  j["backend"] = summary.backend;
  j["precision"] = summary.precision;
  j["ensemble"] = m_config.ensemble;
  const auto file =
      std::filesystem::path(m_config.runs_dir) / (std::to_string(c.index) + "_" + m_config.labels[i] + ".json");
  std::ofstream(file) << j.dump(2) << "\n";
}

namespace {

// One diameter's run into the candidate's evaluation: its angle, or why it has none.
void addRun(Evaluation& ev, const std::string& label, const sim::RunSummary& summary) {
  if (ev.ok && summary.status != "ok") {
    ev.ok = false;
    ev.error = label + ": unstable: " + summary.error;
  } else if (ev.ok && !summary.angle_valid) {
    ev.ok = false;
    ev.error = label + ": no angle: " + summary.angle_error;
  }
  ev.angles_deg.push_back(summary.angle_valid ? summary.angle_of_repose_deg : std::nan(""));
}

}  // namespace

Evaluation SimulationObjective::evaluate(const Candidate& c) const {
  const auto wall0 = std::chrono::steady_clock::now();
  Evaluation ev;
  ev.candidate = c;
  ev.ok = true;
  for (std::size_t i = 0; i < m_config.labels.size() && ev.ok; ++i) {
    const scene::Scene scene = sceneFor(i, c);
    sim::RunSummary summary;
    try {
      sim::Simulation sim(scene, m_config.run);
      summary = sim.run();
    } catch (const core::SimulationError& err) {
      summary.status = "failed";
      summary.error = err.what();
    }
    addRun(ev, m_config.labels[i], summary);
    writeRunJson(c, i, summary);
    // A failed diameter fails the candidate; its other diameters would not change that.
  }
  if (ev.ok) ev.sse = sumSquaredErrors(ev.angles_deg, m_config.measured_deg);
  ev.wall_s = std::chrono::duration<double>(std::chrono::steady_clock::now() - wall0).count();
  return ev;
}

std::vector<Evaluation> SimulationObjective::evaluateAll(const std::vector<Candidate>& cs) const {
  if (!m_config.ensemble) return Objective::evaluateAll(cs);
  const auto wall0 = std::chrono::steady_clock::now();
  const std::size_t d = m_config.labels.size();
  sim::EnsembleSpec spec;
  spec.run = m_config.run;
  for (const Candidate& c : cs)
    for (std::size_t i = 0; i < d; ++i) {
      spec.scenes.push_back(sceneFor(i, c));
      spec.out_dirs.push_back("");
    }
  std::vector<sim::RunSummary> runs;
  try {
    runs = sim::runEnsemble(spec);  // a ball out of its drum fails its run alone
  } catch (const core::SimulationError&) {
    // The shared solver diverged: every candidate alone, so each gets its own outcome (and a
    // stable one is not journalled as failed because another was not).
    return Objective::evaluateAll(cs);
  }
  const double wall = std::chrono::duration<double>(std::chrono::steady_clock::now() - wall0).count();
  std::vector<Evaluation> out;
  for (std::size_t k = 0; k < cs.size(); ++k) {
    Evaluation ev;
    ev.candidate = cs[k];
    ev.ok = true;
    for (std::size_t i = 0; i < d; ++i) {
      addRun(ev, m_config.labels[i], runs[k * d + i]);
      writeRunJson(cs[k], i, runs[k * d + i]);
    }
    if (ev.ok) ev.sse = sumSquaredErrors(ev.angles_deg, m_config.measured_deg);
    ev.wall_s = wall / static_cast<double>(cs.size());  // its share: the batch's runs shared one solver
    out.push_back(ev);
  }
  return out;
}

}  // namespace millsim::calib
