#pragma once
// The processes one job is spread over (MPI ranks under `mpirun -np N millsim ...`), as the
// library sees them: independent simulations are dealt out by rank and their results gathered
// back as strings (the callers serialise). The library itself has no MPI dependency: the CLI
// provides the MPI implementation (apps/millsim/mpi_ranks.cpp) when built with MPI, and
// everything works on one rank without it.
#include <exception>
#include <functional>
#include <string>
#include <vector>

namespace millsim::core {

class RankGroup {
 public:
  virtual ~RankGroup() = default;
  virtual int rank() const = 0;
  virtual int size() const = 0;
  // Collective: every rank passes its own string; every rank gets all of them, by rank.
  virtual std::vector<std::string> allGather(const std::string& mine) const = 0;
  // Collective: rank 0's `text` on every rank (what the other ranks pass is ignored).
  virtual std::string broadcast(const std::string& text) const = 0;
};

// Work item k belongs to rank k mod size (round robin: neighbouring items, often of similar
// cost, go to different ranks).
inline bool ownsItem(const RankGroup* ranks, int k) { return !ranks || k % ranks->size() == ranks->rank(); }

// Calls body(k) for k = 0 .. count-1 on up to `threads` threads (on the calling thread when
// threads <= 1), handing out items in order. The first exception a body throws stops the
// hand-out of further items and is returned once all threads are done (null when none threw).
// Bodies guard what they share themselves.
std::exception_ptr forEachItem(std::size_t count, int threads, const std::function<void(std::size_t)>& body);

// Collective: every rank's `payload` (its results of a batch), on every rank, by rank. Every
// rank takes part even when its own work failed (`failure` set), so none waits for ever.
struct GatheredShares {
  std::vector<std::string> payloads;
  std::string failure;  // "rank R: message" of the first rank that failed; empty when none did
};
GatheredShares gatherShares(const RankGroup& ranks, const std::string& payload, std::exception_ptr failure);

// After the gathered results are stored: the failing rank rethrows its own exception, every
// other rank a std::runtime_error with the first failure's message; nothing when none failed.
void throwIfAnyRankFailed(const GatheredShares& shares, std::exception_ptr own_failure);

}  // namespace millsim::core
