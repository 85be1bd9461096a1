#pragma once
// Scene -> SPH solver set-up and particles (fluid boxes, tanks, probes): the part of a fluid
// run that needs no output code, so benchmarks and tests link it without the writers.
#include <array>
#include <string>
#include <vector>

#include "millsim/scene/scene.hpp"
#include "sph/sph_engine.hpp"

namespace millsim::sim {

struct Probe {
  std::string name;
  std::array<double, 3> x{};
};

// "name:x,y[,z];..." -> probes; throws InputError naming the case and what is wrong.
std::vector<Probe> parseProbes(const scene::Scene& scene);

double gravityNorm(const scene::Scene& scene);
// Line of an element in the case file (0 when it came from --set or the defaults).
int lineOf(const scene::Scene& scene, const std::string& element);

// Everything <sph> says (h, c0 from still_water_height unless sph.hswl is given, limits,
// options), without the domain: shared by fluid-only runs and the wet mill.
sph::SphSetup sphSolverSetup(const scene::Scene& scene, double still_water_height);
// DBC layers: sph.boundary_layers, or ceil(2h / dp).
int boundaryLayers(const scene::Scene& scene, const sph::SphSetup& setup);

// The solver set-up a scene asks for (h, c0, layers, domain resolved), and its particles.
sph::SphSetup sphSetupOf(const scene::Scene& scene);
sph::SphHostState sphParticlesOf(const scene::Scene& scene, const sph::SphSetup& setup);

}  // namespace millsim::sim
