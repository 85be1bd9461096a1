// The calibration loop: initial design, proposals, stop rule, parallel batches, journal.
#include "millsim/calib/calibrator.hpp"

#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdint>
#include <cstring>
#include <exception>
#include <mutex>
#include <nlohmann/json.hpp>
#include <set>
#include <stdexcept>

#include "millsim/calib/initial_design.hpp"
#include "millsim/core/rank_group.hpp"

namespace millsim::calib {

Calibrator::Calibrator(const Objective& objective, CalibrationOptions options)
    : m_objective(objective), m_options(std::move(options)) {
  const CalibrationOptions& o = m_options;
  if (o.initial < 3) throw std::invalid_argument("initial candidates must be >= 3 (a plane needs three points)");
  if (o.patience < 1) throw std::invalid_argument("patience must be >= 1");
  if (o.max_evals < o.initial) throw std::invalid_argument("max-evals must be >= the initial candidates");
  if (o.parallel < 1) throw std::invalid_argument("parallel must be >= 1");
  if (!(o.box.e_min < o.box.e_max) || !(o.box.mu_min < o.box.mu_max))
    throw std::invalid_argument("empty parameter range (need min < max)");
  m_proposer = makeProposer(o.method, o.search);
}

void Calibrator::updateState(CalibrationState& state, int initial) {
  std::stable_sort(state.evaluations.begin(), state.evaluations.end(),
                   [](const Evaluation& a, const Evaluation& b) { return a.candidate.index < b.candidate.index; });
  state.best = -1;
  state.since_improvement = 0;
  for (std::size_t i = 0; i < state.evaluations.size(); ++i) {
    const Evaluation& ev = state.evaluations[i];
    const bool better = ev.ok && (state.best < 0 || ev.sse < state.evaluations[state.best].sse);
    if (better) state.best = static_cast<int>(i);
    if (ev.candidate.index < initial) continue;
    state.since_improvement = better ? 0 : state.since_improvement + 1;
  }
}

std::vector<DataPoint> Calibrator::data(const std::vector<Evaluation>& evaluations) const {
  std::vector<DataPoint> d;
  for (const Evaluation& ev : evaluations)
    if (ev.ok) d.push_back({m_options.box.toUnit(ev.candidate.e, ev.candidate.mu), ev.sse});
  return d;
}

namespace {

// Evaluations and candidates between ranks: JSON with every double as its 64-bit pattern, so a
// value (NaN for a failed run's angle included) arrives bit for bit and every rank takes the
// same decisions from it.
std::uint64_t bits(double x) {
  std::uint64_t u;
  std::memcpy(&u, &x, sizeof u);
  return u;
}
double fromBits(std::uint64_t u) {
  double x;
  std::memcpy(&x, &u, sizeof x);
  return x;
}

nlohmann::json candidateJson(const Candidate& c) { return {c.index, bits(c.e), bits(c.mu)}; }
Candidate candidateFrom(const nlohmann::json& j) {
  return {j.at(0).get<int>(), fromBits(j.at(1).get<std::uint64_t>()), fromBits(j.at(2).get<std::uint64_t>())};
}

std::string encodeCandidates(const std::vector<Candidate>& cs) {
  nlohmann::json j = nlohmann::json::array();
  for (const Candidate& c : cs) j.push_back(candidateJson(c));
  return j.dump();
}
std::vector<Candidate> decodeCandidates(const std::string& text) {
  std::vector<Candidate> cs;
  for (const auto& c : nlohmann::json::parse(text)) cs.push_back(candidateFrom(c));
  return cs;
}

std::string encodeEvaluations(const std::vector<Evaluation>& evs) {
  nlohmann::json list = nlohmann::json::array();
  for (const Evaluation& ev : evs) {
    nlohmann::json angles = nlohmann::json::array();
    for (double a : ev.angles_deg) angles.push_back(bits(a));
    list.push_back({{"c", candidateJson(ev.candidate)},
                    {"a", angles},
                    {"sse", bits(ev.sse)},
                    {"ok", ev.ok},
                    {"error", ev.error},
                    {"wall", bits(ev.wall_s)}});
  }
  return list.dump(-1, ' ', false, nlohmann::json::error_handler_t::replace);  // error texts need not be UTF-8
}
std::vector<Evaluation> decodeEvaluations(const std::string& text) {
  std::vector<Evaluation> evs;
  for (const auto& e : nlohmann::json::parse(text)) {
    Evaluation ev;
    ev.candidate = candidateFrom(e.at("c"));
    for (const auto& a : e.at("a")) ev.angles_deg.push_back(fromBits(a.get<std::uint64_t>()));
    ev.sse = fromBits(e.at("sse").get<std::uint64_t>());
    ev.ok = e.at("ok").get<bool>();
    ev.error = e.at("error").get<std::string>();
    ev.wall_s = fromBits(e.at("wall").get<std::uint64_t>());
    evs.push_back(std::move(ev));
  }
  return evs;
}

}  // namespace

CalibrationResult Calibrator::run(Journal* journal, const ProgressCallback& progress) {
  const auto wall0 = std::chrono::steady_clock::now();
  const CalibrationOptions& o = m_options;
  CalibrationResult result;
  CalibrationState& state = result.state;
  // Several ranks (MPI): rank 0 owns the journal and decides every batch; each rank simulates
  // its share of a batch, and all ranks gather all results, so their states stay identical.
  const core::RankGroup* ranks = o.ranks && o.ranks->size() > 1 ? o.ranks : nullptr;
  std::vector<Evaluation> loaded = journal ? journal->loaded() : std::vector<Evaluation>{};
  if (ranks) loaded = decodeEvaluations(ranks->broadcast(encodeEvaluations(loaded)));
  std::set<int> done;
  for (const Evaluation& ev : loaded)
    if (done.insert(ev.candidate.index).second) state.evaluations.push_back(ev);
  state.resumed = static_cast<int>(state.evaluations.size());
  updateState(state, o.initial);

  std::mutex mutex;
  // One finished evaluation: journalled, stored, the stop-rule state updated, reported.
  const auto record = [&](const Evaluation& ev) {
    if (journal) journal->append(ev);
    state.evaluations.push_back(ev);
    ++state.evaluated;
    updateState(state, o.initial);
    if (progress) progress(ev, state);
  };
  // Evaluates this rank's share of `batch` on up to o.parallel threads. On one rank each result
  // is recorded as soon as it is there; on several, the shares are gathered and recorded in
  // candidate order on every rank. The first exception stops the hand-out of further candidates.
  const auto evaluateBatch = [&](const std::vector<Candidate>& batch) {
    std::vector<Candidate> mine;
    for (std::size_t k = 0; k < batch.size(); ++k)
      if (core::ownsItem(ranks, static_cast<int>(k))) mine.push_back(batch[k]);
    std::vector<Evaluation> finished;
    const auto take = [&](Evaluation ev, const Candidate& c) {
      ev.candidate = c;
      std::lock_guard<std::mutex> lock(mutex);
      if (ranks)
        finished.push_back(ev);
      else
        record(ev);
    };
    std::exception_ptr failure;
    if (m_objective.batched()) {  // the whole share at once (an ensemble)
      try {
        if (!mine.empty()) {
          const std::vector<Evaluation> all = m_objective.evaluateAll(mine);
          for (std::size_t k = 0; k < mine.size(); ++k) take(all.at(k), mine[k]);
        }
      } catch (...) {
        failure = std::current_exception();
      }
    } else {
      failure = core::forEachItem(mine.size(), o.parallel,
                                  [&](std::size_t k) { take(m_objective.evaluate(mine[k]), mine[k]); });
    }
    if (!ranks) {
      if (failure) std::rethrow_exception(failure);
      return;
    }
    // The finished evaluations of every rank are recorded before a failure is thrown, as on one
    // process: a resumed calibration does not run them again.
    const core::GatheredShares shares = core::gatherShares(*ranks, encodeEvaluations(finished), failure);
    std::vector<Evaluation> all;
    for (const std::string& share : shares.payloads)
      for (Evaluation& ev : decodeEvaluations(share)) all.push_back(std::move(ev));
    std::sort(all.begin(), all.end(),
              [](const Evaluation& a, const Evaluation& b) { return a.candidate.index < b.candidate.index; });
    for (const Evaluation& ev : all) record(ev);
    core::throwIfAnyRankFailed(shares, failure);
  };
  // On several ranks rank 0's batch is the batch (a proposer's floating-point result could
  // differ by a bit between machines; the decision must not).
  const auto agreed = [&](const std::vector<Candidate>& batch) {
    return ranks ? decodeCandidates(ranks->broadcast(encodeCandidates(batch))) : batch;
  };

  // 1. The initial design (only what the journal lacks).
  const std::vector<Point2> design = maximinLatinHypercube(o.initial, o.seed);
  std::vector<Candidate> pending;
  for (int i = 0; i < o.initial; ++i) {
    if (done.count(i)) continue;
    const Point2 p = o.box.fromUnit(design[i]);
    pending.push_back({i, p[0], p[1]});
  }
  evaluateBatch(agreed(pending));

  // 2. Proposals until the stop rule or the budget; a batch has o.parallel candidates per rank.
  const int batch_size = o.parallel * (ranks ? ranks->size() : 1);
  while (true) {
    const int total = static_cast<int>(state.evaluations.size());
    if (total >= o.max_evals) {
      result.stop_reason = "max_evals";
      break;
    }
    if (state.since_improvement >= o.patience) {
      result.stop_reason = "patience";
      break;
    }
    int next_index = o.initial;
    std::vector<Point2> avoid;
    for (const Evaluation& ev : state.evaluations) {
      next_index = std::max(next_index, ev.candidate.index + 1);
      avoid.push_back(o.box.toUnit(ev.candidate.e, ev.candidate.mu));
    }
    const int k = std::min(batch_size, o.max_evals - total);
    // On several ranks only rank 0 proposes (its batch is broadcast below): the surrogate's fit
    // could fail on one machine alone, and the others would only repeat its work.
    std::vector<Point2> proposals;
    if (!ranks || ranks->rank() == 0) proposals = m_proposer->propose(data(state.evaluations), avoid, k);
    std::vector<Candidate> batch;
    for (const Point2& u : proposals) {
      const Point2 p = o.box.fromUnit(u);
      batch.push_back({next_index++, p[0], p[1]});
    }
    batch = agreed(batch);
    if (batch.empty()) {
      result.stop_reason = "no candidate left";
      break;
    }
    evaluateBatch(batch);
  }

  // 3. The result, the final surrogate on a grid: the map and its minimum.
  {
    std::vector<int> ok;
    for (std::size_t i = 0; i < state.evaluations.size(); ++i)
      if (state.evaluations[i].ok) ok.push_back(static_cast<int>(i));
    const std::vector<DataPoint> d = data(state.evaluations);
    const int k = m_proposer->recommend(d);
    if (k >= 0) {
      result.recommended = ok[k];
      result.recommended_mean = m_proposer->surface(d, {d[k].x})[0];
    }
  }
  const int n = result.surface_n;
  std::vector<Point2> grid;
  for (int j = 0; j < n; ++j)
    for (int i = 0; i < n; ++i) grid.push_back({static_cast<double>(i) / (n - 1), static_cast<double>(j) / (n - 1)});
  result.surface = m_proposer->surface(data(state.evaluations), grid);
  std::size_t arg = 0;
  for (std::size_t i = 1; i < grid.size(); ++i)
    if (result.surface[i] < result.surface[arg] || std::isnan(result.surface[arg])) arg = i;
  result.surrogate_min = o.box.fromUnit(grid[arg]);
  result.surrogate_min_sse = result.surface[arg];
  result.wall_s = std::chrono::duration<double>(std::chrono::steady_clock::now() - wall0).count();
  return result;
}

}  // namespace millsim::calib
