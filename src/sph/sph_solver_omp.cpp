// OpenMP instantiations of the one SPH solver template (2D and 3D, double and float).
#include "sph/sph_solver.hpp"

namespace millsim::sph {

std::unique_ptr<SphEngine> makeSphEngineOmp(const SphSetup& setup, bool single_precision) {
  if (single_precision) {
    if (setup.dimension == 2) return std::make_unique<SphSolver<backend::Omp, float, 2>>(setup);
    return std::make_unique<SphSolver<backend::Omp, float, 3>>(setup);
  }
  if (setup.dimension == 2) return std::make_unique<SphSolver<backend::Omp, double, 2>>(setup);
  return std::make_unique<SphSolver<backend::Omp, double, 3>>(setup);
}

}  // namespace millsim::sph
