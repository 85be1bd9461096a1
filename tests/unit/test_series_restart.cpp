// series.csv across a restart (sim::SeriesWriter). A run stopped after its last checkpoint has
// written rows past it; the resumed run starts at the checkpoint's time and writes those times
// again. The full 500 mm wet run (2026-12-03) showed it: killed at t = 5.59 s, resumed from its
// t = 5 s checkpoint, its series.csv ran 5.00 .. 5.59 and then 5.00 again. A resumed writer
// now keeps the header and the rows before the resume time (within the 9 printed digits) and
// appends after them; a fresh writer starts a new file.
#include <gtest/gtest.h>

#include <cstdio>
#include <filesystem>
#include <fstream>
#include <string>
#include <vector>

#include "sim/run_outputs.hpp"

namespace millsim {
namespace {

std::vector<std::string> lines(const std::filesystem::path& p) {
  std::ifstream in(p);
  std::vector<std::string> out;
  for (std::string l; std::getline(in, l);) out.push_back(l);
  return out;
}

TEST(SeriesRestart, ResumedWriterDropsTheRowsFromItsStartOn) {
  const auto path = std::filesystem::temp_directory_path() / "millsim_test_series_restart.csv";
  {
    sim::SeriesWriter w(path, {"time_s", "x"}, false);
    for (int k = 0; k <= 10; ++k) w.row({0.1 * k, double(k)});
    w.row({0.500000004, 99.0});  // a row at the resume time as 9 digits print it
  }
  ASSERT_EQ(lines(path).size(), 13u);
  {
    sim::SeriesWriter w(path, {"time_s", "x"}, true, 0.5);
    w.row({0.5, 5.5});
    w.row({0.6, 6.5});
  }
  const std::vector<std::string> got = lines(path);
  ASSERT_EQ(got.size(), 8u);  // header, 0.0 .. 0.4, then the resumed 0.5 and 0.6
  EXPECT_EQ(got[0], "time_s,x");
  EXPECT_EQ(got[5], "0.4,4");
  EXPECT_EQ(got[6], "0.5,5.5");
  EXPECT_EQ(got[7], "0.6,6.5");
  {
    sim::SeriesWriter w(path, {"time_s", "x"}, false);  // a new run: a new file
    w.row({0.0, 1.0});
  }
  EXPECT_EQ(lines(path).size(), 2u);
  std::filesystem::remove(path);
}

// Appending without a resume time (the default, +inf) keeps every row already written.
TEST(SeriesRestart, AppendWithoutResumeTimeKeepsEveryRow) {
  const auto path = std::filesystem::temp_directory_path() / "millsim_test_series_append.csv";
  {
    sim::SeriesWriter w(path, {"time_s", "x"}, false);
    for (int k = 0; k <= 3; ++k) w.row({0.1 * k, double(k)});
  }
  {
    sim::SeriesWriter w(path, {"time_s", "x"}, true);
    w.row({0.4, 4.0});
  }
  const std::vector<std::string> got = lines(path);
  ASSERT_EQ(got.size(), 6u);  // header, 0.0 .. 0.3, then 0.4
  EXPECT_EQ(got[1], "0,0");
  EXPECT_EQ(got[4], "0.3,3");
  EXPECT_EQ(got[5], "0.4,4");
  std::filesystem::remove(path);
}

}  // namespace
}  // namespace millsim
