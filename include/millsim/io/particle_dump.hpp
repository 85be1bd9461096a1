#pragma once
// Reader for LAMMPS/LIGGGHTS text dumps (`dump custom ... id x y z radius`), so another code's
// particle positions can go through millsim's own angle-of-repose pipeline (cross-code checks).
#include <cstdint>
#include <string>
#include <vector>

namespace millsim::io {

struct ParticleFrame {
  std::int64_t timestep = 0;
  std::vector<double> x, y, z, radius;
};

// All frames of one dump file (a file may hold several timesteps). Needs the columns x, y, z and
// radius (or diameter) in the "ITEM: ATOMS" header; errors name the file and line.
std::vector<ParticleFrame> readParticleDump(const std::string& path);

}  // namespace millsim::io
