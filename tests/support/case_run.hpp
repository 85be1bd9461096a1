#pragma once
// Runs a shipped case through Simulation (the code path of `millsim run`) into a fresh
// directory and reads back what it wrote: series.csv by column, and summary.json.
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <map>
#include <nlohmann/json.hpp>
#include <sstream>
#include <string>
#include <vector>

#include "millsim/io/case_xml.hpp"
#include "millsim/sim/simulation.hpp"

namespace millsim::testing {

struct CaseOutput {
  std::map<std::string, std::vector<double>> series;
  nlohmann::json summary;
};

inline std::map<std::string, std::vector<double>> readSeries(const std::filesystem::path& csv) {
  std::ifstream in(csv);
  std::string line;
  std::getline(in, line);
  std::vector<std::string> names;
  std::stringstream header(line);
  for (std::string c; std::getline(header, c, ',');) names.push_back(c);
  std::map<std::string, std::vector<double>> cols;
  while (std::getline(in, line)) {
    std::stringstream row(line);
    std::string c;
    for (std::size_t k = 0; k < names.size() && std::getline(row, c, ','); ++k) cols[names[k]].push_back(std::stod(c));
  }
  return cols;
}

// backend: "omp" or "cuda" (tests/gpu). The case comes from MILLSIM_SOURCE_DIR in the environment
// when set (a copied tree, e.g. on the GPU machine), else from the tree the test was built in.
inline CaseOutput runCase(const std::string& case_name, const std::vector<std::string>& overrides,
                          const std::string& out_name, int threads = 1, const std::string& precision = "double",
                          const std::string& backend = "omp") {
  const char* env = std::getenv("MILLSIM_SOURCE_DIR");
  const auto path = std::filesystem::path(env ? env : MILLSIM_SOURCE_DIR) / "cases" / (case_name + ".xml");
  const auto out = std::filesystem::temp_directory_path() / ("millsim_test_" + out_name);
  std::filesystem::remove_all(out);
  sim::RunOptions opt;
  opt.out_dir = out.string();
  opt.threads = threads;
  opt.backend = backend;
  opt.precision = precision;
  sim::Simulation simulation(io::loadCaseFile(path.string(), overrides), opt);
  simulation.run();
  CaseOutput r;
  r.series = readSeries(out / "series.csv");
  std::ifstream js(out / "summary.json");
  r.summary = nlohmann::json::parse(js);
  return r;
}

}  // namespace millsim::testing
