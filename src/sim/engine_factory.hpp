#pragma once
// The engines a run asks for, from --backend (auto: CUDA when a device is present, else OpenMP)
// and --precision, resolved the same way for every solver: balls, stirred beads, fluid, and both
// halves of the wet mill (which must sit on the same backend).
#include <memory>

#include "dem/dem_engine.hpp"
#include "millsim/sim/simulation.hpp"
#include "sph/sph_engine.hpp"

namespace millsim::sim {

struct EngineChoice {
  bool cuda = false;
  bool single = false;  // float
};

// Throws core::InputError for an unknown backend or precision, for cuda without a CUDA build or
// without a device.
EngineChoice engineChoice(const RunOptions& options);

std::unique_ptr<dem::DemEngine> makeDemEngine(const dem::DemSetup& setup, const RunOptions& options);
std::unique_ptr<sph::SphEngine> makeSphEngine(const sph::SphSetup& setup, const RunOptions& options);

}  // namespace millsim::sim
