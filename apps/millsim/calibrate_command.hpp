#pragma once
// `millsim calibrate`: restitution and friction from measured angles of repose at several drum
// diameters (issue 8, docs/calibration.md). Kept apart from main.cpp so the command's options,
// checks and outputs live in one place; main.cpp only registers and dispatches it.
#include <CLI/CLI.hpp>
#include <string>
#include <vector>

namespace millsim::cli {

struct CalibrateArgs {
  std::string diameters;                                        // "300,400,500"
  std::string measured;                                         // "43.25,42.15,40.35" [deg]
  std::string measured_videos;                                  // "a.mp4,b.mp4,c.mp4"
  std::string case_template = "cases/ball_mill_{D}_balls.xml";  // {D}: each diameter
  std::string e_range = "0.3,0.55";                             // paper section 3.9
  std::string mu_range = "0.3,0.7";                             // paper section 3.9
  int initial = 6;                                              // paper: 6
  int patience = 3;                                             // paper: 3
  int max_evals = 40;
  int parallel = 1;
  bool ensemble = false;  // a batch's runs in one DEM solver (sim::runEnsemble)
  std::string method = "bo";  // bo | paper
  std::vector<std::string> sets;
  std::string out = "calibration_out";
  std::string backend = "auto";
  std::string precision = "double";
  int threads = 1;  // OpenMP threads per simulation
  unsigned long long seed = 1;
  bool quiet = false;
};

CLI::App* addCalibrateCommand(CLI::App& app, CalibrateArgs& args);

// Throws core::InputError for bad input (exit 2 in main).
int calibrateCommand(const CalibrateArgs& args);

}  // namespace millsim::cli
