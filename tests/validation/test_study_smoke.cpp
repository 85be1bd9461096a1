// Issue 9, Done-when 1: `millsim study accuracy --quick` runs as a smoke test: its numbers are
// not asserted, only that it writes its outputs and that they are sane (finite errors, positive
// wall times, a Pareto front per problem, the plots).
#include <gtest/gtest.h>
#include <sys/wait.h>

#include <algorithm>
#include <cmath>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <sstream>
#include <string>

namespace {

TEST(StudySmoke, QuickAccuracyStudyWritesSaneOutputs) {
  const auto out = std::filesystem::temp_directory_path() / "millsim_test_study";
  std::filesystem::remove_all(out);
  const std::string cmd = std::string(MILLSIM_CLI) + " study accuracy --quick --out " + out.string() + " --source " +
                          MILLSIM_SOURCE_DIR + " > /dev/null 2>&1";
  ASSERT_EQ(std::system(cmd.c_str()), 0) << cmd;
  std::ifstream csv(out / "accuracy_cost.csv");
  ASSERT_TRUE(csv.good());
  std::string line;
  std::getline(csv, line);
  EXPECT_EQ(line,
            "problem,axis,setting,error,value,wall_s,wall_s_per_simulated_s,particles,steps,backend,pareto,"
            "slurry_curve_mm");
  int rows = 0, front = 0;
  while (std::getline(csv, line)) {
    std::vector<std::string> c;
    std::stringstream ss(line);
    for (std::string cell; std::getline(ss, cell, ',');) c.push_back(cell);
    ASSERT_GE(c.size(), 11u) << line;  // the 12th, the slurry curve, is empty on other problems' rows
    ASSERT_LE(c.size(), 12u) << line;
    if (c[0] == "wet_drum_slurry") {  // its fitted curve's three coefficients
      ASSERT_EQ(c.size(), 12u) << line;
      EXPECT_EQ(std::count(c[11].begin(), c[11].end(), ';'), 2) << line;
    }
    const double error = std::stod(c[3]), wall = std::stod(c[5]);
    EXPECT_TRUE(std::isfinite(error) && error >= 0) << line;
    EXPECT_GT(wall, 0) << line;
    front += c[10] == "1";
    ++rows;
  }
  EXPECT_GE(rows, 14);
  EXPECT_GE(front, 5);  // at least one point on each problem's front
  for (const char* problem : {"dam_break_2d", "hertz_impact", "drum_300", "wet_drum_angle", "wet_drum_slurry"})
    EXPECT_TRUE(std::filesystem::exists(out / (std::string("pareto_") + problem + ".png"))) << problem;

  // --replot redraws from the CSV without running anything: the same CSV comes back.
  const auto again = out / "replot";
  const std::string replot = std::string(MILLSIM_CLI) + " study accuracy --replot " +
                             (out / "accuracy_cost.csv").string() + " --out " + again.string() + " > /dev/null 2>&1";
  ASSERT_EQ(std::system(replot.c_str()), 0) << replot;
  auto slurp = [](const std::filesystem::path& f) {
    std::ifstream in(f);
    std::stringstream ss;
    ss << in.rdbuf();
    return ss.str();
  };
  EXPECT_EQ(slurp(again / "accuracy_cost.csv"), slurp(out / "accuracy_cost.csv"));
  EXPECT_TRUE(std::filesystem::exists(again / "pareto_drum_300.png"));
  // A file that is not a study's CSV: bad input, exit code 2.
  const std::string bad = std::string(MILLSIM_CLI) +
                          " study accuracy --replot " MILLSIM_SOURCE_DIR "/cases/minimal_drum.xml --out " +
                          again.string() + " > /dev/null 2>&1";
  EXPECT_EQ(WEXITSTATUS(std::system(bad.c_str())), 2);
}

}  // namespace
