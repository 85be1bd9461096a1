// The calibration loop: initial design, proposals, stop rule, parallel batches, journal.
#include "millsim/calib/calibrator.hpp"

#include <algorithm>
#include <atomic>
#include <chrono>
#include <cmath>
#include <exception>
#include <mutex>
#include <set>
#include <stdexcept>
#include <thread>

#include "millsim/calib/initial_design.hpp"

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

CalibrationResult Calibrator::run(Journal* journal, const ProgressCallback& progress) {
  const auto wall0 = std::chrono::steady_clock::now();
  const CalibrationOptions& o = m_options;
  CalibrationResult result;
  CalibrationState& state = result.state;
  std::set<int> done;
  if (journal)
    for (const Evaluation& ev : journal->loaded())
      if (done.insert(ev.candidate.index).second) state.evaluations.push_back(ev);
  state.resumed = static_cast<int>(state.evaluations.size());
  updateState(state, o.initial);

  std::mutex mutex;
  // Evaluates `batch` on up to o.parallel threads; each result is stored and journalled as soon
  // as it is there. The first exception stops the hand-out of further candidates.
  const auto evaluateBatch = [&](const std::vector<Candidate>& batch) {
    std::atomic<std::size_t> next{0};
    std::exception_ptr failure;
    const auto worker = [&]() {
      while (true) {
        {
          std::lock_guard<std::mutex> lock(mutex);
          if (failure) return;
        }
        const std::size_t k = next++;
        if (k >= batch.size()) return;
        try {
          Evaluation ev = m_objective.evaluate(batch[k]);
          ev.candidate = batch[k];
          std::lock_guard<std::mutex> lock(mutex);
          if (journal) journal->append(ev);
          state.evaluations.push_back(ev);
          ++state.evaluated;
          updateState(state, o.initial);
          if (progress) progress(ev, state);
        } catch (...) {
          std::lock_guard<std::mutex> lock(mutex);
          if (!failure) failure = std::current_exception();
          return;
        }
      }
    };
    const int threads = std::min<int>(o.parallel, static_cast<int>(batch.size()));
    if (threads <= 1) {
      worker();
    } else {
      std::vector<std::thread> pool;
      for (int t = 0; t < threads; ++t) pool.emplace_back(worker);
      for (auto& t : pool) t.join();
    }
    if (failure) std::rethrow_exception(failure);
  };

  // 1. The initial design (only what the journal lacks).
  const std::vector<Point2> design = maximinLatinHypercube(o.initial, o.seed);
  std::vector<Candidate> pending;
  for (int i = 0; i < o.initial; ++i) {
    if (done.count(i)) continue;
    const Point2 p = o.box.fromUnit(design[i]);
    pending.push_back({i, p[0], p[1]});
  }
  evaluateBatch(pending);

  // 2. Proposals until the stop rule or the budget.
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
    const int k = std::min(o.parallel, o.max_evals - total);
    const std::vector<Point2> proposals = m_proposer->propose(data(state.evaluations), avoid, k);
    if (proposals.empty()) {
      result.stop_reason = "no candidate left";
      break;
    }
    std::vector<Candidate> batch;
    for (const Point2& u : proposals) {
      const Point2 p = o.box.fromUnit(u);
      batch.push_back({next_index++, p[0], p[1]});
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
