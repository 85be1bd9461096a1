#pragma once
// `millsim sweep CASE --vary PATH=V1,V2,... [--vary ...]`: the case over a full grid of settings,
// spread over MPI ranks under mpirun (docs/cluster.md). Registered and dispatched by main.cpp.
#include <CLI/CLI.hpp>
#include <string>
#include <vector>

namespace millsim::cli {

struct SweepArgs {
  std::string case_path;
  std::vector<std::string> vary;  // "dem.restitution=0.3,0.4"
  std::vector<std::string> sets;
  std::string out = "sweep_out";
  std::string backend = "auto";
  std::string precision = "double";
  int threads = 1;  // OpenMP threads per run
  int parallel = 1;
  bool ensemble = false;  // a rank's runs in one DEM solver
  bool quiet = false;
};

CLI::App* addSweepCommand(CLI::App& app, SweepArgs& args);

// 0 when every run ended ok, 3 when some stopped (their rows say why); throws core::InputError
// for bad input (exit 2 in main).
int sweepCommand(const SweepArgs& args);

}  // namespace millsim::cli
