#pragma once
// The DEM particles' part of a checkpoint, shared by the drum runs (simulation.cpp) and the
// stirred mill (stirred_run.cpp): state, contact springs, the forces of the last step, and the
// per-particle energy accounts. The runs add their own scalars (time, angles, bookkeeping).
#include <cstdint>
#include <string>

#include "dem/dem_engine.hpp"
#include "millsim/io/fields_writer.hpp"

namespace millsim::sim {

// A checkpoint at (t, step) holding the engine's particles (DemEngine::getState); the caller adds
// its own part and writes it.
io::CheckpointData demCheckpoint(const dem::DemEngine& engine, double t, std::int64_t step);

// The state a checkpoint holds, for DemEngine::setState. Throws core::InputError naming `path`
// when an array every checkpoint has is missing; arrays added later restart from zero.
dem::DemHostState takeDemState(const io::CheckpointData& cp, const std::string& path);

}  // namespace millsim::sim
