#pragma once
// The three small drums the ensemble tests share (tests/validation/test_drum_ensemble.cpp on
// the CPU, tests/gpu/test_ensemble_cuda_vs_omp.cpp CUDA vs OpenMP), as --set lists over
// cases/minimal_drum.xml: the case as shipped; a wider, longer drum with larger balls (12 mm: a
// longer automatic time step, 1.2x fewer steps, so it rests while the others finish), another
// charge, restitution and friction; a faster drum with more balls and three lifters. Each case
// steps by its own automatic dt. The window is 0.05 s of compaction (the pistons push the
// charges in) and 0.07 s of rotation: the energies of two correct runs whose sums differ only
// in order drift apart exponentially (measured with two ensembles of the same cases in
// different orders, relative to the work put in: 5e-12 at t = 0.1 s, 4e-8 at 0.15 s, 1e-6 at
// 0.2 s, 6e-5 at 0.3 s), so a longer window would test the chaos of a granular bed, not the
// ensemble; 1e-6 of the work separates summation order from error.
#include <cstdlib>
#include <string>
#include <vector>

namespace millsim::testing {

// cases/NAME.xml of the tree the test runs in (MILLSIM_SOURCE_DIR from the environment on a
// copied tree, e.g. the GPU machine).
inline std::string sourceCase(const std::string& name) {
  const char* env = std::getenv("MILLSIM_SOURCE_DIR");
  return std::string(env ? env : MILLSIM_SOURCE_DIR) + "/cases/" + name + ".xml";
}

inline std::string minimalDrumCase() { return sourceCase("minimal_drum"); }

inline std::vector<std::vector<std::string>> ensembleTestDrums() {
  const std::vector<std::string> common{"time.end=0.12", "compaction.duration=0.05", "drum.start_time=0.05",
                                        "output.fields_every=0", "output.checkpoint_every=0"};
  std::vector<std::vector<std::string>> v(3, common);
  v[1].insert(v[1].end(),
              {"drum.diameter=0.12", "drum.length=0.05", "charge.seed=2", "charge.count=20", "charge.top_size=0.012",
               "charge.min_size=0.012", "dem.restitution=0.6", "dem.friction=0.3"});
  v[2].insert(v[2].end(), {"drum.critical_fraction=0.6", "charge.count=24", "charge.seed=3", "drum.lifters.count=3",
                           "dem.restitution=0.2", "dem.friction=0.7"});
  return v;
}

}  // namespace millsim::testing
