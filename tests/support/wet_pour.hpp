#pragma once
// The wet mill's coupled step from a given charge, on a chosen backend (tests/gpu: CUDA against
// OpenMP). The charge of a wet case is packed once (compaction on OpenMP, double), then each run
// pours the slurry into that same charge (sim::WetMill, what `millsim run` does when the drum
// starts) and takes `steps` coupled steps (an SPH step with its DEM sub-steps), so two runs differ
// only by the backend's arithmetic (summation order, FMA, atomics), not by a packing that chaos
// has already spread apart (float and double packings of wet_drum_small differ by 4% in the
// dissipated energy after its 0.6 s of compaction).
#include <omp.h>

#include <memory>
#include <string>
#include <vector>

#include "dem/dem_engine.hpp"
#include "millsim/io/case_xml.hpp"
#include "sim/charge_setup.hpp"
#include "sim/drum_motion.hpp"
#include "sim/drum_setup.hpp"
#include "sim/engine_factory.hpp"
#include "sim/wet_mill.hpp"
#include "sph/sph_pair.hpp"

namespace millsim::testing {

struct PackedCharge {
  scene::Scene scene;
  sim::ChargeSetup charge;
  dem::DemHostState balls;  // at the drum's start
  double t = 0, phi = 0;
};

inline PackedCharge packCharge(const std::string& case_file, const std::vector<std::string>& overrides) {
  PackedCharge p;
  p.scene = io::loadCaseFile(case_file, overrides);
  p.charge = sim::buildCharge(p.scene);
  const sim::DrumMotion motion(p.scene, p.charge.generation_length, sim::drumSpeedRpm(p.scene, p.charge));
  const double dt = sim::drumTimeStep(p.scene, p.charge);
  sim::RunOptions options;
  options.backend = "omp";
  auto dem = sim::makeDemEngine(sim::drumDemSetup(p.scene, p.charge), options);
  dem->setState(p.charge.state);
  dem->initialize(motion.at(0, 0));
  while (p.t < p.scene.drum.start_time - 0.5 * dt) {
    motion.stepDem(*dem, p.t, p.phi, dt);
  }
  p.balls = dem::ballStates(*dem);
  return p;
}

struct PourResult {
  std::vector<double> ball_pos;   // x, y, z per ball
  std::vector<double> fluid_pos;  // x, y, z per fluid particle, in the order of the pour
  double slurry_kinetic = 0, ball_kinetic = 0;
  long long sph_steps = 0;
};

// `steps` coupled steps after the pour; backend "omp" (on `threads` threads) or "cuda".
inline PourResult pourAndStep(const PackedCharge& p, const std::string& backend, int steps, int threads = 0) {
  sim::RunOptions options;
  options.backend = backend;
  options.precision = "double";
  options.write_outputs = false;
  if (threads > 0) omp_set_num_threads(threads);
  const sim::DrumMotion motion(p.scene, p.charge.generation_length, sim::drumSpeedRpm(p.scene, p.charge));
  const double dt = sim::drumTimeStep(p.scene, p.charge);
  auto dem = sim::makeDemEngine(sim::drumDemSetup(p.scene, p.charge), options);
  dem->setState(p.balls);
  double t = p.t, phi = p.phi;
  dem->initialize(motion.at(t, phi));
  sim::WetMill wet(p.scene, options, p.balls, phi, t);
  long long dem_steps = 0;
  for (int k = 0; k < steps; ++k) wet.advance(*dem, motion, t, phi, dem_steps, dt);
  PourResult r;
  r.ball_pos = dem::ballStates(*dem).pos;
  sph::SphHostState s;
  wet.getFluidState(s);
  for (std::size_t i = 0; i < s.size(); ++i)
    if (s.code[i] == sph::kFluid)
      r.fluid_pos.insert(r.fluid_pos.end(), {s.pos[3 * i], s.pos[3 * i + 1], s.pos[3 * i + 2]});
  r.slurry_kinetic = wet.sums().kinetic;
  r.ball_kinetic = dem->sums().kinetic;
  r.sph_steps = wet.sphSteps();
  return r;
}

}  // namespace millsim::testing
