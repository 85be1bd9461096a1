#include "mpi_ranks.hpp"

#include <cstdio>
#include <cstdlib>
#include <stdexcept>

#include "millsim/backend/info.hpp"

#ifdef MILLSIM_HAVE_MPI
#include <mpi.h>
#endif

namespace millsim::cli {

namespace {

const MpiSession* g_session = nullptr;

#ifdef MILLSIM_HAVE_MPI
// Launchers leave these in the environment of every process they start: Open MPI's mpirun,
// MPICH/Hydra and PMIx-based ones (srun --mpi=pmix).
bool launchedByMpi() {
  for (const char* v : {"OMPI_COMM_WORLD_SIZE", "PMI_SIZE", "PMIX_RANK", "MPI_LOCALNRANKS"})
    if (std::getenv(v)) return true;
  return false;
}

void check(int rc, const char* what) {
  if (rc != MPI_SUCCESS) throw std::runtime_error(std::string("MPI: ") + what + " failed");
}

class MpiRanks final : public core::RankGroup {
 public:
  MpiRanks() {
    MPI_Comm_rank(MPI_COMM_WORLD, &m_rank);
    MPI_Comm_size(MPI_COMM_WORLD, &m_size);
  }
  int rank() const override { return m_rank; }
  int size() const override { return m_size; }

  std::vector<std::string> allGather(const std::string& mine) const override {
    int len = static_cast<int>(mine.size());
    std::vector<int> lens(m_size), offsets(m_size);
    check(MPI_Allgather(&len, 1, MPI_INT, lens.data(), 1, MPI_INT, MPI_COMM_WORLD), "MPI_Allgather");
    int total = 0;
    for (int r = 0; r < m_size; ++r) {
      offsets[r] = total;
      total += lens[r];
    }
    std::string all(static_cast<std::size_t>(total), '\0');
    check(MPI_Allgatherv(mine.data(), len, MPI_CHAR, all.data(), lens.data(), offsets.data(), MPI_CHAR, MPI_COMM_WORLD),
          "MPI_Allgatherv");
    std::vector<std::string> out;
    for (int r = 0; r < m_size; ++r) out.push_back(all.substr(offsets[r], lens[r]));
    return out;
  }

  std::string broadcast(const std::string& text) const override {
    int len = static_cast<int>(text.size());
    check(MPI_Bcast(&len, 1, MPI_INT, 0, MPI_COMM_WORLD), "MPI_Bcast");
    std::string out = m_rank == 0 ? text : std::string(static_cast<std::size_t>(len), '\0');
    check(MPI_Bcast(out.data(), len, MPI_CHAR, 0, MPI_COMM_WORLD), "MPI_Bcast");
    return out;
  }

 private:
  int m_rank = 0, m_size = 1;
};
#endif

}  // namespace

MpiSession::MpiSession(int* argc, char*** argv) {
#ifdef MILLSIM_HAVE_MPI
  if (!launchedByMpi()) return;
  // Only the main thread calls MPI; worker threads (--parallel) and OpenMP run simulations.
  int provided = 0;
  check(MPI_Init_thread(argc, argv, MPI_THREAD_FUNNELED, &provided), "MPI_Init_thread");
  m_initialised = true;
  m_ranks = std::make_unique<MpiRanks>();
  // One GPU per rank of a node: the launcher's node-local rank picks it (round robin when a
  // node has more ranks than GPUs). Without CUDA or a GPU this does nothing.
  for (const char* v : {"OMPI_COMM_WORLD_LOCAL_RANK", "MPI_LOCALRANKID", "SLURM_LOCALID"})
    if (const char* local = std::getenv(v)) {
      backend::selectCudaDevice(std::atoi(local));
      break;
    }
#else
  (void)argc;
  (void)argv;
  // Started by mpirun without MPI in the build: every process would run the whole command.
  for (const char* v : {"OMPI_COMM_WORLD_SIZE", "PMI_SIZE", "PMIX_RANK"})
    if (std::getenv(v)) {
      std::fprintf(stderr,
                   "millsim: warning: started by an MPI launcher, but this build has no MPI (MILLSIM_MPI): "
                   "each process runs the whole command\n");
      break;
    }
#endif
}

MpiSession::~MpiSession() {
#ifdef MILLSIM_HAVE_MPI
  if (m_initialised) MPI_Finalize();
#endif
}

bool mpiCompiled() {
#ifdef MILLSIM_HAVE_MPI
  return true;
#else
  return false;
#endif
}

void MpiSession::abortAll(int code) const {
#ifdef MILLSIM_HAVE_MPI
  if (m_ranks && m_ranks->size() > 1) MPI_Abort(MPI_COMM_WORLD, code);
#else
  (void)code;
#endif
}

const MpiSession& mpiSession() {
  static const MpiSession none;
  return g_session ? *g_session : none;
}

void setMpiSession(const MpiSession* session) { g_session = session; }

}  // namespace millsim::cli
