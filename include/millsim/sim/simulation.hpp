#pragma once
// Simulation turns a Scene into the stages it needs and runs them: only the effects the scene
// calls for get arrays and stages (a balls-only drum has no SPH anything), which memoryReport()
// and stages() make visible. Outputs go to RunOptions::out_dir (see docs/outputs.md).
#include <array>
#include <map>
#include <memory>
#include <string>
#include <vector>

#include "millsim/scene/scene.hpp"

namespace millsim::sim {

struct RunOptions {
  std::string out_dir = "out";
  std::string backend = "auto";    // auto | omp | cuda
  std::string precision = "double";  // double | float
  int threads = 0;                 // OpenMP threads, 0 = runtime default
  bool progress = false;           // progress line with ETA on stderr
  std::string restart;             // checkpoint to continue from
  bool write_outputs = true;       // false: no files (tests that only need numbers)
};

// Key results of a run (also written to OUT/summary.json).
struct RunSummary {
  std::string status = "not run";  // ok | failed
  std::string error;
  std::string backend, precision;
  int threads = 1;
  double wall_time_s = 0, simulated_time_s = 0, dt = 0;
  long long steps = 0, neighbour_rebuilds = 0;
  std::size_t particles = 0;
  double angle_of_repose_deg = 0, angle_stderr_deg = 0;
  int angle_frames = 0, angle_points = 0;
  bool angle_valid = false;
  std::string angle_error;  // why no angle could be measured (too few surface points, ...)
  double power_W = 0, torque_Nm = 0, omega_rad_s = 0;
  double energy_kinetic = 0, energy_potential = 0, energy_dissipated = 0, energy_work_in = 0, energy_elastic = 0;
  double energy_residual = 0;  // work_in - (dKE + dPE + elastic + dissipated)
  double charge_mass_kg = 0;
  // Wet mill (SPH-DEM): slurry particles, exclusions, SPH steps, and the slurry curve
  // y = c0 + c1 x + c2 x^2 (mm, front view, origin on the drum axis).
  std::size_t sph_particles = 0;
  long long sph_excluded = 0, sph_steps = 0;
  double slurry_kinetic = 0, slurry_potential = 0;  // of the slurry at the end, J
  int slurry_frames = 0;
  bool slurry_valid = false;
  std::array<double, 3> slurry_coef{};
  std::string slurry_error;
};

class SphRun;
class StirredRun;

class Simulation {
 public:
  Simulation(const scene::Scene& scene, const RunOptions& options);
  ~Simulation();
  Simulation(const Simulation&) = delete;
  Simulation& operator=(const Simulation&) = delete;

  // Runs to scene.time.end. Throws core::SimulationError on instability after writing the
  // failure into summary.json (the last checkpoint and all series rows already written stay).
  const RunSummary& run();

  std::vector<std::string> stages() const;
  std::map<std::string, std::size_t> memoryReport() const;
  const RunSummary& summary() const;
  double timeStep() const;
  std::size_t particleCount() const;

 private:
  struct Impl;
  std::unique_ptr<Impl> m_impl;     // balls (DEM) cases
  std::unique_ptr<SphRun> m_sph;    // fluid-only cases
  std::unique_ptr<StirredRun> m_stirred;  // stirred media mill cases (<stirrer>)
};

}  // namespace millsim::sim
