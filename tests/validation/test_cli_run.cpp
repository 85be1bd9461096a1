// End-to-end: `millsim run/validate` as a user calls it. Bad input must fail with exit code 2
// and a one-line message naming file:line; a run writes the documented outputs, which a real
// HDF5 reader (h5dump) opens; a restart continues from the checkpoint; a balls-only run has no
// SPH stage and no SPH arrays.
#include <gtest/gtest.h>
#include <sys/wait.h>
#include <unistd.h>

#include <algorithm>
#include <array>
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <nlohmann/json.hpp>
#include <sstream>
#include <string>
#include <vector>

#include "millsim/io/case_xml.hpp"
#include "millsim/sim/simulation.hpp"
#include "support/shell_command.hpp"

namespace fs = std::filesystem;

namespace {

using Result = millsim::testing::ShellResult;

std::string cli() { return MILLSIM_CLI; }
std::string sourceDir() { return MILLSIM_SOURCE_DIR; }

fs::path tempDir(const std::string& name) {
  const fs::path d = fs::temp_directory_path() / ("millsim_cli_" + name + "_" + std::to_string(::getpid()));
  fs::remove_all(d);
  fs::create_directories(d);
  return d;
}

std::string writeCase(const fs::path& dir, const std::string& text) {
  const fs::path f = dir / "case.xml";
  std::ofstream(f) << text;
  return f.string();
}

std::string minimalCase() {
  std::ifstream in(sourceDir() + "/cases/minimal_drum.xml");
  std::stringstream ss;
  ss << in.rdbuf();
  return ss.str();
}

void expectInputError(const Result& r, const std::string& where) {
  EXPECT_EQ(r.code, 2) << r.output;
  EXPECT_NE(r.output.find(where), std::string::npos) << r.output;
  // One line: the message itself (CLI11 or the loader add nothing else).
  EXPECT_EQ(std::count(r.output.begin(), r.output.end(), '\n'), 1) << r.output;
}

}  // namespace

TEST(CliBadInput, MalformedXml) {
  const auto dir = tempDir("malformed");
  const auto f = writeCase(dir, "<millsim>\n  <time end=\"1\"\n</millsim>\n");
  expectInputError(millsim::testing::runShell(cli() + " validate " + f), f + ":");
}

TEST(CliBadInput, MissingAttribute) {
  const auto dir = tempDir("missing");
  std::string text = minimalCase();
  text.replace(text.find("end=\"1\""), 7, "");
  const auto f = writeCase(dir, text);
  const Result r = millsim::testing::runShell(cli() + " run " + f + " --out " + (dir / "out").string());
  expectInputError(r, f + ":13:");
  EXPECT_NE(r.output.find("'end'"), std::string::npos) << r.output;
}

TEST(CliBadInput, NegativeDiameter) {
  const auto dir = tempDir("negative");
  std::string text = minimalCase();
  text.replace(text.find("diameter=\"0.1\""), 14, "diameter=\"-0.1\"");
  const auto f = writeCase(dir, text);
  const Result r = millsim::testing::runShell(cli() + " validate " + f);
  expectInputError(r, f + ":18:");
  EXPECT_NE(r.output.find("diameter"), std::string::npos);
}

TEST(CliBadInput, ImpossibleFilling) {
  const auto dir = tempDir("filling");
  std::string text = minimalCase();
  text.replace(text.find("count=\"20\""), 10, "count=\"0\"");
  text.replace(text.find("filling=\"0.3\""), 13, "filling=\"0.7\"");
  text.replace(text.find("length_factor=\"3\""), 17, "length_factor=\"1\"");
  const auto f = writeCase(dir, text);
  const Result r = millsim::testing::runShell(cli() + " validate " + f);
  expectInputError(r, f + ":21:");
  EXPECT_NE(r.output.find("do not fit"), std::string::npos) << r.output;
}

// A fluid-only run writes no checkpoint; given --restart it used to start over silently and
// overwrite the outputs it was meant to continue.
TEST(CliBadInput, RestartOfARunWithoutCheckpoints) {
  const auto dir = tempDir("restart_unsupported");
  const std::string checkpoint = (dir / "checkpoint.h5").string();
  std::ofstream(checkpoint) << "not read";
  const std::string c = sourceDir() + "/cases/hydrostatic_2d.xml", out = (dir / "out").string();
  const Result r = millsim::testing::runShell(cli() + " run " + c + " --out " + out + " --restart " + checkpoint);
  expectInputError(r, checkpoint + ": --restart continues drum and stirred-mill runs only; " + c);
  EXPECT_FALSE(fs::exists(out + "/series.csv"));
}

// compare-power reads power.csv as a stirred run writes it (header of stirred_run.cpp).
static void writePowerCsv(const fs::path& dir, const std::vector<std::array<double, 2>>& levels) {
  fs::create_directories(dir);
  std::ofstream f(dir / "power.csv");
  f << "rpm,power_W,net_power_W,stirrer_torque_Nm,outer_torque_Nm,window_from_s,window_to_s,samples,"
       "power_first_half_W,power_second_half_W,steady,revolutions_held,kinetic_open_J,kinetic_close_J\n";
  for (const auto& [rpm, p] : levels)
    f << rpm << "," << p << "," << p << ",-1,1,0.1,0.2,10," << p << "," << p << ",1,3,1,1\n";
}

TEST(CliComparePower, MonotoneFlagAndSquaredDifferences) {
  const auto dir = tempDir("compare_power");
  writePowerCsv(dir / "a", {{1000, 100}, {2000, 300}, {3000, 600}});
  writePowerCsv(dir / "b", {{1000, 100}, {2000, 400}, {3000, 350}});
  std::ofstream(dir / "measured.csv") << "rpm,power_W\n1000,110\n2000,290\n\n4000,900\n";
  const fs::path png = dir / "power.png";
  const Result r = millsim::testing::runShell(cli() + " compare-power " + (dir / "a").string() + " " +
                                              (dir / "b").string() + " --labels soft,stiff --measured " +
                                              (dir / "measured.csv").string() + " --png " + png.string());
  ASSERT_EQ(r.code, 0) << r.output;
  const auto j = nlohmann::json::parse(r.output);
  ASSERT_EQ(j.size(), 2u);
  EXPECT_TRUE(j[0]["monotone"].get<bool>());
  EXPECT_FALSE(j[1]["monotone"].get<bool>());
  EXPECT_EQ(j[1]["drops_rpm"], nlohmann::json::parse("[[2000.0, 3000.0]]"));
  // The seed's measure over the speeds both curves have: (100-110)^2 + (300-290)^2 = 200 for a,
  // (100-110)^2 + (400-290)^2 = 12 200 for b; 4000 rpm has no level.
  EXPECT_DOUBLE_EQ(j[0]["sse_W2"].get<double>(), 200.0);
  EXPECT_DOUBLE_EQ(j[0]["rms_W"].get<double>(), 10.0);
  EXPECT_DOUBLE_EQ(j[1]["sse_W2"].get<double>(), 12200.0);
  EXPECT_EQ(j[0]["measured_points_matched"].get<int>(), 2);
  EXPECT_EQ(j[0]["measured_rpm_without_level"], nlohmann::json::parse("[4000.0]"));
  EXPECT_EQ(j[1]["label"].get<std::string>(), "stiff");
  ASSERT_TRUE(fs::exists(png));
  EXPECT_GT(fs::file_size(png), 1000u);
}

TEST(CliBadInput, ComparePowerMeasuredNotANumber) {
  const auto dir = tempDir("compare_power_bad");
  writePowerCsv(dir / "a", {{1000, 100}});
  const std::string measured = (dir / "measured.csv").string();
  std::ofstream(measured) << "rpm,power_W\n1000,110\n2000,abc\n";
  const Result r =
      millsim::testing::runShell(cli() + " compare-power " + (dir / "a").string() + " --measured " + measured);
  expectInputError(r, measured + ":3: 'power_W' is not a number: 'abc'");
  // A directory without power.csv (a drum's output, say) is named too.
  const Result r2 = millsim::testing::runShell(cli() + " compare-power " + dir.string());
  expectInputError(r2, (dir / "power.csv").string() + ": cannot open");
}

TEST(CliRun, WritesOutputsAndRestarts) {
  const auto dir = tempDir("run");
  const std::string out = (dir / "out").string();
  const Result r =
      millsim::testing::runShell(cli() + " run " + sourceDir() + "/cases/minimal_drum.xml --out " + out + " -q");
  ASSERT_EQ(r.code, 0) << r.output;
  nlohmann::json s = nlohmann::json::parse(std::ifstream(out + "/summary.json"));
  EXPECT_EQ(s["status"], "ok");
  EXPECT_EQ(s["particles"]["dem_spheres"], 20);
  EXPECT_EQ(s["particles"]["sph"], 0);
  EXPECT_NEAR(s["simulated_time_s"].get<double>(), 1.0, 1e-4);
  // The drum turns: the walls did positive work, all of it (and the compaction's) dissipated
  // within the energy budget. Budget: work_in = dKE + dPE + elastic + dissipated; the residual
  // is the integration error of the step: within 5% of the work in at t_c/50 with sliding contacts,
  // the bound DrumStability (tests/stability/test_drum_stability.cpp) holds this same case to.
  const double work = s["energy"]["work_in_J"], residual = s["energy"]["budget_residual_J"];
  EXPECT_GT(work, 0.0);
  EXPECT_LT(std::abs(residual), 0.05 * work);
  for (const char* k : {"backend", "threads", "wall_time_s", "steps", "stages", "memory_bytes", "power_W", "energy"})
    EXPECT_TRUE(s.contains(k)) << k;
  ASSERT_TRUE(fs::exists(out + "/series.csv"));
  ASSERT_TRUE(fs::exists(out + "/fields.xdmf"));
  ASSERT_TRUE(fs::exists(out + "/checkpoint.h5"));
  if (fs::exists("/usr/bin/h5dump")) {
    const Result h = millsim::testing::runShell("h5dump -H " + out + "/fields/frame_000000.h5");
    EXPECT_EQ(h.code, 0);
    EXPECT_NE(h.output.find("position"), std::string::npos);
  }
  // Restart from the final checkpoint and run 0.2 s more.
  const Result r2 = millsim::testing::runShell(cli() + " run " + sourceDir() + "/cases/minimal_drum.xml --out " + out +
                                               " --restart " + out + "/checkpoint.h5 --set time.end=1.2 -q");
  ASSERT_EQ(r2.code, 0) << r2.output;
  nlohmann::json s2 = nlohmann::json::parse(std::ifstream(out + "/summary.json"));
  EXPECT_NEAR(s2["simulated_time_s"].get<double>(), 1.2, 1e-4);
  EXPECT_GT(s2["energy"]["work_in_J"].get<double>(), work);
}

TEST(BallsOnly, NoSphStageNoSphArrays) {
  auto scene = millsim::io::loadCaseFile(sourceDir() + "/cases/minimal_drum.xml");
  millsim::sim::RunOptions opt;
  opt.write_outputs = false;
  millsim::sim::Simulation sim(scene, opt);
  for (const auto& stage : sim.stages()) EXPECT_EQ(stage.find("sph"), std::string::npos) << stage;
  std::size_t total = 0;
  for (const auto& [group, bytes] : sim.memoryReport()) {
    EXPECT_TRUE(group.rfind("dem.", 0) == 0 || group == "neighbors") << group;
    total += bytes;
  }
  EXPECT_GT(total, 0u);
  EXPECT_FALSE(scene.effect_sph);
}
