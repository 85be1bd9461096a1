// The accuracy study's bookkeeping (src/sim/accuracy_study.cpp): the slurry curves' distance, the
// errors against each problem's reference row, --merge, and the CSV round trip of the curves.
#include <gtest/gtest.h>

#include <cmath>
#include <filesystem>
#include <fstream>

#include "millsim/sim/accuracy_study.hpp"

namespace millsim::sim {
namespace {

// RMS over |x| <= L of d(x) = a + b x + c x^2 by the midpoint rule on 10^6 panels (relative
// error ~1e-12 for this smooth integrand).
double rmsNumerically(double a, double b, double c, double L) {
  const int n = 1000000;
  double sum = 0;
  for (int k = 0; k < n; ++k) {
    const double x = -L + (k + 0.5) * 2 * L / n, d = a + b * x + c * x * x;
    sum += d * d;
  }
  return std::sqrt(sum / n);
}

TEST(AccuracyStudy, SlurryCurveDistanceIsTheRmsOverTheInterval) {
  const std::vector<double> ref{10, 0.2, 0.003};
  // Shifted by 4 mm: 4 mm everywhere.
  EXPECT_NEAR(slurryCurveDistance({14, 0.2, 0.003}, ref, 50), 4.0, 1e-12);
  // Tilted by 0.1: 0.1 L / sqrt(3).
  EXPECT_NEAR(slurryCurveDistance({10, 0.3, 0.003}, ref, 50), 0.1 * 50 / std::sqrt(3.0), 1e-12);
  // All three at once.
  EXPECT_NEAR(slurryCurveDistance({7, -0.1, 0.001}, ref, 50), rmsNumerically(-3, -0.3, -0.002, 50), 1e-9);
  EXPECT_DOUBLE_EQ(slurryCurveDistance(ref, ref, 50), 0.0);
  EXPECT_TRUE(std::isnan(slurryCurveDistance({}, ref, 50)));  // a run without a curve
}

StudyRow row(const std::string& problem, const std::string& axis, const std::string& setting, double value,
             std::vector<double> curve = {}) {
  StudyRow r;
  r.problem = problem;
  r.axis = axis;
  r.setting = setting;
  r.value = value;
  r.curve = std::move(curve);
  r.wall_s = 1;
  r.simulated_s = 1;
  return r;
}

TEST(AccuracyStudy, ErrorsAreAgainstTheProblemsOwnReference) {
  std::vector<StudyRow> rows{row("drum_300", "reference", "t_c/200", 40.0),
                             row("drum_300", "dt_divisor", "t_c/50", 41.5),
                             row("wet_drum_angle", "reference", "dp 4", 55.0),
                             row("wet_drum_angle", "dp", "dp 5", 53.0),
                             row("wet_drum_slurry", "reference", "dp 4", 10, {10, 0.2, 0.0}),
                             row("wet_drum_slurry", "dp", "dp 5", 13, {13, 0.2, 0.0})};
  fillReferenceErrors(rows);
  EXPECT_DOUBLE_EQ(rows[1].error, 1.5);
  EXPECT_DOUBLE_EQ(rows[3].error, 2.0);
  EXPECT_NEAR(rows[5].error, 3.0, 1e-12);  // over |x| <= 50 mm, the wet drum's central half
  EXPECT_DOUBLE_EQ(rows[0].error + rows[2].error + rows[4].error, 0.0);
  // Without its reference a problem's errors are unknown, not zero.
  std::vector<StudyRow> lone{row("wet_drum_angle", "dp", "dp 5", 53.0)};
  fillReferenceErrors(lone);
  EXPECT_TRUE(std::isnan(lone[0].error));
}

TEST(AccuracyStudy, MergeReplacesARowAndRecomputesTheErrors) {
  const std::vector<StudyRow> base{row("wet_drum_angle", "reference", "dp 4", 55.0),
                                   row("wet_drum_angle", "dp", "dp 5", 53.0), row("drum_300", "reference", "x", 40)};
  const auto merged = mergeStudyRows(base, {row("wet_drum_angle", "reference", "dp 4", 52.0)});
  ASSERT_EQ(merged.size(), 3u);
  EXPECT_DOUBLE_EQ(merged[0].value, 52.0);
  EXPECT_DOUBLE_EQ(merged[1].error, 1.0);
}

TEST(AccuracyStudy, CsvKeepsTheSlurryCurvesToFullPrecision) {
  std::vector<StudyRow> rows{row("wet_drum_slurry", "reference", "dp 4", 10, {10.123456789012345, 0.2, 1.0 / 3}),
                             row("wet_drum_slurry", "dp", "dp 5", 13, {13, 0.2, 0.0}),
                             row("drum_300", "reference", "t_c/200", 40.0)};
  fillReferenceErrors(rows);
  const auto dir = std::filesystem::temp_directory_path() / "millsim_test_study_csv";
  std::filesystem::remove_all(dir);
  writeAccuracyStudy(rows, dir.string());
  const auto back = readAccuracyStudy((dir / "accuracy_cost.csv").string());
  ASSERT_EQ(back.size(), 3u);
  EXPECT_EQ(back[0].curve, rows[0].curve);
  EXPECT_TRUE(back[2].curve.empty());
  EXPECT_TRUE(std::filesystem::exists(dir / "pareto_wet_drum_slurry.png"));
  EXPECT_FALSE(std::filesystem::exists(dir / "pareto_dam_break_2d.png"));  // no rows, no plot
  // A study written before the slurry column (11 columns) still reads.
  {
    std::ofstream old(dir / "old.csv");
    old << "problem,axis,setting,error,value,wall_s,wall_s_per_simulated_s,particles,steps,backend,pareto\n"
        << "drum_300,reference,t_c/200,0,40,10,1,100,1000,omp,1\n";
  }
  const auto old_rows = readAccuracyStudy((dir / "old.csv").string());
  ASSERT_EQ(old_rows.size(), 1u);
  EXPECT_DOUBLE_EQ(old_rows[0].value, 40.0);
}

}  // namespace
}  // namespace millsim::sim
