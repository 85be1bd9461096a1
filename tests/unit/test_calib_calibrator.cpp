// The calibration loop on analytic objectives: both methods find known minima (smooth bowl,
// narrow curved valley, noisy bowl), the stop rule counts exactly as specified, the budget
// holds, parallel batches propose distinct points, and an interrupted calibration resumes from
// its journal without re-evaluating anything.
#include <gtest/gtest.h>

#include <atomic>
#include <cmath>
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <map>
#include <memory>
#include <stdexcept>

#include "millsim/calib/analytic_objective.hpp"
#include "millsim/calib/calibrator.hpp"
#include "millsim/core/error.hpp"
#include "support/thread_ranks.hpp"

namespace calib = millsim::calib;
namespace fs = std::filesystem;

namespace {

// The truth used throughout: inside the paper's box, not on a grid line of the design.
constexpr double kE0 = 0.42, kMu0 = 0.48;

calib::CalibrationOptions options(const std::string& method, int max_evals = 40) {
  calib::CalibrationOptions o;
  o.method = method;
  o.max_evals = max_evals;
  return o;
}

// The reported result (Proposer::recommend).
const calib::Evaluation& best(const calib::CalibrationResult& r) { return r.state.evaluations.at(r.recommended); }

// Counts calls; optionally throws at call number `fail_at` (an interruption).
class CountingObjective : public calib::Objective {
 public:
  CountingObjective(const calib::Objective& inner, int fail_at = -1) : m_inner(inner), m_fail_at(fail_at) {}
  calib::Evaluation evaluate(const calib::Candidate& c) const override {
    const int n = ++m_calls;
    if (n == m_fail_at) throw std::runtime_error("interrupted");
    return m_inner.evaluate(c);
  }
  std::string signature() const override { return m_inner.signature(); }
  int calls() const { return m_calls; }

 private:
  const calib::Objective& m_inner;
  int m_fail_at;
  mutable std::atomic<int> m_calls{0};
};

// Returns scripted SSEs in call order (the stop rule test).
class ScriptedObjective : public calib::Objective {
 public:
  explicit ScriptedObjective(std::vector<double> sse) : m_sse(std::move(sse)) {}
  calib::Evaluation evaluate(const calib::Candidate& c) const override {
    calib::Evaluation ev;
    ev.candidate = c;
    const std::size_t k = m_next++;
    ev.ok = k < m_sse.size() && std::isfinite(m_sse[k]);
    ev.sse = ev.ok ? m_sse[k] : 0;
    return ev;
  }
  std::string signature() const override { return "scripted"; }

 private:
  std::vector<double> m_sse;
  mutable std::size_t m_next = 0;
};

fs::path freshDir(const std::string& name) {
  const fs::path d = fs::temp_directory_path() / ("millsim_calib_" + name);
  fs::remove_all(d);
  fs::create_directories(d);
  return d;
}

}  // namespace

// Tolerances: the bowl's SSE is 1 at 0.05 in e or 0.08 in mu from the minimum; the methods must
// land within a fifth of that (0.01, 0.016: SSE < 0.08) on a smooth bowl, and within 0.03 in e
// and the twin experiment's 0.05 in mu (test_calibration_twin.cpp, where e is not identifiable and
// not asserted) on the noisy bowl and on the valley (whose
// floor rises only as ((e - e0) / 0.1)^2; mu tolerance there explained in the test).
class BothMethods : public ::testing::TestWithParam<std::string> {};

TEST_P(BothMethods, SmoothBowl) {
  const auto f = calib::smoothBowl(kE0, kMu0);
  calib::Calibrator c(f, options(GetParam()));
  const auto r = c.run(nullptr);
  EXPECT_NEAR(best(r).candidate.e, kE0, 0.01);
  EXPECT_NEAR(best(r).candidate.mu, kMu0, 0.016);
  EXPECT_EQ(r.stop_reason, "patience");
  std::printf("[ %s ] bowl: %zu evaluations, best e=%.4f mu=%.4f SSE=%.3g\n", GetParam().c_str(),
              r.state.evaluations.size(), best(r).candidate.e, best(r).candidate.mu, best(r).sse);
}

TEST_P(BothMethods, NarrowCurvedValley) {
  // The floor is the parabola mu - mu0 = 0.1 ((1 + (e - e0) / 0.1)^2 - 1): where it is 0.03 in
  // e from the minimum (SSE 0.09 there) it is 0.069 in mu from it, so the mu tolerance here is
  // 0.07, not 0.05: a point on the floor as good as the e tolerance allows must pass.
  const auto f = calib::curvedValley(kE0, kMu0);
  calib::Calibrator c(f, options(GetParam()));
  const auto r = c.run(nullptr);
  EXPECT_NEAR(best(r).candidate.e, kE0, 0.03);
  EXPECT_NEAR(best(r).candidate.mu, kMu0, 0.07);
  std::printf("[ %s ] valley: %zu evaluations, best e=%.4f mu=%.4f SSE=%.3g\n", GetParam().c_str(),
              r.state.evaluations.size(), best(r).candidate.e, best(r).candidate.mu, best(r).sse);
}

TEST_P(BothMethods, NoisyBowl) {
  // sigma 0.3 on the SSE: what angle noise of ~0.3 deg per diameter gives near the optimum.
  const auto f = calib::noisyBowl(kE0, kMu0, 0.3);
  calib::Calibrator c(f, options(GetParam()));
  const auto r = c.run(nullptr);
  EXPECT_NEAR(best(r).candidate.e, kE0, 0.03);
  EXPECT_NEAR(best(r).candidate.mu, kMu0, 0.05);
  std::printf("[ %s ] noisy bowl: %zu evaluations, best e=%.4f mu=%.4f SSE=%.3g\n", GetParam().c_str(),
              r.state.evaluations.size(), best(r).candidate.e, best(r).candidate.mu, best(r).sse);
}

INSTANTIATE_TEST_SUITE_P(Calibration, BothMethods, ::testing::Values("paper", "bo"));

TEST(StopRule, StopsAfterPatienceCandidatesWithoutStrictImprovement) {
  // 6 initial (best 4), then 3 (better), 3.5, 2 (better), 2.5, 2.0 (equal: not better), 2.1
  // -> three in a row without improvement after the 11th: stop after exactly 12 evaluations.
  const ScriptedObjective f({5, 4, 6, 7, 8, 9, 3, 3.5, 2, 2.5, 2.0, 2.1, 0.1, 0.1});
  calib::Calibrator c(f, options("paper"));
  const auto r = c.run(nullptr);
  EXPECT_EQ(r.state.evaluations.size(), 12u);
  EXPECT_EQ(r.stop_reason, "patience");
  EXPECT_EQ(r.state.evaluations.at(r.state.best).candidate.index, 8);
  EXPECT_EQ(r.state.since_improvement, 3);
}

TEST(StopRule, InitialCandidatesDoNotCountAndFailuresDo) {
  // Improvements inside the initial design never count towards patience; a failed candidate
  // (NaN here) counts as no improvement.
  const ScriptedObjective f({9, 8, 7, 6, 5, 4, NAN, 1, NAN, NAN, 5, 0.5});
  calib::CalibrationOptions o = options("bo");
  o.patience = 3;
  calib::Calibrator c(f, o);
  const auto r = c.run(nullptr);
  EXPECT_EQ(r.state.evaluations.size(), 11u);
  EXPECT_EQ(r.state.evaluations.at(r.state.best).sse, 1.0);
}

TEST(StopRule, BudgetAndPatienceOptions) {
  const auto f = calib::smoothBowl(kE0, kMu0);
  calib::CalibrationOptions o = options("paper", 8);
  o.patience = 100;
  const auto r = calib::Calibrator(f, o).run(nullptr);
  EXPECT_EQ(r.state.evaluations.size(), 8u);
  EXPECT_EQ(r.stop_reason, "max_evals");
  o.initial = 2;
  EXPECT_THROW(calib::Calibrator(f, o), std::invalid_argument);
  o = options("paper", 5);
  EXPECT_THROW(calib::Calibrator(f, o), std::invalid_argument);  // budget below the initial design
  EXPECT_THROW(calib::Calibrator(f, options("simplex")), std::invalid_argument);
}

TEST(Parallel, BatchesOfDistinctCandidatesOnThreads) {
  for (const std::string method : {"paper", "bo"}) {
    const auto f = calib::smoothBowl(kE0, kMu0);
    calib::CalibrationOptions o = options(method, 24);
    o.parallel = 3;
    const fs::path dir = freshDir("parallel_" + method);
    calib::Journal journal((dir / "evaluations.csv").string(), f.signature(), {});
    const auto r = calib::Calibrator(f, o).run(&journal);
    // Every candidate different (the believer spreads a batch), indices 0..n-1.
    for (std::size_t i = 0; i < r.state.evaluations.size(); ++i) {
      EXPECT_EQ(r.state.evaluations[i].candidate.index, static_cast<int>(i));
      for (std::size_t j = 0; j < i; ++j)
        EXPECT_FALSE(r.state.evaluations[i].candidate.e == r.state.evaluations[j].candidate.e &&
                     r.state.evaluations[i].candidate.mu == r.state.evaluations[j].candidate.mu);
    }
    EXPECT_NEAR(best(r).candidate.e, kE0, 0.01) << method;
    EXPECT_NEAR(best(r).candidate.mu, kMu0, 0.016) << method;
    calib::Journal again((dir / "evaluations.csv").string(), f.signature(), {});
    EXPECT_EQ(again.loaded().size(), r.state.evaluations.size());
  }
}

// A batched objective (an ensemble: every run of a batch in one solver) gets each batch in one
// evaluateAll call: the initial design at once, then --parallel candidates at a time, and the
// calibration takes the same steps as with one candidate per thread.
class BatchedObjective : public calib::Objective {
 public:
  explicit BatchedObjective(const calib::Objective& inner) : m_inner(inner) {}
  calib::Evaluation evaluate(const calib::Candidate&) const override {
    throw std::logic_error("a batched objective is evaluated in batches");
  }
  std::vector<calib::Evaluation> evaluateAll(const std::vector<calib::Candidate>& cs) const override {
    m_batches.push_back(static_cast<int>(cs.size()));
    std::vector<calib::Evaluation> out;
    for (const auto& c : cs) out.push_back(m_inner.evaluate(c));
    return out;
  }
  bool batched() const override { return true; }
  std::string signature() const override { return m_inner.signature(); }
  const std::vector<int>& batches() const { return m_batches; }

 private:
  const calib::Objective& m_inner;
  mutable std::vector<int> m_batches;
};

TEST(Batched, AnEnsembleObjectiveGetsWholeBatchesAndTakesTheStepsOfThreads) {
  for (const std::string method : {"paper", "bo"}) {
    const auto f = calib::noisyBowl(kE0, kMu0, 0.3);
    calib::CalibrationOptions o = options(method, 21);
    o.parallel = 3;
    const auto threads = calib::Calibrator(f, o).run(nullptr);
    const BatchedObjective batched(f);
    const auto together = calib::Calibrator(batched, o).run(nullptr);
    ASSERT_EQ(together.state.evaluations.size(), threads.state.evaluations.size()) << method;
    for (std::size_t i = 0; i < threads.state.evaluations.size(); ++i) {
      EXPECT_EQ(together.state.evaluations[i].candidate.e, threads.state.evaluations[i].candidate.e) << method << i;
      EXPECT_EQ(together.state.evaluations[i].candidate.mu, threads.state.evaluations[i].candidate.mu) << method << i;
      EXPECT_EQ(together.state.evaluations[i].sse, threads.state.evaluations[i].sse) << method << i;
    }
    EXPECT_EQ(together.recommended, threads.recommended) << method;
    const std::vector<int>& b = batched.batches();
    ASSERT_GE(b.size(), 2u) << method;
    EXPECT_EQ(b[0], 6) << method;  // the initial design
    int total = 0;
    for (std::size_t k = 1; k < b.size(); ++k) {
      EXPECT_LE(b[k], 3) << method;
      EXPECT_GE(b[k], 1) << method;
    }
    for (int n : b) total += n;
    EXPECT_EQ(total, static_cast<int>(threads.state.evaluations.size())) << method;
  }
}

// Ranks (MPI's code path, on threads here): 3 ranks of one candidate each take the same steps as
// one process with 3 threads: same batches, same candidates, same result on every rank; only
// rank 0 journals, and a resumed ranked calibration re-evaluates nothing.
TEST(Ranks, ThreeRanksTakeTheStepsOfOneProcessWithThreeThreads) {
  for (const std::string method : {"paper", "bo"}) {
    const auto f = calib::noisyBowl(kE0, kMu0, 0.3);
    calib::CalibrationOptions o = options(method, 21);
    o.parallel = 3;
    const auto threads = calib::Calibrator(f, o).run(nullptr);
    const fs::path dir = freshDir("ranks_" + method);
    const std::string path = (dir / "evaluations.csv").string();
    std::vector<calib::CalibrationResult> per_rank(3);
    std::atomic<int> calls{0};
    millsim::testing::runOnRanks(3, [&](const millsim::core::RankGroup& ranks) {
      CountingObjective counted(f);
      calib::CalibrationOptions ro = options(method, 21);
      ro.ranks = &ranks;
      std::unique_ptr<calib::Journal> journal;
      if (ranks.rank() == 0)
        journal = std::make_unique<calib::Journal>(path, f.signature(), std::vector<std::string>{});
      per_rank[ranks.rank()] = calib::Calibrator(counted, ro).run(journal.get());
      calls += counted.calls();
    });
    EXPECT_EQ(calls.load(), static_cast<int>(threads.state.evaluations.size())) << method;  // each once
    for (const auto& r : per_rank) {
      ASSERT_EQ(r.state.evaluations.size(), threads.state.evaluations.size()) << method;
      for (std::size_t i = 0; i < r.state.evaluations.size(); ++i) {
        EXPECT_EQ(r.state.evaluations[i].candidate.e, threads.state.evaluations[i].candidate.e) << method << i;
        EXPECT_EQ(r.state.evaluations[i].candidate.mu, threads.state.evaluations[i].candidate.mu) << method << i;
        EXPECT_EQ(r.state.evaluations[i].sse, threads.state.evaluations[i].sse) << method << i;
      }
      EXPECT_EQ(r.recommended, threads.recommended) << method;
      EXPECT_EQ(r.stop_reason, threads.stop_reason) << method;
    }
    calib::Journal journal(path, f.signature(), {});
    EXPECT_EQ(journal.loaded().size(), threads.state.evaluations.size()) << method;
    // Started again on 3 ranks with rank 0's journal: nothing is evaluated.
    std::atomic<int> again{0};
    millsim::testing::runOnRanks(3, [&](const millsim::core::RankGroup& ranks) {
      CountingObjective counted(f);
      calib::CalibrationOptions ro = options(method, 21);
      ro.ranks = &ranks;
      std::unique_ptr<calib::Journal> j;
      if (ranks.rank() == 0) j = std::make_unique<calib::Journal>(path, f.signature(), std::vector<std::string>{});
      calib::Calibrator(counted, ro).run(j.get());
      again += counted.calls();
    });
    EXPECT_EQ(again.load(), 0) << method;
  }
}

// An error on one rank (here rank 1's first evaluation throws) stops every rank, after the
// evaluations the others finished are in rank 0's journal.
TEST(Ranks, AnErrorOnOneRankStopsAllAndKeepsTheOthersResults) {
  const auto f = calib::smoothBowl(kE0, kMu0);
  const fs::path dir = freshDir("ranks_failure");
  const std::string path = (dir / "evaluations.csv").string();
  std::atomic<int> threw{0};
  millsim::testing::runOnRanks(3, [&](const millsim::core::RankGroup& ranks) {
    CountingObjective counted(f, ranks.rank() == 1 ? 1 : -1);
    calib::CalibrationOptions ro = options("bo", 21);
    ro.ranks = &ranks;
    std::unique_ptr<calib::Journal> journal;
    if (ranks.rank() == 0) journal = std::make_unique<calib::Journal>(path, f.signature(), std::vector<std::string>{});
    try {
      calib::Calibrator(counted, ro).run(journal.get());
    } catch (const std::runtime_error& e) {
      ++threw;
      if (ranks.rank() != 1) {
        EXPECT_NE(std::string(e.what()).find("rank 1: interrupted"), std::string::npos);
      }
    }
  });
  EXPECT_EQ(threw.load(), 3);
  // The initial design's 6 candidates: ranks 0 and 2 finished theirs (2 each), rank 1 none.
  calib::Journal journal(path, f.signature(), {});
  EXPECT_EQ(journal.loaded().size(), 4u);
}

TEST(Resume, AnInterruptedCalibrationRerunsNothing) {
  for (const std::string method : {"paper", "bo"}) {
    const auto f = calib::curvedValley(kE0, kMu0);
    // Uninterrupted reference.
    CountingObjective reference(f);
    const auto full = calib::Calibrator(reference, options(method)).run(nullptr);
    const int total = reference.calls();
    ASSERT_GT(total, 8) << method;

    // Interrupted at the 8th evaluation (2 after the initial design): 7 rows in the journal.
    const fs::path dir = freshDir("resume_" + method);
    const std::string path = (dir / "evaluations.csv").string();
    {
      CountingObjective broken(f, 8);
      calib::Journal journal(path, f.signature(), {});
      EXPECT_THROW(calib::Calibrator(broken, options(method)).run(&journal), std::runtime_error);
    }
    calib::Journal journal(path, f.signature(), {});
    ASSERT_EQ(journal.loaded().size(), 7u);
    CountingObjective resumed(f);
    const auto r = calib::Calibrator(resumed, options(method)).run(&journal);
    EXPECT_EQ(resumed.calls(), total - 7) << method;  // nothing of the journal evaluated again
    EXPECT_EQ(r.state.resumed, 7);
    ASSERT_EQ(r.state.evaluations.size(), full.state.evaluations.size());
    for (std::size_t i = 0; i < r.state.evaluations.size(); ++i) {
      EXPECT_EQ(r.state.evaluations[i].candidate.e, full.state.evaluations[i].candidate.e) << method << i;
      EXPECT_EQ(r.state.evaluations[i].candidate.mu, full.state.evaluations[i].candidate.mu) << method << i;
    }
    // Finished calibration: starting again evaluates nothing at all.
    calib::Journal done(path, f.signature(), {});
    CountingObjective idle(f);
    calib::Calibrator(idle, options(method)).run(&done);
    EXPECT_EQ(idle.calls(), 0) << method;
  }
}

TEST(Resume, AJournalOfAnotherCalibrationIsRefused) {
  const fs::path dir = freshDir("signature");
  const std::string path = (dir / "evaluations.csv").string();
  { calib::Journal j(path, "analytic:bowl", {}); }
  EXPECT_THROW(calib::Journal(path, "analytic:valley", {}), millsim::core::InputError);
  EXPECT_THROW(calib::Journal(path, "analytic:bowl", {"300"}), millsim::core::InputError);
}

TEST(Resume, ATruncatedLastRowIsIgnored) {
  const fs::path dir = freshDir("truncated");
  const std::string path = (dir / "evaluations.csv").string();
  {
    calib::Journal j(path, "s", {"300"});
    calib::Evaluation ev;
    ev.candidate = {0, 0.4, 0.5};
    ev.angles_deg = {43.1};
    ev.sse = 0.25;
    ev.ok = true;
    j.append(ev);
  }
  std::ofstream(path, std::ios::app) << "1,0.35,0.6";  // cut off mid-row by an interruption
  calib::Journal j(path, "s", {"300"});
  ASSERT_EQ(j.loaded().size(), 1u);
  EXPECT_EQ(j.loaded()[0].candidate.e, 0.4);
  EXPECT_EQ(j.loaded()[0].angles_deg[0], 43.1);
  EXPECT_EQ(j.loaded()[0].sse, 0.25);
}

// Paper method against the default on the same objectives: 9 truths over the box x 3
// objectives; evaluations to stop, evaluations until the first candidate within (0.01, 0.016)
// of the truth (bowl) or (0.03, 0.05) (valley, noisy bowl; all evaluations when none is), and how
// often the result is within tolerance. Disabled: a report (docs/calibration.md), ~1 s.
TEST(MethodComparison, DISABLED_PaperAgainstBo) {
  for (const std::string kind : {"bowl", "valley", "noisy"}) {
    for (const std::string method : {"paper", "bo"}) {
      double evals = 0, first = 0, hits = 0, n = 0;
      for (double e0 : {0.34, 0.42, 0.5})
        for (double mu0 : {0.36, 0.48, 0.62}) {
          const auto f = kind == "bowl"     ? calib::smoothBowl(e0, mu0)
                         : kind == "valley" ? calib::curvedValley(e0, mu0)
                                            : calib::noisyBowl(e0, mu0, 0.3);
          const double te = kind == "bowl" ? 0.01 : 0.03, tm = kind == "bowl" ? 0.016 : 0.05;
          const auto r = calib::Calibrator(f, options(method)).run(nullptr);
          evals += r.state.evaluations.size();
          int k = 0;
          for (const auto& ev : r.state.evaluations) {
            ++k;
            if (std::abs(ev.candidate.e - e0) < te && std::abs(ev.candidate.mu - mu0) < tm) break;
          }
          first += k;
          hits += std::abs(best(r).candidate.e - e0) < te && std::abs(best(r).candidate.mu - mu0) < tm;
          n += 1;
        }
      std::printf("%-7s %-6s mean evaluations %.1f, first within tolerance at %.1f, result within tolerance %g/%g\n",
                  kind.c_str(), method.c_str(), evals / n, first / n, hits, n);
    }
  }
}
