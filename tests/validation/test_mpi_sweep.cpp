// `mpirun -np 2 millsim sweep` through the real MPI layer (apps/millsim/mpi_ranks.cpp): the
// two ranks split the runs and rank 0 writes every run's row, equal to the rows of the same sweep
// on one process. Skipped, with the reason, when this build has no MPI or mpirun is missing.
#include <gtest/gtest.h>
#include <sys/wait.h>

#include <cstdio>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <sstream>
#include <string>
#include <vector>

#include "support/shell_command.hpp"

namespace {

// The columns of sweep.csv that a run's physics sets (index .. steps), per row.
std::vector<std::string> physicsColumns(const std::filesystem::path& csv) {
  std::ifstream in(csv);
  std::vector<std::string> rows;
  for (std::string line; std::getline(in, line);) {
    std::stringstream ss(line);
    std::string cell, kept;
    for (int c = 0; c < 10 && std::getline(ss, cell, ','); ++c) kept += cell + ",";
    rows.push_back(kept);
  }
  return rows;
}

TEST(MpiSweep, TwoRanksWriteTheRowsOfOneProcess) {
  if (millsim::testing::runShell(std::string(MILLSIM_CLI) + " info").output.find("\"mpi_compiled\": true") == std::string::npos)
    GTEST_SKIP() << "this build has no MPI (MILLSIM_MPI, libopenmpi-dev)";
  if (std::system("command -v mpirun > /dev/null 2>&1") != 0) GTEST_SKIP() << "mpirun not found (openmpi-bin)";
  const auto dir = std::filesystem::temp_directory_path() / "millsim_test_mpi_sweep";
  std::filesystem::remove_all(dir);
  const std::string args = std::string(" sweep ") + MILLSIM_SOURCE_DIR +
                           "/cases/minimal_drum.xml --set time.end=0.4 --set output.fields_every=0"
                           " --vary dem.restitution=0.3,0.6 --vary dem.friction=0.2,0.5 -q --out ";
  const std::string serial = std::string(MILLSIM_CLI) + args + (dir / "serial").string() + " > /dev/null 2>&1";
  ASSERT_EQ(std::system(serial.c_str()), 0) << serial;
  // As root (CI containers) Open MPI wants --allow-run-as-root; 2 ranks on any core count.
  const std::string mpi = "mpirun --allow-run-as-root --oversubscribe -np 2 " + std::string(MILLSIM_CLI) + args +
                          (dir / "mpi").string() + " > " + (dir / "mpi.log").string() + " 2>&1";
  std::filesystem::create_directories(dir);
  ASSERT_EQ(std::system(mpi.c_str()), 0) << mpi;
  const auto a = physicsColumns(dir / "serial" / "sweep.csv"), b = physicsColumns(dir / "mpi" / "sweep.csv");
  ASSERT_EQ(a.size(), 5u);  // header + 4 runs
  EXPECT_EQ(a, b);
  // Both ranks ran some of them: the JSON line says 2 ranks, and every run folder exists.
  std::ifstream log(dir / "mpi.log");
  std::stringstream text;
  text << log.rdbuf();
  EXPECT_NE(text.str().find("\"ranks\":2"), std::string::npos) << text.str();
  for (const char* run : {"run_000", "run_001", "run_002", "run_003"})
    EXPECT_TRUE(std::filesystem::exists(dir / "mpi" / run / "summary.json")) << run;
}

}  // namespace
