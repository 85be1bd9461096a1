#pragma once
// The time loop of a fluid-only case (tanks, dam breaks): builds the particles from the scene,
// runs the SPH engine with the variable (CFL) or fixed time step, and writes series.csv (front,
// energies, probe pressures, exclusions), fields (.h5 + .xdmf) and summary.json.
#include <array>
#include <map>
#include <memory>
#include <string>
#include <vector>

#include "millsim/scene/scene.hpp"
#include "millsim/sim/simulation.hpp"
#include "sim/sph_setup.hpp"
#include "sph/sph_engine.hpp"

namespace millsim::sim {

class SphRun {
 public:
  SphRun(const scene::Scene& scene, const RunOptions& options);
  const RunSummary& run();
  std::vector<std::string> stages() const;
  std::map<std::string, std::size_t> memoryReport() const { return m_engine->memoryBytes(); }
  const RunSummary& summary() const { return m_summary; }
  std::size_t particleCount() const { return m_particles; }
  double timeStep() const { return m_engine->nextDt(); }

 private:
  sph::SphMotion motionAt(double t) const;
  void writeSummary(const sph::SphSums& now, const std::vector<double>& last_probe) const;

  scene::Scene m_scene;
  RunOptions m_options;
  sph::SphSetup m_setup;
  std::unique_ptr<sph::SphEngine> m_engine;
  std::vector<Probe> m_probes;
  RunSummary m_summary;
  std::size_t m_particles = 0;
  long long m_fluid0 = 0;
  double m_fluid_mass0 = 0;
  double m_omega_full = 0;
};

}  // namespace millsim::sim
