#pragma once
// Errors a user can act on. InputError carries file:line so the CLI prints one line naming the
// place; the CLI maps InputError to exit code 2 and SimulationError (instability) to 3.
#include <stdexcept>
#include <string>

namespace millsim::core {

class InputError : public std::runtime_error {
 public:
  InputError(const std::string& file, int line, const std::string& what)
      : std::runtime_error(file + ":" + std::to_string(line) + ": " + what), m_file(file), m_line(line) {}
  explicit InputError(const std::string& what) : std::runtime_error(what), m_line(0) {}
  const std::string& file() const { return m_file; }
  int line() const { return m_line; }

 private:
  std::string m_file;
  int m_line;
};

// A run that went unstable: NaN, escaped particles, ... The last good state is on disk.
class SimulationError : public std::runtime_error {
 public:
  using std::runtime_error::runtime_error;
};

}  // namespace millsim::core
