#pragma once
// Diagnostic tests that run a list of variants picked by an environment variable: runs are
// separated by spaces, their fields by ':' ("4:no_slip 6:dbc:mdbc"); a missing field is empty.
#include <algorithm>
#include <cstdlib>
#include <sstream>
#include <string>
#include <vector>

namespace millsim::testing {

// The runs of `var`, or of `fallback` when it is not set, each padded to `fields` fields.
inline std::vector<std::vector<std::string>> envRuns(const char* var, const char* fallback, std::size_t fields) {
  const char* env = std::getenv(var);
  std::istringstream runs(env ? env : fallback);
  std::vector<std::vector<std::string>> out;
  for (std::string run; runs >> run;) {
    std::istringstream in(run);
    std::vector<std::string> f;
    for (std::string field; std::getline(in, field, ':');) f.push_back(field);
    f.resize(std::max(f.size(), fields));
    out.push_back(f);
  }
  return out;
}

}  // namespace millsim::testing
