// LIGGGHTS/LAMMPS dump reader and the front-view angle of particle frames: a lattice of balls
// filling the drum below a plane surface of known slope must give that slope back.
#include <gtest/gtest.h>

#include <cmath>
#include <filesystem>
#include <fstream>

#include "millsim/core/error.hpp"
#include "millsim/io/particle_dump.hpp"
#include "millsim/vision/front_view_angle.hpp"

namespace fs = std::filesystem;
using millsim::io::readParticleDump;

namespace {

fs::path tempFile(const std::string& name) {
  const fs::path d = fs::temp_directory_path() / ("millsim_dump_" + std::to_string(::getpid()));
  fs::create_directories(d);
  return d / name;
}

// Balls of radius r on a square lattice inside a drum of radius R, below y = -tan(a) x (a surface
// through the centre falling to the right at angle a), written as LIGGGHTS dump frames.
void writeLatticeDump(const fs::path& f, double a_deg, int frames, bool diameter_column) {
  const double R = 0.146, r = 0.004, slope = -std::tan(a_deg * M_PI / 180);
  std::ofstream out(f);
  for (int t = 0; t < frames; ++t) {
    std::vector<std::array<double, 3>> balls;
    for (double x = -R; x <= R; x += 2 * r)
      for (double y = -R; y <= R; y += 2 * r)
        if (std::hypot(x, y) < R - r && y + r < slope * x) balls.push_back({x, y, 0.05});
    out << "ITEM: TIMESTEP\n" << 1000 * t << "\nITEM: NUMBER OF ATOMS\n" << balls.size() << "\n";
    out << "ITEM: BOX BOUNDS ff ff ff\n-0.2 0.2\n-0.2 0.2\n0 0.1\n";
    out << (diameter_column ? "ITEM: ATOMS id type diameter x y z\n" : "ITEM: ATOMS id x y z radius\n");
    int id = 1;
    for (const auto& b : balls) {
      if (diameter_column)
        out << id++ << " 1 " << 2 * r << " " << b[0] << " " << b[1] << " " << b[2] << "\n";
      else
        out << id++ << " " << b[0] << " " << b[1] << " " << b[2] << " " << r << "\n";
    }
  }
}

}  // namespace

TEST(ParticleDump, ReadsFramesInAnyColumnOrder) {
  const auto f = tempFile("a.dump");
  writeLatticeDump(f, 40, 3, true);
  const auto frames = readParticleDump(f.string());
  ASSERT_EQ(frames.size(), 3u);
  EXPECT_EQ(frames[2].timestep, 2000);
  ASSERT_FALSE(frames[0].x.empty());
  EXPECT_DOUBLE_EQ(frames[0].radius[0], 0.004);
  EXPECT_DOUBLE_EQ(frames[0].z[0], 0.05);
}

TEST(ParticleDump, ErrorsNameFileAndLine) {
  const auto f = tempFile("bad.dump");
  std::ofstream(f) << "ITEM: TIMESTEP\n0\nITEM: NUMBER OF ATOMS\n2\nITEM: ATOMS id x y\n1 0 0\n2 0 0\n";
  try {
    readParticleDump(f.string());
    FAIL() << "no error";
  } catch (const millsim::core::InputError& e) {
    EXPECT_NE(std::string(e.what()).find(f.string() + ":5:"), std::string::npos) << e.what();
  }
  EXPECT_THROW(readParticleDump((f.parent_path() / "missing.dump").string()), millsim::core::InputError);
}

// The lattice edge is a staircase of 8 mm balls: its regression line has the slope of the
// plane within ~0.5 deg over a 100+ mm window; the highest point sits at the drum wall on the
// left, and the fit starts 60 mm right of it as in the paper. Tolerance 1 deg.
TEST(FrontViewAngle, RecoversSurfaceSlopeOfParticleFrames) {
  for (double a : {35.0, 42.0}) {
    const auto f = tempFile("lattice.dump");
    writeLatticeDump(f, a, 2, false);
    millsim::vision::FrontViewAngle angle(0.292, millsim::vision::AngleOptions{});
    for (const auto& fr : readParticleDump(f.string())) angle.addFrame(fr.x, fr.y, fr.radius);
    EXPECT_EQ(angle.frames(), 2);
    EXPECT_NEAR(angle.measure().angle_deg, a, 1.0);
  }
}
