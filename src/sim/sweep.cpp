#include "millsim/sim/sweep.hpp"

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <memory>
#include <mutex>
#include <nlohmann/json.hpp>
#include <stdexcept>

#include "millsim/core/error.hpp"
#include "millsim/io/case_xml.hpp"
#include "millsim/sim/ensemble_run.hpp"

namespace millsim::sim {

namespace {

// Every combination of the axes' values, the first axis slowest.
std::vector<std::vector<std::string>> grid(const std::vector<SweepAxis>& axes) {
  std::vector<std::vector<std::string>> combos{{}};
  for (const SweepAxis& a : axes) {
    std::vector<std::vector<std::string>> next;
    for (const auto& c : combos)
      for (const std::string& v : a.values) {
        next.push_back(c);
        next.back().push_back(v);
      }
    combos = std::move(next);
  }
  return combos;
}

std::string runDir(const std::string& out, int k) {
  char name[32];
  std::snprintf(name, sizeof name, "run_%03d", k);
  return (std::filesystem::path(out) / name).string();
}

SweepRow startRow(const SweepSpec& spec, const std::vector<std::string>& values, int k) {
  SweepRow row;
  row.index = k;
  row.values = values;
  row.out_dir = runDir(spec.run.out_dir, k);
  return row;
}

void failRow(SweepRow& row, const std::string& error) {
  row.error = error;
  row.status = "failed";
  row.angle_deg = row.budget_residual = std::nan("");
}

// The row's numbers from the run's summary (the run may have failed after it started).
void fillRow(SweepRow& row, const RunSummary& s) {
  row.status = row.error.empty() ? s.status : "failed";
  row.angle_deg = s.angle_valid ? s.angle_of_repose_deg : std::nan("");
  row.power_W = s.power_W;
  row.torque_Nm = s.torque_Nm;
  row.budget_residual = s.energy_work_in != 0 ? s.energy_residual / s.energy_work_in : std::nan("");
  row.simulated_s = s.simulated_time_s;
  row.wall_s = s.wall_time_s;
  row.steps = s.steps;
  row.sph_excluded = s.sph_excluded;
}

SweepRow runOne(const SweepSpec& spec, const std::vector<std::string>& sets, const std::vector<std::string>& values,
                int k) {
  SweepRow row = startRow(spec, values, k);
  RunOptions opt = spec.run;
  opt.out_dir = row.out_dir;
  opt.progress = false;
  // Whatever stops one run (instability, a charge that does not fit, an I/O error) is that run's
  // row; the sweep goes on. Its outputs up to the failure stay in its folder.
  std::unique_ptr<Simulation> simulation;
  try {
    simulation = std::make_unique<Simulation>(io::loadCaseFile(spec.case_path, sets), opt);
    simulation->run();
  } catch (const std::exception& e) {
    failRow(row, e.what());
    if (!simulation) return row;
  }
  fillRow(row, simulation->summary());
  return row;
}

// This rank's runs as one ensemble: one row per run; a failure (the shared solver went unstable,
// cases that cannot share it) fails every row with the cause.
std::vector<SweepRow> runEnsembleRows(const SweepSpec& spec, const std::vector<std::vector<std::string>>& settings,
                                      const std::vector<std::vector<std::string>>& combos,
                                      const std::vector<int>& mine) {
  std::vector<SweepRow> rows;
  EnsembleSpec e;
  e.run = spec.run;
  e.run.progress = false;
  for (const int k : mine) {
    rows.push_back(startRow(spec, combos[k], k));
    e.scenes.push_back(io::loadCaseFile(spec.case_path, settings[k]));
    e.out_dirs.push_back(rows.back().out_dir);
  }
  try {
    const std::vector<RunSummary> summaries = runEnsemble(e);
    for (std::size_t i = 0; i < rows.size(); ++i) fillRow(rows[i], summaries[i]);
  } catch (const core::SimulationError&) {
    // The shared solver diverged: every run alone, so each row gets its own outcome.
    rows.clear();
    for (const int k : mine) rows.push_back(runOne(spec, settings[k], combos[k], k));
  } catch (const std::exception& err) {
    for (SweepRow& row : rows) failRow(row, std::string("in the ensemble of this rank's runs: ") + err.what());
  }
  return rows;
}

// Rows between ranks. Numbers as JSON (nlohmann writes doubles to round trip); NaN has no JSON
// form, so angles go as null when not measured.
// NaN and inf have no JSON form: they travel as null and come back as NaN.
nlohmann::json number(double x) { return std::isfinite(x) ? nlohmann::json(x) : nlohmann::json(); }
double number(const nlohmann::json& j) { return j.is_null() ? std::nan("") : j.get<double>(); }

nlohmann::json toJson(const SweepRow& r) {
  return {{"index", r.index},
          {"values", r.values},
          {"out_dir", r.out_dir},
          {"status", r.status},
          {"error", r.error},
          {"angle", number(r.angle_deg)},
          {"power", number(r.power_W)},
          {"torque", number(r.torque_Nm)},
          {"budget", number(r.budget_residual)},
          {"simulated", number(r.simulated_s)},
          {"wall", number(r.wall_s)},
          {"steps", r.steps},
          {"excluded", r.sph_excluded}};
}

SweepRow fromJson(const nlohmann::json& j) {
  SweepRow r;
  r.index = j.at("index").get<int>();
  r.values = j.at("values").get<std::vector<std::string>>();
  r.out_dir = j.at("out_dir").get<std::string>();
  r.status = j.at("status").get<std::string>();
  r.error = j.at("error").get<std::string>();
  r.angle_deg = number(j.at("angle"));
  r.power_W = number(j.at("power"));
  r.torque_Nm = number(j.at("torque"));
  r.budget_residual = number(j.at("budget"));
  r.simulated_s = number(j.at("simulated"));
  r.wall_s = number(j.at("wall"));
  r.steps = j.at("steps").get<long long>();
  r.sph_excluded = j.at("excluded").get<long long>();
  return r;
}

}  // namespace

std::vector<std::vector<std::string>> sweepSettings(const SweepSpec& spec) {
  for (const SweepAxis& a : spec.axes) {
    if (a.path.empty() || a.values.empty()) throw core::InputError("--vary " + a.path + ": give PATH=VALUE[,VALUE...]");
    if (std::count_if(spec.axes.begin(), spec.axes.end(), [&](const SweepAxis& b) { return b.path == a.path; }) > 1)
      throw core::InputError("--vary " + a.path + ": given twice");
  }
  std::vector<std::vector<std::string>> all;
  std::vector<scene::Scene> scenes;
  for (const auto& values : grid(spec.axes)) {
    std::vector<std::string> sets = spec.sets;
    for (std::size_t i = 0; i < values.size(); ++i) sets.push_back(spec.axes[i].path + "=" + values[i]);
    scenes.push_back(io::loadCaseFile(spec.case_path, sets));  // throws InputError naming the file and the field
    all.push_back(std::move(sets));
  }
  // An ensemble's runs must be able to share one solver: a varied stiffness cannot.
  if (spec.ensemble) checkEnsembleCases(scenes, spec.run);
  return all;
}

std::vector<SweepRow> runSweep(const SweepSpec& spec, const core::RankGroup* ranks,
                               const std::function<void(const SweepRow&)>& progress) {
  if (spec.parallel < 1) throw core::InputError("--parallel: at least 1");
  const auto settings = sweepSettings(spec);
  const auto combos = grid(spec.axes);
  if (ranks && ranks->size() < 2) ranks = nullptr;
  std::vector<int> mine;
  for (int k = 0; k < static_cast<int>(settings.size()); ++k)
    if (core::ownsItem(ranks, k)) mine.push_back(k);

  std::vector<SweepRow> done;
  std::mutex mutex;
  std::exception_ptr failure;
  if (spec.ensemble) {
    if (!mine.empty()) done = runEnsembleRows(spec, settings, combos, mine);
    if (progress)
      for (const SweepRow& row : done) progress(row);
  } else {
    failure = core::forEachItem(mine.size(), spec.parallel, [&](std::size_t i) {
      SweepRow row = runOne(spec, settings[mine[i]], combos[mine[i]], mine[i]);
      std::lock_guard<std::mutex> lock(mutex);
      if (progress) progress(row);
      done.push_back(std::move(row));
    });
  }
  if (ranks) {
    nlohmann::json share = nlohmann::json::array();
    for (const SweepRow& r : done) share.push_back(toJson(r));
    done.clear();
    const core::GatheredShares shares =
        core::gatherShares(*ranks, share.dump(-1, ' ', false, nlohmann::json::error_handler_t::replace), failure);
    for (const std::string& s : shares.payloads)
      for (const auto& row : nlohmann::json::parse(s)) done.push_back(fromJson(row));
    core::throwIfAnyRankFailed(shares, failure);
  } else if (failure) {
    std::rethrow_exception(failure);
  }
  std::sort(done.begin(), done.end(), [](const SweepRow& a, const SweepRow& b) { return a.index < b.index; });
  return done;
}

void writeSweepCsv(const std::vector<SweepRow>& rows, const std::vector<SweepAxis>& axes, const std::string& path) {
  std::ofstream out(path);
  if (!out) throw std::runtime_error(path + ": cannot write");
  // Plain CSV: a comma in a value or a message would shift the columns, so it becomes ';'.
  auto cell = [](std::string v) {
    std::replace(v.begin(), v.end(), ',', ';');
    std::replace(v.begin(), v.end(), '\n', ' ');
    return v;
  };
  out << "index";
  for (const SweepAxis& a : axes) out << "," << cell(a.path);
  out << ",status,angle_of_repose_deg,power_W,torque_Nm,budget_residual,simulated_s,steps,sph_excluded,wall_s,out_dir,"
         "error\n";
  out.precision(10);
  for (const SweepRow& r : rows) {
    out << r.index;
    for (const std::string& v : r.values) out << "," << cell(v);
    out << "," << r.status << ",";
    if (std::isfinite(r.angle_deg)) out << r.angle_deg;
    out << "," << r.power_W << "," << r.torque_Nm << ",";
    if (std::isfinite(r.budget_residual)) out << r.budget_residual;
    out << "," << r.simulated_s << "," << r.steps << "," << r.sph_excluded << "," << r.wall_s << "," << cell(r.out_dir)
        << "," << cell(r.error) << "\n";
  }
}

}  // namespace millsim::sim
