// Shaft torque against the moment balance of the charge: in steady rotation the drum's torque on
// the charge balances gravity's moment about the axis, so the time-averaged torque of the charge
// on the drum equals -M g <x_cg> (drum axis z, gravity -y, x_cg the charge's centre of mass).
// This checks the wall forces that power_W comes from against a quantity computed from
// positions only. 80 balls of 10 mm in the 100 mm minimal drum at 30% critical, averaged over
// [1, 3] s (rotation starts at 0.3 s).
//
// The torque's time average is taken from the walls' work (work_in_J, integrated every step:
// mean torque = delta W / (omega delta t)), not from the torque column, which samples a
// fluctuating quantity every 0.01 s: over charge seeds 1..20 the sampled mean deviates from
// -M g <x_cg> by sd 2-3% (up to 6.5%), the work-based one by sd 0.23% (up to 0.6%) (measured
// 2026-11-23, docs/validation.md).
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
  const int c_t = column("time_s"), c_tq = column("drum_torque_Nm"), c_x = column("com_x_m"),
            c_w = column("work_in_J");
  ASSERT_GE(c_x, 0);
  ASSERT_GE(c_w, 0);
  double sampled = 0, x_cg = 0, t0 = -1, w0 = 0, t1 = 0, w1 = 0;
  int n = 0;
  while (std::getline(in, line)) {
    std::stringstream ss(line);
    std::vector<double> v;
    for (std::string c; std::getline(ss, c, ',');) v.push_back(std::stod(c));
    if (v[c_t] < 1.0 - 1e-9) continue;
    if (t0 < 0) {
      t0 = v[c_t];
      w0 = v[c_w];
    }
    t1 = v[c_t];
    w1 = v[c_w];
    sampled += v[c_tq];
    x_cg += v[c_x];
    ++n;
  }
  ASSERT_GT(n, 150);
  sampled /= n;
  x_cg /= n;
  const double torque = (w1 - w0) / (summary.omega_rad_s * (t1 - t0));
  const double expected = -summary.charge_mass_kg * 9.81 * x_cg;
  // The charge is lifted on the left (clockwise drum): x_cg < 0, torque > 0.
  EXPECT_LT(x_cg, 0.0);
  // 2%: the balance holds up to the change of the charge's own angular momentum between the
  // window's ends (~M r^2 omega ~ 1e-3 N m s against ~0.13 N m s of torque impulse over the 2 s:
  // < 1%) and the sampling of x_cg every 0.01 s.
  EXPECT_NEAR(torque, expected, 0.02 * std::abs(expected));
  // The torque column is the same quantity sampled: its mean agrees within its sampling noise
  // (sd 3%, see above; 10% is over 3 sd).
  EXPECT_NEAR(sampled, torque, 0.10 * std::abs(torque));
  fs::remove_all(opt.out_dir);
}
