#pragma once
// An in-process stand-in for MPI ranks: N threads, each holding a ThreadRank, whose collective
// calls meet at a barrier. Tests run the same code paths the MPI build runs (apps/millsim/
// mpi_ranks.cpp has the real one), without needing mpirun.
#include <condition_variable>
#include <functional>
#include <mutex>
#include <string>
#include <thread>
#include <vector>

#include "millsim/core/rank_group.hpp"

namespace millsim::testing {

class ThreadWorld {
 public:
  explicit ThreadWorld(int size) : m_size(size), m_slots(size) {}
  int size() const { return m_size; }

  // Collective step: every rank deposits its string, waits for all, and reads them all.
  std::vector<std::string> exchange(int rank, const std::string& mine) {
    std::unique_lock<std::mutex> lock(m_mutex);
    const long generation = m_generation;
    m_slots[rank] = mine;
    if (++m_arrived == m_size) {
      m_result = m_slots;
      m_arrived = 0;
      ++m_generation;
      m_cv.notify_all();
    } else {
      m_cv.wait(lock, [&] { return m_generation != generation; });
    }
    return m_result;
  }

 private:
  int m_size;
  std::vector<std::string> m_slots, m_result;
  int m_arrived = 0;
  long m_generation = 0;
  std::mutex m_mutex;
  std::condition_variable m_cv;
};

class ThreadRank final : public core::RankGroup {
 public:
  ThreadRank(ThreadWorld& world, int rank) : m_world(world), m_rank(rank) {}
  int rank() const override { return m_rank; }
  int size() const override { return m_world.size(); }
  std::vector<std::string> allGather(const std::string& mine) const override { return m_world.exchange(m_rank, mine); }
  std::string broadcast(const std::string& text) const override { return m_world.exchange(m_rank, text)[0]; }

 private:
  ThreadWorld& m_world;
  int m_rank;
};

// Runs body(rank_group) on `size` threads, one rank each; returns when all are done.
inline void runOnRanks(int size, const std::function<void(const core::RankGroup&)>& body) {
  ThreadWorld world(size);
  std::vector<std::thread> threads;
  for (int r = 0; r < size; ++r)
    threads.emplace_back([&world, &body, r] {
      ThreadRank rank(world, r);
      body(rank);
    });
  for (auto& t : threads) t.join();
}

}  // namespace millsim::testing
