// OpenMP instantiations of the one DEM solver template.
#include "dem/dem_solver.hpp"

namespace millsim::dem {

std::unique_ptr<DemEngine> makeDemEngineOmp(const DemSetup& setup, bool single_precision) {
  if (single_precision) return std::make_unique<DemSolver<backend::Omp, float>>(setup);
  return std::make_unique<DemSolver<backend::Omp, double>>(setup);
}

}  // namespace millsim::dem
