// `millsim calibrate` (see calibrate_command.hpp): parse and check the options, build the
// simulation objective, run the calibrator with its journal, write calibration.json and
// sse_map.png.
#include "calibrate_command.hpp"

#include <cmath>
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <iostream>
#include <memory>
#include <mutex>
#include <nlohmann/json.hpp>
#include <sstream>

#include "csv_table.hpp"
#include "millsim/backend/info.hpp"
#include "millsim/calib/calibrator.hpp"
#include "millsim/calib/simulation_objective.hpp"
#include "millsim/calib/sse_map.hpp"
#include "millsim/core/error.hpp"
#include "millsim/vision/video_angle.hpp"
#include "mpi_ranks.hpp"

namespace millsim::cli {

namespace {

using core::InputError;

double parseNumber(const std::string& s, const std::string& option) {
  double v = 0;
  if (!toNumber(s, v)) throw InputError(option + ": '" + s + "' is not a number");
  return v;
}

std::vector<double> parseNumbers(const std::string& s, const std::string& option) {
  std::vector<double> v;
  for (const auto& item : splitList(s)) v.push_back(parseNumber(item, option));
  return v;
}

std::pair<double, double> parseRange(const std::string& s, const std::string& option, double lo_bound,
                                     double hi_bound) {
  const auto v = parseNumbers(s, option);
  if (v.size() != 2 || !(v[0] < v[1])) throw InputError(option + ": expected MIN,MAX with MIN < MAX, got '" + s + "'");
  if (v[0] < lo_bound || v[1] > hi_bound)
    throw InputError(option + ": '" + s + "' leaves [" + std::to_string(lo_bound) + ", " + std::to_string(hi_bound) +
                     "]");
  return {v[0], v[1]};
}

// Measured angles from recordings, through the vision module (balls mode; the outline is the
// drum's outer rim, whose diameter is the label).
std::vector<double> anglesFromVideos(const std::vector<std::string>& videos, const std::vector<std::string>& labels) {
  std::vector<double> angles;
  for (std::size_t i = 0; i < videos.size(); ++i) {
    if (!std::filesystem::exists(videos[i])) throw InputError("--measured-videos: " + videos[i] + ": no such file");
    vision::VideoAngleOptions opt;
    opt.view.diameter_mm = parseNumber(labels[i], "--diameters");
    opt.angle.pixels_per_mm = opt.view.pixels_per_mm;
    const auto r = vision::measureVideoAngle(vision::readVideoFrames(videos[i], 100), opt);
    std::fprintf(stderr, "calibrate: measured %s mm from %s: %.2f deg (+- %.2f)\n", labels[i].c_str(),
                 videos[i].c_str(), r.angle.angle_deg, r.angle.stderr_deg);
    angles.push_back(r.angle.angle_deg);
  }
  return angles;
}

nlohmann::ordered_json anglesJson(const std::vector<std::string>& labels, const std::vector<double>& angles) {
  nlohmann::ordered_json j = nlohmann::ordered_json::object();
  for (std::size_t i = 0; i < labels.size(); ++i)
    j[labels[i]] = i < angles.size() && std::isfinite(angles[i]) ? nlohmann::json(angles[i]) : nlohmann::json();
  return j;
}

}  // namespace

CLI::App* addCalibrateCommand(CLI::App& app, CalibrateArgs& a) {
  auto* c = app.add_subcommand(
      "calibrate",
      "Find restitution and friction from measured angles of repose at several diameters; writes "
      "OUT/calibration.json, OUT/evaluations.csv (journal: rerun with the same --out to resume), OUT/sse_map.png");
  c->add_option("--diameters", a.diameters, "Drum diameters, comma separated (fill {D} of --case-template)")
      ->required();
  auto* measured = c->add_option("--measured", a.measured, "Measured angles of repose [deg], one per diameter");
  auto* videos = c->add_option("--measured-videos", a.measured_videos,
                               "Recordings (one per diameter) to measure the angles from, instead of --measured");
  measured->excludes(videos);
  c->add_option("--case-template", a.case_template, "Case file per diameter; {D} is replaced by the diameter")
      ->capture_default_str();
  c->add_option("--e-range", a.e_range, "Restitution range MIN,MAX")->capture_default_str();
  c->add_option("--mu-range", a.mu_range, "Kinetic friction range MIN,MAX")->capture_default_str();
  c->add_option("--initial", a.initial, "Space-filling initial candidates")->capture_default_str();
  c->add_option("--patience", a.patience, "Stop after this many successive candidates without improvement")
      ->capture_default_str();
  c->add_option("--max-evals", a.max_evals, "Most candidates in all (each runs every diameter)")->capture_default_str();
  c->add_option("--parallel", a.parallel, "Candidates simulated at once per process (threads; under mpirun, per rank)")
      ->capture_default_str();
  c->add_flag("--ensemble", a.ensemble,
              "Run each batch (--parallel candidates x the diameters) as one ensemble in one DEM solver: on a GPU "
              "one launch per stage for the whole batch (docs/calibration.md)");
  c->add_option("--method", a.method, "bo: Gaussian process + expected improvement; paper: thin-plate SSE argmin")
      ->check(CLI::IsMember({"bo", "paper"}))
      ->capture_default_str();
  c->add_option("--set", a.sets, "Override for every run: element.path.attribute=value (repeatable)");
  c->add_option("--out,-o", a.out, "Output directory")->capture_default_str();
  c->add_option("--backend", a.backend, "Backend of each simulation")
      ->check(CLI::IsMember({"auto", "omp", "cuda"}))
      ->capture_default_str();
  c->add_option("--precision", a.precision, "Precision of each simulation")
      ->check(CLI::IsMember({"double", "float"}))
      ->capture_default_str();
  c->add_option("--threads", a.threads, "OpenMP threads per simulation")->capture_default_str();
  c->add_option("--seed", a.seed, "Seed of the initial design")->capture_default_str();
  c->add_flag("--quiet,-q", a.quiet, "No progress lines");
  return c;
}

int calibrateCommand(const CalibrateArgs& a) {
  // --- checks (each an InputError: exit 2) ---
  const std::vector<std::string> labels = splitList(a.diameters);
  for (const auto& l : labels) {
    const double d = parseNumber(l, "--diameters");
    if (!(d > 0)) throw InputError("--diameters: '" + l + "' is not a positive diameter");
  }
  for (std::size_t i = 0; i < labels.size(); ++i)
    for (std::size_t j = 0; j < i; ++j)
      if (labels[i] == labels[j]) throw InputError("--diameters: " + labels[i] + " given twice");
  if (a.measured.empty() && a.measured_videos.empty())
    throw InputError("calibrate: give --measured ANGLES or --measured-videos FILES");
  const std::size_t given = splitList(a.measured.empty() ? a.measured_videos : a.measured).size();
  if (given != labels.size())
    throw InputError(std::string(a.measured.empty() ? "--measured-videos" : "--measured") + ": " +
                     std::to_string(given) + " values for " + std::to_string(labels.size()) + " diameters");
  const auto e_range = parseRange(a.e_range, "--e-range", 1e-9, 1.0);
  const auto mu_range = parseRange(a.mu_range, "--mu-range", 0.0, 1e9);
  if (a.initial < 3) throw InputError("--initial: at least 3 candidates (a plane needs three points)");
  if (a.patience < 1) throw InputError("--patience: at least 1");
  if (a.max_evals < a.initial) throw InputError("--max-evals: at least --initial (" + std::to_string(a.initial) + ")");
  if (a.parallel < 1) throw InputError("--parallel: at least 1");
  if (a.threads < 0) throw InputError("--threads: 0 (all) or more");
  if (a.backend == "cuda" && !backend::cudaCompiled()) throw InputError("--backend cuda: this build has no CUDA");
  // `auto` with a GPU present is cuda too: worker threads would all land on one GPU.
  if (backend::resolvedBackend(a.backend) == "cuda" && a.parallel > 1 && !a.ensemble)
    throw InputError("--backend " + a.backend +
                     " (cuda) with --parallel > 1: one GPU runs one simulation at a time; use --parallel 1 "
                     "(and mpirun with one rank per GPU for more), or --ensemble to run the batch in one solver");

  calib::SimulationObjectiveConfig config;
  config.labels = labels;
  for (const auto& l : labels) {
    const std::string path = calib::expandCaseTemplate(a.case_template, l);
    if (!std::filesystem::exists(path))
      throw InputError("--case-template " + a.case_template + ": " + path + " (diameter " + l + "): no such file");
    config.case_paths.push_back(path);
  }
  config.measured_deg = a.measured.empty() ? std::vector<double>{} : parseNumbers(a.measured, "--measured");
  config.overrides = a.sets;
  config.run.backend = a.backend;
  config.run.precision = a.precision;
  config.run.threads = a.threads;
  config.runs_dir = (std::filesystem::path(a.out) / "runs").string();
  config.ensemble = a.ensemble;
  if (config.measured_deg.empty()) config.measured_deg = anglesFromVideos(splitList(a.measured_videos), labels);
  const calib::SimulationObjective objective(config);  // loads every case: bad --set fails here

  calib::CalibrationOptions options;
  options.box = {e_range.first, e_range.second, mu_range.first, mu_range.second};
  options.method = a.method;
  options.initial = a.initial;
  options.patience = a.patience;
  options.max_evals = a.max_evals;
  options.parallel = a.parallel;
  options.seed = a.seed;
  // Under mpirun each rank simulates its share of every batch; rank 0 keeps the journal, prints
  // and writes the outputs (docs/cluster.md).
  const MpiSession& mpi = mpiSession();
  options.ranks = mpi.ranks();
  const int n_ranks = mpi.ranks() ? mpi.ranks()->size() : 1;
  calib::Calibrator calibrator(objective, options);
  std::unique_ptr<calib::Journal> journal;
  if (mpi.leader()) {
    journal = std::make_unique<calib::Journal>((std::filesystem::path(a.out) / "evaluations.csv").string(),
                                               objective.signature(), labels);
    if (!journal->loaded().empty())
      std::fprintf(stderr, "calibrate: resuming: %zu evaluations from %s\n", journal->loaded().size(),
                   journal->path().c_str());
    if (n_ranks > 1)
      std::fprintf(stderr, "calibrate: %d MPI ranks, batches of %d candidates\n", n_ranks, n_ranks * a.parallel);
  }

  const auto progress = [&](const calib::Evaluation& ev, const calib::CalibrationState& s) {
    if (a.quiet || !mpi.leader()) return;
    std::string angles;
    char buf[64];
    for (double x : ev.angles_deg) {
      std::snprintf(buf, sizeof buf, " %.2f", x);
      angles += buf;
    }
    const calib::Evaluation& b = s.evaluations[s.best >= 0 ? s.best : 0];
    if (ev.ok)
      std::snprintf(buf, sizeof buf, "SSE %.4g", ev.sse);
    else
      std::snprintf(buf, sizeof buf, "failed");
    std::fprintf(stderr,
                 "calibrate [%s] #%d (%zu/%d) e=%.4f mu=%.4f ->%s deg, %s | best SSE %.4g at e=%.4f mu=%.4f | "
                 "no improvement %d/%d | %.1f s%s%s\n",
                 a.method.c_str(), ev.candidate.index + 1, s.evaluations.size(), a.max_evals, ev.candidate.e,
                 ev.candidate.mu, angles.c_str(), buf, s.best >= 0 ? b.sse : NAN, b.candidate.e, b.candidate.mu,
                 s.since_improvement, a.patience, ev.wall_s, ev.ok ? "" : " : ", ev.ok ? "" : ev.error.c_str());
  };
  const calib::CalibrationResult r = calibrator.run(journal.get(), progress);
  const calib::CalibrationState& s = r.state;
  const std::string journal_path = (std::filesystem::path(a.out) / "evaluations.csv").string();
  if (s.best < 0) throw std::runtime_error("calibrate: every candidate failed (see " + journal_path + ")");
  if (!mpi.leader()) return 0;  // the other ranks' share is in the journal rank 0 wrote

  // --- outputs ---
  const std::filesystem::path out(a.out);
  calib::writeSseMap((out / "sse_map.png").string(), options.box, r.surface, r.surface_n, s.evaluations,
                     options.initial, r.recommended >= 0 ? r.recommended : s.best);
  // The result: Proposer::recommend (paper: the lowest SSE; bo: the lowest GP mean among the
  // evaluated candidates, which noise fools less than the lowest observation).
  const calib::Evaluation& best = s.evaluations[r.recommended >= 0 ? r.recommended : s.best];
  const calib::Evaluation& lowest = s.evaluations[s.best];
  long long runs = 0;
  for (const auto& ev : s.evaluations) runs += static_cast<long long>(ev.angles_deg.size());
  double sim_wall = 0;
  for (const auto& ev : s.evaluations) sim_wall += ev.wall_s;
  nlohmann::ordered_json j;
  j["method"] = a.method;
  j["best"] = {{"e", best.candidate.e},
               {"mu", best.candidate.mu},
               {"sse", best.sse},
               {"candidate", best.candidate.index + 1},
               {"angles_deg", anglesJson(labels, best.angles_deg)}};
  j["best"]["surrogate_sse"] = r.recommended_mean;
  j["lowest_observed"] = {{"e", lowest.candidate.e},
                          {"mu", lowest.candidate.mu},
                          {"sse", lowest.sse},
                          {"candidate", lowest.candidate.index + 1}};
  j["measured_deg"] = anglesJson(labels, config.measured_deg);
  j["surrogate_min"] = {{"e", r.surrogate_min[0]}, {"mu", r.surrogate_min[1]}, {"sse", r.surrogate_min_sse}};
  j["iterations"] = s.evaluations.size();
  j["runs"] = runs;
  j["evaluated_this_session"] = s.evaluated;
  j["resumed_from_journal"] = s.resumed;
  j["stop_reason"] = r.stop_reason;
  j["wall_time_s"] = r.wall_s;
  j["simulation_wall_time_s_all_evaluations"] = sim_wall;
  j["backend"] = backend::resolvedBackend(a.backend);
  j["precision"] = a.precision;
  j["threads_per_run"] = a.threads;
  j["parallel"] = a.parallel;
  j["ensemble"] = a.ensemble;
  j["mpi_ranks"] = n_ranks;
  j["e_range"] = {options.box.e_min, options.box.e_max};
  j["mu_range"] = {options.box.mu_min, options.box.mu_max};
  j["initial"] = a.initial;
  j["patience"] = a.patience;
  j["max_evals"] = a.max_evals;
  j["seed"] = a.seed;
  j["cases"] = config.case_paths;
  j["overrides"] = a.sets;
  if (!a.measured_videos.empty()) j["measured_videos"] = splitList(a.measured_videos);
  std::ofstream(out / "calibration.json") << j.dump(2) << "\n";
  std::cout << nlohmann::ordered_json{{"e", best.candidate.e}, {"mu", best.candidate.mu},
                                      {"sse", best.sse},       {"iterations", s.evaluations.size()},
                                      {"runs", runs},          {"stop_reason", r.stop_reason},
                                      {"out", a.out}}
                   .dump()
            << std::endl;
  return 0;
}

}  // namespace millsim::cli
