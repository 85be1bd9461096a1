#pragma once
// MPI for the CLI: `mpirun -np N millsim calibrate|sweep ...` spreads independent simulations
// over the ranks (docs/cluster.md). MPI is initialised only when the process was started by an
// MPI launcher (its environment says so), so a plain `millsim run` never touches MPI, and a
// build without MPI (MILLSIM_MPI=OFF or no libopenmpi-dev) runs everything on one rank.
#include <memory>

#include "millsim/core/rank_group.hpp"

namespace millsim::cli {

class MpiSession {
 public:
  MpiSession() = default;               // one process, no MPI
  MpiSession(int* argc, char*** argv);  // MPI_Init when launched by mpirun/srun, else nothing
  ~MpiSession();                        // MPI_Finalize when initialised
  MpiSession(const MpiSession&) = delete;
  MpiSession& operator=(const MpiSession&) = delete;

  // The ranks of MPI_COMM_WORLD; nullptr when MPI is not running (one process).
  const core::RankGroup* ranks() const { return m_ranks.get(); }
  // Rank 0, or the only process: the one that prints and writes the shared outputs.
  bool leader() const { return !m_ranks || m_ranks->rank() == 0; }
  // After an error on one rank: stops every rank (the others may wait in a collective call)
  // with `code`. Without MPI, or on one rank, it returns and the caller exits normally.
  void abortAll(int code) const;

 private:
  std::unique_ptr<core::RankGroup> m_ranks;
  bool m_initialised = false;
};

// Whether this build has MPI (MILLSIM_MPI found Open MPI or another implementation).
bool mpiCompiled();

// The process's session (set by main before any command runs).
const MpiSession& mpiSession();
void setMpiSession(const MpiSession* session);

}  // namespace millsim::cli
