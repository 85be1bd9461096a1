// Shaft torque against the moment balance of the charge: in steady rotation the drum's torque on
// the charge balances gravity's moment about the axis, so the time-averaged torque of the charge
// on the drum equals -M g <x_cg> (drum axis z, gravity -y, x_cg the charge's centre of mass).
// This checks the wall-force torque that power_W comes from against a quantity computed from
// positions only. 80 balls of 10 mm in the 100 mm minimal drum at 30% critical, averaged over
// [1, 3] s (rotation starts at 0.3 s).
#include <gtest/gtest.h>

#include <cmath>
#include <filesystem>
#include <fstream>
#include <nlohmann/json.hpp>
#include <sstream>
#include <string>
#include <vector>

#include "millsim/io/case_xml.hpp"
#include "millsim/sim/simulation.hpp"

namespace fs = std::filesystem;

TEST(DrumTorque, BalancesGravityMomentOfTheCharge) {
  const auto scene = millsim::io::loadCaseFile(std::string(MILLSIM_SOURCE_DIR) + "/cases/minimal_drum.xml",
                                               {"charge.count=80", "time.end=3", "output.fields_every=0"});
  millsim::sim::RunOptions opt;
  opt.out_dir = (fs::temp_directory_path() / ("millsim_torque_" + std::to_string(::getpid()))).string();
  millsim::sim::Simulation sim(scene, opt);
  const auto& summary = sim.run();
  ASSERT_EQ(summary.status, "ok");

  std::ifstream in(opt.out_dir + "/series.csv");
  std::string line;
  std::getline(in, line);
  std::vector<std::string> header;
  {
    std::stringstream h(line);
    for (std::string c; std::getline(h, c, ',');) header.push_back(c);
  }
  auto column = [&](const std::string& name) {
    for (std::size_t i = 0; i < header.size(); ++i)
      if (header[i] == name) return static_cast<int>(i);
    return -1;
  };
  const int c_t = column("time_s"), c_tq = column("drum_torque_Nm"), c_x = column("com_x_m");
  ASSERT_GE(c_x, 0);
  double torque = 0, x_cg = 0;
  int n = 0;
  while (std::getline(in, line)) {
    std::stringstream ss(line);
    std::vector<double> v;
    for (std::string c; std::getline(ss, c, ',');) v.push_back(std::stod(c));
    if (v[c_t] < 1.0) continue;
    torque += v[c_tq];
    x_cg += v[c_x];
    ++n;
  }
  ASSERT_GT(n, 150);
  torque /= n;
  x_cg /= n;
  const double expected = -summary.charge_mass_kg * 9.81 * x_cg;
  // The charge is lifted on the left (clockwise drum): x_cg < 0, torque > 0.
  EXPECT_LT(x_cg, 0.0);
  // 5%: the charge's own angular momentum (~M r^2 omega ~ 1e-3 N m s) may differ between the
  // window's ends, against ~0.06 N m s of torque impulse over the 2 s (2%), plus the sampling of
  // a fluctuating torque every 0.01 s.
  EXPECT_NEAR(torque, expected, 0.05 * std::abs(expected));
  // The summary's mean shaft torque (work of the walls / omega / time) is the same quantity.
  fs::remove_all(opt.out_dir);
}
