#pragma once
// OUT/evaluations.csv: one row per finished evaluation, appended (and flushed) as soon as it
// finishes, so a calibration that is interrupted loses at most the evaluations under way.
// Starting again with the same --out reads the rows back and evaluates only what is missing.
//   # millsim calibrate journal; signature=<Objective::signature()>
//   index,e,mu,sse,ok,wall_s,angle_<label>...,error
// Numbers are written with 17 significant digits, so a resumed run sees bit-identical values.
#include <mutex>
#include <string>
#include <vector>

#include "millsim/calib/objective.hpp"

namespace millsim::calib {

class Journal {
 public:
  // Opens (creating when absent) `path`. An existing file must carry the same signature and
  // labels, else core::InputError (a journal of another calibration is never mixed in).
  Journal(std::string path, std::string signature, std::vector<std::string> labels);

  const std::vector<Evaluation>& loaded() const { return m_loaded; }
  // Thread-safe append of one row.
  void append(const Evaluation& ev);
  const std::string& path() const { return m_path; }

 private:
  std::string m_path;
  std::vector<std::string> m_labels;
  std::vector<Evaluation> m_loaded;
  std::mutex m_mutex;
};

}  // namespace millsim::calib
