// evaluations.csv: read back on start, one flushed row per finished evaluation (see header).
#include "millsim/calib/journal.hpp"

#include <cstdio>
#include <filesystem>
#include <fstream>
#include <sstream>

#include "millsim/core/error.hpp"

namespace millsim::calib {

namespace {

const char* const kMagic = "# millsim calibrate journal; signature=";

std::string header(const std::vector<std::string>& labels) {
  std::string h = "index,e,mu,sse,ok,wall_s";
  for (const auto& l : labels) h += ",angle_" + l;
  return h + ",error";
}

std::vector<std::string> splitCsv(const std::string& line) {
  std::vector<std::string> out;
  std::string cell;
  std::istringstream in(line);
  while (std::getline(in, cell, ',')) out.push_back(cell);
  if (!line.empty() && line.back() == ',') out.emplace_back();
  return out;
}

std::string number(double v) {
  char buf[40];
  std::snprintf(buf, sizeof buf, "%.17g", v);
  return buf;
}

// Errors are free text; keep the row one CSV line.
std::string clean(std::string s) {
  for (char& c : s)
    if (c == ',' || c == '\n' || c == '\r') c = ';';
  return s;
}

}  // namespace

Journal::Journal(std::string path, std::string signature, std::vector<std::string> labels)
    : m_path(std::move(path)), m_labels(std::move(labels)) {
  const std::string expected_header = header(m_labels);
  if (std::filesystem::exists(m_path)) {
    std::ifstream in(m_path);
    std::string line;
    int line_no = 0;
    if (!std::getline(in, line) || line != kMagic + signature)
      throw core::InputError(m_path, 1,
                             "journal of another calibration (different measured angles, cases, overrides or "
                             "objective); choose another --out or remove the file");
    ++line_no;
    if (!std::getline(in, line) || line != expected_header)
      throw core::InputError(m_path, 2, "unexpected columns; expected '" + expected_header + "'");
    ++line_no;
    const std::size_t columns = 7 + m_labels.size();
    while (std::getline(in, line)) {
      ++line_no;
      if (line.empty()) continue;
      const auto cells = splitCsv(line);
      // A row cut short by an interruption is ignored: that evaluation is simply redone.
      if (cells.size() != columns) continue;
      try {
        Evaluation ev;
        ev.candidate.index = std::stoi(cells[0]);
        ev.candidate.e = std::stod(cells[1]);
        ev.candidate.mu = std::stod(cells[2]);
        ev.sse = std::stod(cells[3]);
        ev.ok = cells[4] == "1";
        ev.wall_s = std::stod(cells[5]);
        for (std::size_t k = 0; k < m_labels.size(); ++k) ev.angles_deg.push_back(std::stod(cells[6 + k]));
        ev.error = cells.back();
        m_loaded.push_back(ev);
      } catch (const std::exception&) {
        throw core::InputError(m_path, line_no, "unreadable journal row");
      }
    }
  } else {
    const auto parent = std::filesystem::path(m_path).parent_path();
    if (!parent.empty()) std::filesystem::create_directories(parent);
    std::ofstream out(m_path);
    if (!out) throw core::InputError(m_path, 0, "cannot create the journal");
    out << kMagic << signature << "\n" << expected_header << "\n";
  }
}

void Journal::append(const Evaluation& ev) {
  std::string row = std::to_string(ev.candidate.index) + "," + number(ev.candidate.e) + "," + number(ev.candidate.mu) +
                    "," + number(ev.sse) + "," + (ev.ok ? "1" : "0") + "," + number(ev.wall_s);
  for (std::size_t k = 0; k < m_labels.size(); ++k)
    row += "," + (k < ev.angles_deg.size() ? number(ev.angles_deg[k]) : std::string("nan"));
  row += "," + clean(ev.error) + "\n";
  std::lock_guard<std::mutex> lock(m_mutex);
  std::ofstream out(m_path, std::ios::app);
  out << row;
  out.flush();
  if (!out) throw std::runtime_error(m_path + ": cannot append to the journal");
}

}  // namespace millsim::calib
