#pragma once
// `millsim compare-power DIR... [--measured CSV] [--png FILE]`: the net-power curves of several
// stirred-mill runs side by side (their OUT/power.csv), whether each rises monotonically with
// speed, and, against a measured curve, the summed squared difference the seed calibrates mu_c
// by (seed 004 section 4.1). Registered and dispatched by main.cpp.
#include <CLI/CLI.hpp>
#include <string>
#include <vector>

namespace millsim::cli {

struct ComparePowerArgs {
  std::vector<std::string> dirs;
  std::vector<std::string> labels;
  std::string measured;  // CSV: rpm,power_W (net power), one header line
  std::string png;
};

CLI::App* addComparePowerCommand(CLI::App& app, ComparePowerArgs& args);

// Prints the comparison as JSON; throws core::InputError naming the file (and line) of bad input.
int comparePowerCommand(const ComparePowerArgs& args);

}  // namespace millsim::cli
