#pragma once
// What a balls-only drum case asks of the DEM, from its scene and charge: the time step, the
// solver's setup (contact law, skin, domain), the drum speed and the front view's angle options.
// Shared by the single run (simulation.cpp) and the ensemble (ensemble_run.cpp), so both read a
// case the same way.
#include <filesystem>
#include <string>
#include <vector>

#include "dem/dem_engine.hpp"
#include "millsim/scene/scene.hpp"
#include "millsim/sim/simulation.hpp"
#include "millsim/vision/angle_of_repose.hpp"
#include "millsim/vision/front_view_angle.hpp"
#include "sim/charge_setup.hpp"

namespace millsim::sim {

// The contact law's part of a DEM setup from <dem> (stiffness, damping for the restitution,
// friction), shared by the drum and the stirred mill.
dem::DemSetup demContactSetup(const scene::Scene& scene);
// dt: the fixed one, or the shortest Hertz contact time / dt_divisor.
double drumTimeStep(const scene::Scene& scene, const ChargeSetup& charge);
// The DEM setup of the case, its domain around the generation drum.
dem::DemSetup drumDemSetup(const scene::Scene& scene, const ChargeSetup& charge);
// Drum speed in rpm (a fraction of critical, or as given).
double drumSpeedRpm(const scene::Scene& scene, const ChargeSetup& charge);
vision::AngleOptions drumAngleOptions(const scene::Scene& scene);

// series.csv of a drum run: its columns, and one row from the sums now and the drum's state.
std::vector<std::string> drumSeriesColumns();
std::vector<double> drumSeriesRow(double t, const dem::DemSums& now, const dem::DrumState& drum, double residual);
// The summary's energies now, and the budget's residual since `start`:
// work in (walls and external loads) - (dKE + dPE + d elastic + dissipated).
void fillDrumEnergy(RunSummary& s, const dem::DemSums& now, const dem::DemSums& start);
// The angle of repose from the frames into the summary (or why none could be measured), and
// the front-view images into `out` when `write`.
void finishDrumAngle(const vision::FrontViewAngle& angle, RunSummary& s, const std::filesystem::path& out, bool write);
// Throws core::SimulationError naming `label` and the ball when a ball of host numbers [lo, hi)
// in `pos` (3 per ball, its drum's front plate at z = z0) is outside its drum.
void checkBallsInDrum(const std::vector<double>& pos, int lo, int hi, double z0, const scene::Scene& scene,
                      const ChargeSetup& charge, double t, const std::string& label);

}  // namespace millsim::sim
