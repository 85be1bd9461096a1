#include "millsim/io/particle_dump.hpp"

#include <fstream>
#include <sstream>

#include "millsim/core/error.hpp"

namespace millsim::io {

namespace {

int columnOf(const std::vector<std::string>& cols, const std::string& name) {
  for (std::size_t i = 0; i < cols.size(); ++i)
    if (cols[i] == name) return static_cast<int>(i);
  return -1;
}

}  // namespace

std::vector<ParticleFrame> readParticleDump(const std::string& path) {
  std::ifstream in(path);
  if (!in) throw core::InputError(path + ": cannot open particle dump");
  std::vector<ParticleFrame> frames;
  std::string line;
  int line_no = 0;
  auto next = [&](const char* what) {
    if (!std::getline(in, line)) throw core::InputError(path, line_no, std::string("unexpected end of file, expected ") + what);
    ++line_no;
  };
  std::int64_t timestep = 0;
  long count = -1;
  while (std::getline(in, line)) {
    ++line_no;
    if (line.rfind("ITEM: TIMESTEP", 0) == 0) {
      next("a timestep");
      timestep = std::stoll(line);
    } else if (line.rfind("ITEM: NUMBER OF ATOMS", 0) == 0) {
      next("an atom count");
      count = std::stol(line);
    } else if (line.rfind("ITEM: ATOMS", 0) == 0) {
      std::istringstream h(line.substr(11));
      std::vector<std::string> cols;
      for (std::string c; h >> c;) cols.push_back(c);
      const int cx = columnOf(cols, "x"), cy = columnOf(cols, "y"), cz = columnOf(cols, "z");
      int cr = columnOf(cols, "radius");
      const bool diameter = cr < 0;
      if (diameter) cr = columnOf(cols, "diameter");
      if (cx < 0 || cy < 0 || cz < 0 || cr < 0)
        throw core::InputError(path, line_no, "ITEM: ATOMS needs columns x, y, z and radius (or diameter)");
      if (count < 0) throw core::InputError(path, line_no, "ITEM: ATOMS before ITEM: NUMBER OF ATOMS");
      ParticleFrame f;
      f.timestep = timestep;
      std::vector<double> v(cols.size());
      for (long i = 0; i < count; ++i) {
        next("an atom line");
        std::istringstream a(line);
        for (auto& x : v)
          if (!(a >> x)) throw core::InputError(path, line_no, "expected " + std::to_string(cols.size()) + " numbers");
        f.x.push_back(v[cx]);
        f.y.push_back(v[cy]);
        f.z.push_back(v[cz]);
        f.radius.push_back(diameter ? 0.5 * v[cr] : v[cr]);
      }
      frames.push_back(std::move(f));
    }
  }
  return frames;
}

}  // namespace millsim::io
