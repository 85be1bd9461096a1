#include "millsim/core/rank_group.hpp"

#include <algorithm>
#include <atomic>
#include <mutex>
#include <nlohmann/json.hpp>
#include <stdexcept>
#include <thread>

namespace millsim::core {

std::exception_ptr forEachItem(std::size_t count, int threads, const std::function<void(std::size_t)>& body) {
  std::atomic<std::size_t> next{0};
  std::atomic<bool> stop{false};
  std::mutex mutex;
  std::exception_ptr failure;
  const auto worker = [&]() {
    for (std::size_t k = next++; k < count && !stop; k = next++) {
      try {
        body(k);
      } catch (...) {
        std::lock_guard<std::mutex> lock(mutex);
        if (!failure) failure = std::current_exception();
        stop = true;
      }
    }
  };
  const int n = static_cast<int>(std::min<std::size_t>(static_cast<std::size_t>(std::max(threads, 1)), count));
  if (n <= 1) {
    worker();
  } else {
    std::vector<std::thread> pool;
    for (int t = 0; t < n; ++t) pool.emplace_back(worker);
    for (auto& t : pool) t.join();
  }
  return failure;
}

GatheredShares gatherShares(const RankGroup& ranks, const std::string& payload, std::exception_ptr failure) {
  std::string message;
  if (failure) try {
      std::rethrow_exception(failure);
    } catch (const std::exception& e) {
      message = e.what();
    } catch (...) {
      message = "unknown error";
    }
  GatheredShares out;
  const std::vector<std::string> shares =
      ranks.allGather(nlohmann::json{{"payload", payload}, {"failure", message}}.dump(
          -1, ' ', false, nlohmann::json::error_handler_t::replace));  // a message need not be UTF-8
  for (std::size_t r = 0; r < shares.size(); ++r) {
    const nlohmann::json j = nlohmann::json::parse(shares[r]);
    out.payloads.push_back(j.at("payload").get<std::string>());
    const std::string f = j.at("failure").get<std::string>();
    if (!f.empty() && out.failure.empty()) out.failure = "rank " + std::to_string(r) + ": " + f;
  }
  return out;
}

void throwIfAnyRankFailed(const GatheredShares& shares, std::exception_ptr own_failure) {
  if (own_failure) std::rethrow_exception(own_failure);
  if (!shares.failure.empty()) throw std::runtime_error(shares.failure);
}

}  // namespace millsim::core
