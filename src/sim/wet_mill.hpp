#pragma once
// The wet mill (paper's third stage): balls (DEM) and slurry (SPH) in one rotating drum,
// coupled both ways. Created when the drum starts (the charge has settled during compaction):
// the slurry is poured into the voids of the charge, the drum walls become moving boundary
// particles, and every ball carries a shell of body particles (sph::kBoundBody) so the fluid
// sees it; the summed fluid force and torque on each shell drive its ball (DEM external loads).
//
// Time stepping (SphDemCoupling): one SPH step of dt_sph (CFL) per advance(); inside it the DEM
// takes ceil(dt_sph / dt_dem) sub-steps with the fluid loads held fixed at the impulse the fluid
// gives up in that step (Verlet: from the step's start; symplectic: from the mid-step
// evaluation), then the shells are placed at the balls' new positions and the fluid step ends.
// Fluid and balls exchange equal and opposite momentum. Stable while a ball moves much less than
// dp per SPH step (v dt_sph << dp: 3 m/s x 5e-5 s = 0.15 mm against 5 mm).
//
// The slurry surface is measured as the paper measures it in its simulations (section 3.8.2):
// in the plane at mid-length, for each horizontal position the highest fluid particle, per
// frame; per position only the points between the median and Q3 over the frames are kept; a
// quadratic is fitted with its 95% band (vision::fitSlurryCurve, the code the videos use).
#include <filesystem>
#include <map>
#include <memory>
#include <string>
#include <vector>

#include "coupling/sph_dem_coupling.hpp"
#include "dem/dem_engine.hpp"
#include "millsim/io/fields_writer.hpp"
#include "millsim/io/plot_png.hpp"
#include "millsim/scene/scene.hpp"
#include "millsim/sim/simulation.hpp"
#include "millsim/vision/slurry_surface.hpp"
#include "sim/drum_motion.hpp"
#include "sph/sph_engine.hpp"

namespace millsim::sim {

class WetMill {
 public:
  WetMill(const scene::Scene& scene, const RunOptions& options, const dem::DemHostState& balls, double phi, double t);
  // From a checkpoint that save() wrote (file: its name, for errors), with the DEM's balls as
  // restored and the drum at angle phi turning at omega.
  WetMill(const scene::Scene& scene, const RunOptions& options, const io::CheckpointData& cp,
          const dem::DemHostState& balls, double phi, double omega, const std::string& file);
  // Adds the slurry's state (SPH restart state, surface frames) to a checkpoint.
  void save(io::CheckpointData& cp) const;
  static bool inCheckpoint(const io::CheckpointData& cp);

  // One coupled step; advances t, phi and the DEM step count.
  void advance(dem::DemEngine& dem, const DrumMotion& motion, double& t, double& phi, long long& dem_steps,
               double dt_dem);
  void captureSurface();
  // Slurry curve (OUT/slurry_curve.csv, slurry_points.csv, slurry_overlay.png) into the summary.
  void finish(const std::filesystem::path& out, RunSummary& summary, bool write);

  sph::SphSums sums() const { return m_engine->sums(); }
  void getFluidState(sph::SphHostState& s) const { m_engine->getState(s); }  // fluid, walls and shells
  std::map<std::string, std::size_t> memoryBytes() const { return m_engine->memoryBytes(); }
  std::vector<std::string> stages() const;
  std::size_t particles() const { return m_particles; }
  long long sphSteps() const { return m_steps; }
  double startTime() const { return m_t0; }

 private:
  sph::SphMotion motionAt(double phi, double omega) const { return {phi - m_phi0, omega}; }
  void setupSolver();
  void makeEngine(const RunOptions& options);
  void writeOverlay(const std::filesystem::path& path, const RunSummary& summary) const;

  scene::Scene m_scene;
  sph::SphSetup m_setup;
  std::unique_ptr<sph::SphEngine> m_engine;
  std::unique_ptr<coupling::SphDemCoupling> m_coupling;
  std::size_t m_particles = 0, m_balls = 0;
  long long m_fluid0 = 0, m_steps = 0;
  double m_phi0 = 0, m_t0 = 0;
  double m_hswl = 0;                            // still-water height of the pour (sets c0)
  std::vector<vision::SurfacePoint> m_surface;  // per frame, highest fluid per x bin (mm)
  int m_frames = 0;
  bool m_curve_valid = false;
  std::array<double, 3> m_curve{};
  double m_x_min_mm = 0, m_x_max_mm = 0;
  std::vector<io::PlotCurve> m_overlay_curves;
};

}  // namespace millsim::sim
