#include "millsim/core/rank_group.hpp"

#include <nlohmann/json.hpp>
#include <stdexcept>
#include <thread>

namespace millsim::core {

void runWorkers(int threads, const std::function<void()>& worker) {
  if (threads <= 1) {
    worker();
    return;
  }
  std::vector<std::thread> pool;
  for (int t = 0; t < threads; ++t) pool.emplace_back(worker);
  for (auto& t : pool) t.join();
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
