#include "sim/engine_factory.hpp"

#include "millsim/backend/info.hpp"
#include "millsim/core/error.hpp"

namespace millsim::sim {

EngineChoice engineChoice(const RunOptions& options) {
  if (options.precision != "double" && options.precision != "float")
    throw core::InputError("--precision " + options.precision + ": expected double or float");
  EngineChoice c;
  c.single = options.precision == "float";
  std::string backend = options.backend;
  if (backend == "auto") backend = backend::cudaDevices() > 0 ? "cuda" : "omp";
  if (backend == "cuda") {
#if defined(MILLSIM_HAVE_CUDA)
    if (backend::cudaDevices() == 0) throw core::InputError("--backend cuda: no CUDA device found on this machine");
    c.cuda = true;
#else
    throw core::InputError("--backend cuda: this millsim was built without CUDA (MILLSIM_CUDA=OFF or no nvcc)");
#endif
  } else if (backend != "omp") {
    throw core::InputError("--backend " + backend + ": expected auto, omp or cuda");
  }
  return c;
}

std::unique_ptr<dem::DemEngine> makeDemEngine(const dem::DemSetup& setup, const RunOptions& options) {
  const EngineChoice c = engineChoice(options);
#if defined(MILLSIM_HAVE_CUDA)
  if (c.cuda) return dem::makeDemEngineCuda(setup, c.single);
#endif
  return dem::makeDemEngineOmp(setup, c.single);
}

std::unique_ptr<sph::SphEngine> makeSphEngine(const sph::SphSetup& setup, const RunOptions& options) {
  const EngineChoice c = engineChoice(options);
#if defined(MILLSIM_HAVE_CUDA)
  if (c.cuda) return sph::makeSphEngineCuda(setup, c.single);
#endif
  return sph::makeSphEngineOmp(setup, c.single);
}

}  // namespace millsim::sim
