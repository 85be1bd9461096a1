#pragma once
// A run's CSV output (series.csv, power.csv) or a user's data file read back by column name, for
// the compare-* commands, and the comma lists and numbers of command-line options. Bad input
// throws core::InputError naming the file, line and column.
#include <algorithm>
#include <cmath>
#include <fstream>
#include <sstream>
#include <stdexcept>
#include <string>
#include <vector>

#include "millsim/core/error.hpp"

namespace millsim::cli {

// Comma-separated items with the blanks around each removed ("a, b,,c" -> a, b, "", c).
inline std::vector<std::string> splitList(const std::string& line) {
  std::vector<std::string> out;
  std::stringstream in(line);
  for (std::string c; std::getline(in, c, ',');) {
    const std::size_t a = c.find_first_not_of(" \t\r"), b = c.find_last_not_of(" \t\r");
    out.push_back(a == std::string::npos ? std::string() : c.substr(a, b - a + 1));
  }
  return out;
}

// True when all of `s` is one finite number (no trailing text), stored in v.
inline bool toNumber(const std::string& s, double& v) {
  std::size_t used = 0;
  try {
    v = std::stod(s, &used);
  } catch (const std::exception&) {
    return false;
  }
  return !s.empty() && used == s.size() && std::isfinite(v);
}

struct CsvTable {
  std::string path;
  std::vector<std::string> names;               // the header line's columns
  std::vector<std::vector<std::string>> cells;  // one row per data line
  std::vector<int> lines;                       // each row's line in the file (1-based)

  // The column called `name`; `what` says what kind of file was expected, for the error.
  std::size_t column(const std::string& name, const std::string& what) const {
    const auto it = std::find(names.begin(), names.end(), name);
    if (it == names.end()) throw core::InputError(path, 1, "no column '" + name + "' (" + what + ")");
    return static_cast<std::size_t>(it - names.begin());
  }

  double number(std::size_t row, std::size_t col) const {
    const std::string field = col < names.size() ? names[col] : "?";
    if (col >= cells[row].size()) throw core::InputError(path, lines[row], "no value for '" + field + "'");
    const std::string& s = cells[row][col];
    double v = 0;
    if (!toNumber(s, v)) throw core::InputError(path, lines[row], "'" + field + "' is not a number: '" + s + "'");
    return v;
  }
};

// `missing` completes "cannot open PATH" (e.g. how to produce the file). Blank lines are skipped.
inline CsvTable readCsvTable(const std::string& path, const std::string& missing) {
  std::ifstream in(path);
  if (!in) throw core::InputError(path + ": cannot open" + (missing.empty() ? "" : " (" + missing + ")"));
  CsvTable t;
  t.path = path;
  std::string line;
  if (!std::getline(in, line)) throw core::InputError(path, 1, "empty file: expected a header line");
  t.names = splitList(line);
  for (int n = 2; std::getline(in, line); ++n) {
    if (line.find_first_not_of(" \t\r") == std::string::npos) continue;
    t.cells.push_back(splitList(line));
    t.lines.push_back(n);
  }
  return t;
}

}  // namespace millsim::cli
