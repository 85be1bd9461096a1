// CUDA instantiations of the one DEM solver template: the same functors as the OpenMP build.
#include "backend/cuda/partner_scatter_cuda.cuh"
#include "millsim/backend/cuda.cuh"
#include "dem/dem_solver.hpp"

namespace millsim::dem {

std::unique_ptr<DemEngine> makeDemEngineCuda(const DemSetup& setup, bool single_precision) {
  if (single_precision) return std::make_unique<DemSolver<backend::Cuda, float>>(setup);
  return std::make_unique<DemSolver<backend::Cuda, double>>(setup);
}

}  // namespace millsim::dem
