#pragma once
// The distance test of a host neighbour search, for a cell list whose particles were renumbered
// in cell order (slot s holds particle s, CellList::renumberedInOrder): the candidates of a row
// of cells are then consecutive positions, which a vector unit can load and test 4 to 16 at a
// time (three loads, a de-interleave of x, y, z by permutes, the squared distance, a compare,
// and the hits moved to the front of the buffer: a compress with AVX-512, a table of lane
// numbers with AVX2; other CPUs run the scalar test). Why: in the SPH pair loop the test of each candidate,
// one after another, was a quarter of a wet mill's step (perf, 2026-12-03; about a quarter of
// the candidates are hits).
//
// Every level returns the same hits in slot order with the same squared distances, bit for bit:
// r2 is summed as core::norm2 does it, ((dx dx + dy dy) + dz dz), without FMA contraction.
// Host only; the level follows backend::simdLevel() (MILLSIM_SIMD).
#include "millsim/core/vec3.hpp"

namespace millsim::neighbors {

// Entries the output buffers need past (end - begin): a vector store writes whole vectors.
inline constexpr int kSlotFilterPad = 16;

// Writes each slot s of the ranges [begin[k], end[k]), k < ranges, with |p - pos[s]|^2 <
// radius2 to hit[0..n) and its squared distance to hit_r2[0..n), range after range in slot
// order, and returns n. The buffers hold the ranges' total length + kSlotFilterPad entries. A
// search passes all the rows of its block in one call: a row holds about one vector of
// candidates, and a call per row spent as much time on its set-up as on the test.
template <class T>
int filterRangesInOrder(const int* begin, const int* end, int ranges, core::Vec3<T> p, T radius2,
                        const core::Vec3<T>* pos, int* hit, T* hit_r2);

extern template int filterRangesInOrder<float>(const int*, const int*, int, core::Vec3<float>, float,
                                               const core::Vec3<float>*, int*, float*);
extern template int filterRangesInOrder<double>(const int*, const int*, int, core::Vec3<double>, double,
                                                const core::Vec3<double>*, int*, double*);

}  // namespace millsim::neighbors
