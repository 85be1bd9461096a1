// `millsim sweep`: options, the grid from --vary, progress lines and OUT/sweep.csv + sweep.json.
#include "sweep_command.hpp"

#include <chrono>
#include <cmath>
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <iostream>
#include <nlohmann/json.hpp>

#include "millsim/backend/info.hpp"
#include "millsim/core/error.hpp"
#include "millsim/io/fields_writer.hpp"
#include "millsim/sim/sweep.hpp"
#include "mpi_ranks.hpp"

namespace millsim::cli {

namespace {

sim::SweepAxis parseAxis(const std::string& text) {
  const std::size_t eq = text.find('=');
  if (eq == std::string::npos || eq == 0 || eq + 1 == text.size())
    throw core::InputError("--vary '" + text + "': expected PATH=VALUE[,VALUE...]");
  sim::SweepAxis a;
  a.path = text.substr(0, eq);
  std::string rest = text.substr(eq + 1);
  for (std::size_t start = 0;;) {
    const std::size_t comma = rest.find(',', start);
    const std::string v = rest.substr(start, comma == std::string::npos ? std::string::npos : comma - start);
    if (v.empty()) throw core::InputError("--vary '" + text + "': an empty value");
    a.values.push_back(v);
    if (comma == std::string::npos) break;
    start = comma + 1;
  }
  return a;
}

}  // namespace

CLI::App* addSweepCommand(CLI::App& app, SweepArgs& a) {
  auto* c =
      app.add_subcommand("sweep",
                         "Run a case over every combination of --vary values; writes OUT/sweep.csv, OUT/sweep.json "
                         "and each run's outputs in OUT/run_NNN (under mpirun the runs are spread over the ranks)");
  c->add_option("case", a.case_path, "Case XML file")->required()->check(CLI::ExistingFile);
  c->add_option("--vary", a.vary, "A setting and its values: element.attribute=V1,V2,... (repeatable: a full grid)")
      ->required();
  c->add_option("--set", a.sets, "Override for every run: element.attribute=value (repeatable)");
  c->add_option("--out,-o", a.out, "Output directory")->capture_default_str();
  c->add_option("--backend", a.backend, "Backend of each run")
      ->check(CLI::IsMember({"auto", "omp", "cuda"}))
      ->capture_default_str();
  c->add_option("--precision", a.precision, "Precision of each run")
      ->check(CLI::IsMember({"double", "float"}))
      ->capture_default_str();
  c->add_option("--threads", a.threads, "OpenMP threads per run")->capture_default_str();
  c->add_option("--parallel", a.parallel, "Runs side by side per process (threads; under mpirun, per rank)")
      ->capture_default_str();
  c->add_flag("--ensemble", a.ensemble,
              "All runs (under mpirun: a rank's runs) as one ensemble in one DEM solver, --threads threads: on a "
              "GPU one launch per stage for all of them; balls-only drum cases; no fields or checkpoints");
  c->add_flag("--quiet,-q", a.quiet, "No progress lines");
  return c;
}

int sweepCommand(const SweepArgs& a) {
  if (a.threads < 0) throw core::InputError("--threads: 0 (all) or more");
  if (a.parallel < 1) throw core::InputError("--parallel: at least 1");
  if (a.backend == "cuda" && !backend::cudaCompiled()) throw core::InputError("--backend cuda: this build has no CUDA");
  // `auto` with a GPU present is cuda too: worker threads would all land on one GPU.
  if (a.ensemble && a.parallel > 1) throw core::InputError("--ensemble with --parallel > 1: an ensemble is one run");
  if (backend::resolvedBackend(a.backend) == "cuda" && a.parallel > 1)
    throw core::InputError("--backend " + a.backend +
                           " (cuda) with --parallel > 1: one GPU runs one simulation at a time; use --parallel 1 "
                           "(and mpirun with one rank per GPU for more), or --ensemble");
  // Several runs writing fields and checkpoints at once need a thread-safe HDF5.
  if (a.parallel > 1 && !io::hdf5ThreadSafe())
    throw core::InputError("--parallel " + std::to_string(a.parallel) +
                           ": the HDF5 library of this build is not thread-safe; use --parallel 1 (or mpirun)");
  sim::SweepSpec spec;
  spec.case_path = a.case_path;
  spec.sets = a.sets;
  for (const std::string& v : a.vary) spec.axes.push_back(parseAxis(v));
  spec.run.out_dir = a.out;
  spec.run.backend = a.backend;
  spec.run.precision = a.precision;
  spec.run.threads = a.threads;
  spec.parallel = a.parallel;
  spec.ensemble = a.ensemble;
  const MpiSession& mpi = mpiSession();
  const int n_ranks = mpi.ranks() ? mpi.ranks()->size() : 1;
  const std::size_t n_runs = sim::sweepSettings(spec).size();  // bad input fails here, on every rank
  if (mpi.leader() && !a.quiet)
    std::fprintf(stderr, "sweep: %zu runs of %s, %d rank(s) x %d at once, out %s\n", n_runs, a.case_path.c_str(),
                 n_ranks, a.parallel, a.out.c_str());
  const int rank = mpi.ranks() ? mpi.ranks()->rank() : 0;
  // This rank's share of the runs, for the progress count and the ETA (runs k = rank mod ranks).
  const int share = static_cast<int>((n_runs + n_ranks - 1 - rank) / n_ranks);
  int finished = 0;  // progress() is called under the sweep's lock: one call at a time
  const auto t0 = std::chrono::steady_clock::now();
  const auto progress = [&](const sim::SweepRow& r) {
    ++finished;
    if (a.quiet) return;
    std::string values;
    for (std::size_t i = 0; i < r.values.size(); ++i) values += " " + spec.axes[i].path + "=" + r.values[i];
    const double elapsed = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
    std::fprintf(stderr, "sweep [rank %d, %d/%d, ETA %.0f s] run %d:%s -> %s", rank, finished, share,
                 elapsed / finished * (share - finished), r.index, values.c_str(), r.status.c_str());
    if (r.status == "ok" && std::isfinite(r.angle_deg)) std::fprintf(stderr, ", angle %.2f deg", r.angle_deg);
    if (r.status == "ok") std::fprintf(stderr, ", power %.4g W, %.1f s\n", r.power_W, r.wall_s);
    if (r.status != "ok") std::fprintf(stderr, ": %s\n", r.error.c_str());
  };
  const std::vector<sim::SweepRow> rows = sim::runSweep(spec, mpi.ranks(), progress);
  int failed = 0;
  for (const auto& r : rows) failed += r.status != "ok";
  if (!mpi.leader()) return failed ? 3 : 0;
  std::filesystem::create_directories(a.out);
  sim::writeSweepCsv(rows, spec.axes, (std::filesystem::path(a.out) / "sweep.csv").string());
  nlohmann::ordered_json j = nlohmann::ordered_json::array();
  for (const auto& r : rows) {
    nlohmann::ordered_json row;
    row["index"] = r.index;
    for (std::size_t i = 0; i < r.values.size(); ++i) row[spec.axes[i].path] = r.values[i];
    row["status"] = r.status;
    row["angle_of_repose_deg"] = std::isfinite(r.angle_deg) ? nlohmann::ordered_json(r.angle_deg) : nullptr;
    row["power_W"] = r.power_W;
    row["torque_Nm"] = r.torque_Nm;
    row["budget_residual"] = std::isfinite(r.budget_residual) ? nlohmann::ordered_json(r.budget_residual) : nullptr;
    row["steps"] = r.steps;
    row["sph_excluded"] = r.sph_excluded;
    row["wall_s"] = r.wall_s;
    row["out_dir"] = r.out_dir;
    if (!r.error.empty()) row["error"] = r.error;
    j.push_back(row);
  }
  std::ofstream(std::filesystem::path(a.out) / "sweep.json") << j.dump(2) << "\n";
  std::cout << nlohmann::ordered_json{{"runs", rows.size()},
                                      {"failed", failed},
                                      {"ranks", n_ranks},
                                      {"csv", (std::filesystem::path(a.out) / "sweep.csv").string()}}
                   .dump()
            << std::endl;
  return failed ? 3 : 0;
}

}  // namespace millsim::cli
