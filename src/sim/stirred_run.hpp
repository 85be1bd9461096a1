#pragma once
// The time loop of a stirred media mill case (<stirrer>, seed 004): places the beads, runs the
// DEM engine with the stirrer's walls (and lubrication when <lubrication viscosity> > 0) through
// the speed program, and measures per speed level the shaft power (stirrer work / time), the
// stirrer and outer-wall torques, the net power, and over the run the energy budget, the
// collision typology by region and the coarse-grained velocity field. Outputs: series.csv,
// power.csv (+ power.png), collisions.csv, regions.csv, velocity_field.h5 (+ PNG maps),
// summary.json (docs/outputs.md).
#include <array>
#include <map>
#include <memory>
#include <string>
#include <vector>

#include "dem/dem_engine.hpp"
#include "millsim/scene/scene.hpp"
#include "millsim/sim/simulation.hpp"

namespace millsim::sim {

struct StirredLevel {
  double rpm = 0;
  double t_begin = 0, t_average = 0, t_end = 0;  // level starts (ramp), averaging window starts, ends
  double power_W = 0;                            // stirrer work over the window / its length
  double net_power_W = 0;                        // power_W - idle power
  double stirrer_torque_Nm = 0;                  // mean torque of the beads on the stirrer (motor torque = -this)
  double outer_torque_Nm = 0;                    // mean torque of the beads on the still chamber
  int samples = 0;
  // Steadiness: the stirrer's power over each half of the window. A bed started from rest needs
  // revolutions to dilate (the seed: 5-10 before its torque is steady); while it does, the
  // halves differ. steady: |second - first| <= kSteadyPowerChange of power_W.
  double t_mid = 0;
  double power_first_half_W = 0, power_second_half_W = 0;
  double revolutions_held = 0;  // rpm / 60 x hold
  bool steady = false;
  // The beads' kinetic energy when the window opened and closed: a bed still spinning up (or
  // down) changes it while the torque may already hold steady.
  double kinetic_open_J = 0, kinetic_close_J = 0;
};

inline constexpr double kSteadyPowerChange = 0.10;

// work_in = dKE + dPE + d(elastic) + contact dissipation + lubrication dissipation + residual.
struct StirredEnergy {
  double work_in = 0, d_kinetic = 0, d_potential = 0, d_elastic = 0;
  double contact_dissipated = 0, lubrication_dissipated = 0, residual = 0;
};

// 9 regions: radial 1 (inner) .. 3 (outer) in equal-area annuli, axial F (z < L/3), C, B
// (z > 2L/3, the drive side).
struct RegionStats {
  std::string name;  // "1F" .. "3B"
  double collisions = 0;
  double dissipated[dem::kModeCount] = {0, 0, 0, 0};
  double energy[dem::kModeCount] = {0, 0, 0, 0};
  double bead_samples = 0;  // beads counted in it over the samples
};

// Bead placement (host): `count` beads at random sites of an FCC lattice clear of every wall.
dem::DemHostState placeBeads(const scene::Scene& scene);
dem::StirrerState stirrerStateOf(const scene::Scene& scene, double omega, double phi);
std::vector<double> speedProgram(const scene::Scene& scene);  // rpm per level

class StirredRun {
 public:
  StirredRun(const scene::Scene& scene, const RunOptions& options);
  ~StirredRun();
  const RunSummary& run();
  std::vector<std::string> stages() const;
  std::map<std::string, std::size_t> memoryReport() const;
  const RunSummary& summary() const;
  double timeStep() const;
  std::size_t particleCount() const;
  double endTime() const;
  const std::vector<StirredLevel>& levels() const;
  const StirredEnergy& energy() const;
  const std::vector<RegionStats>& regions() const;
  const dem::StirredSums& finalSums() const;

 private:
  struct Impl;
  std::unique_ptr<Impl> m_impl;
};

}  // namespace millsim::sim
