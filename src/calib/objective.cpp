// Sum of squared errors between simulated and measured angles (paper section 3.9).
#include "millsim/calib/objective.hpp"

#include <stdexcept>

namespace millsim::calib {

double sumSquaredErrors(const std::vector<double>& simulated, const std::vector<double>& measured) {
  if (simulated.size() != measured.size()) throw std::invalid_argument("sumSquaredErrors: sizes differ");
  double s = 0;
  for (std::size_t i = 0; i < simulated.size(); ++i) s += (simulated[i] - measured[i]) * (simulated[i] - measured[i]);
  return s;
}

}  // namespace millsim::calib
