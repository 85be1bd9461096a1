// CUDA instantiations of the one SPH solver template: the same functors as the OpenMP build.
#include "millsim/backend/cuda.cuh"
#include "sph/sph_solver.hpp"

namespace millsim::sph {

std::unique_ptr<SphEngine> makeSphEngineCuda(const SphSetup& setup, bool single_precision) {
  if (single_precision) {
    if (setup.dimension == 2) return std::make_unique<SphSolver<backend::Cuda, float, 2>>(setup);
    return std::make_unique<SphSolver<backend::Cuda, float, 3>>(setup);
  }
  if (setup.dimension == 2) return std::make_unique<SphSolver<backend::Cuda, double, 2>>(setup);
  return std::make_unique<SphSolver<backend::Cuda, double, 3>>(setup);
}

}  // namespace millsim::sph
