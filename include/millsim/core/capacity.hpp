// One growth rule for the step loop's grow-only buffers (neighbour lists, spring tables,
// per-thread partner rows): a quarter to spare plus a small floor, so a bed that packs a little
// tighter at the next rebuild, or a window that grows by a row, finds its room already there
// and the step loop does not allocate (tests/unit/test_step_allocations.cpp).
#pragma once

#include <cstddef>

namespace millsim::core {

inline std::size_t withSpare(std::size_t need) { return need + need / 4 + 64; }

}  // namespace millsim::core
