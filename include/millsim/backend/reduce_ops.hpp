#pragma once
// The combining step of reduceMax, one definition for both backends. A NaN anywhere in the
// input reaches the result: `a > b ? a : b` (thrust's usual maximum) and std::max drop a NaN or
// keep it depending on where it falls in the combination order, so the two backends could
// disagree, and a check such as "the step's largest acceleration is not finite" missed a NaN
// particle on the host (OpenMP's max reduction ignored it).
#include "millsim/core/hd.hpp"

namespace millsim::backend {

struct MaxKeepNan {
  template <class R>
  MILLSIM_HD R operator()(R a, R b) const {
    if (!(a == a)) return a;  // NaN (for integers never taken)
    if (!(b == b)) return b;
    return a > b ? a : b;
  }
};

}  // namespace millsim::backend
