// Uses the installed library: parses the embedded default case, builds a tiny drum in code and
// runs it for 0.2 s, printing the energy it dissipated. Exit code 1 if nothing happened.
#include <cstdio>

#include "millsim/io/case_xml.hpp"
#include "millsim/sim/simulation.hpp"

int main() {
  millsim::scene::Scene scene = millsim::io::loadCaseText(millsim::io::defaultCaseXml(), "<embedded>");
  scene.drum.diameter = 0.1;
  scene.drum.length = 0.04;
  scene.drum.lifters.height = 0.003;
  scene.charge.count_override = 20;
  scene.charge.min_size = scene.charge.top_size = 0.01;
  scene.time.end = 0.2;
  scene.compaction.duration = 0.1;
  scene.drum.start_time = 0.1;
  scene.angle.enabled = false;
  millsim::sim::RunOptions options;
  options.write_outputs = false;
  millsim::sim::Simulation sim(scene, options);
  const auto& s = sim.run();
  std::printf("example: %zu balls, %lld steps, dissipated %.4g J\n", s.particles, s.steps, s.energy_dissipated);
  return s.steps > 0 && s.energy_dissipated > 0 ? 0 : 1;
}
