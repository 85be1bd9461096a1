#pragma once
// Builds a CellListView on any execution space: key per particle -> sort (key, index) by key ->
// cell offsets. All steps are functors run through the backend, so OpenMP and CUDA share them.
#include <cmath>
#include <vector>

#include "millsim/backend/omp.hpp"
#include "millsim/neighbors/cell_grid.hpp"

namespace millsim::neighbors {

// Key of each particle: its cell, or `out_key` (one past the last cell, never searched) when
// its code is >= skip_from (particles excluded from a run, which sort to the end).
// With two segments, particles whose code is >= split_from (and below skip_from) take keys
// cells + cell: they sort after all the others, each segment in cell order.
template <class T>
struct CellKeyFunctor {
  CellGrid<T> grid;
  const core::Vec3<T>* pos;
  const int* code;  // nullptr: every particle takes part
  int skip_from;
  int split_from;
  int out_key;
  int* keys;
  int* order;
  MILLSIM_HD void operator()(int i) const {
    if (!code) {
      keys[i] = grid.cellOf(pos[i]);
    } else {
      const int c = code[i];
      keys[i] = c >= skip_from ? out_key : grid.cellOf(pos[i]) + (c >= split_from ? grid.cellCount() : 0);
    }
    order[i] = i;
  }
};

// Cell offsets of the sorted keys (CSR): offsets[k] = first slot whose key is >= k, for k in
// [0, cells]; an empty cell has offsets[k] == offsets[k + 1]. Run over s in [0, n]: slot s
// writes the offsets of every key after the previous slot's, up to its own (slot n: up to
// `cells`), so each offset is written once, whatever the gaps. Empty cells having an offset too
// is what lets a search take a row of cells as one range without visiting each cell.
struct CellOffsetsFunctor {
  const int* sorted_keys;
  int n;
  int cells;  // = the out key: excluded particles sort after offsets[cells]
  int* offsets;
  MILLSIM_HD void operator()(int s) const {
    const int prev = s == 0 ? -1 : sorted_keys[s - 1];
    const int cur = s == n ? cells : sorted_keys[s];
    for (int k = prev + 1; k <= cur; ++k) offsets[k] = s;
  }
};

// Writes the offsets for any space; the CUDA backend overloads it (backend::cellOffsets, found by
// argument lookup on backend::Cuda) with one binary search per cell, because on a GPU the slot
// after a long run of empty cells (a sparse domain's margins: 1e6 cells in a 1e7-particle dam
// break) would fill it alone.
template <class Space>
void cellOffsets(Space, const int* sorted_keys, int n, int cells, int* offsets) {
  backend::parallelFor(Space{}, n + 1, CellOffsetsFunctor{sorted_keys, n, cells, offsets});
}

struct IdentityFunctor {
  int* order;
  MILLSIM_HD void operator()(int s) const { order[s] = s; }
};

// Grid covering [lo, hi] with cells of at least `cell`; searches visit `reach` cells on each
// side, so cell * reach must be at least the largest interaction distance.
template <class T>
CellGrid<T> makeGrid(core::Vec3<T> lo, core::Vec3<T> hi, T cell, bool two_d, int reach = 1) {
  auto count = [&](T a, T b) {
    const int n = static_cast<int>(std::ceil((b - a) / cell));
    return n < 1 ? 1 : n;
  };
  CellGrid<T> g{};
  g.origin = lo;
  g.inv_cell = T(1) / cell;
  g.nx = count(lo.x, hi.x);
  g.ny = count(lo.y, hi.y);
  g.nz = two_d ? 1 : count(lo.z, hi.z);
  g.reach = reach;
  return g;
}

// One sort for up to two segments of particles (SPH: fluid, then walls and bodies), each in cell
// order with its own offsets; view(k) searches segment k alone.
template <class Space, class T>
class CellList {
 public:
  void setGrid(const CellGrid<T>& grid, int segments = 1) {
    m_grid = grid;
    m_segments = segments;
    m_offsets.resize(static_cast<std::size_t>(segments) * grid.cellCount() + 1);
  }
  const CellGrid<T>& grid() const { return m_grid; }

  void build(const core::Vec3<T>* pos, int n) { build(pos, n, nullptr, 0); }

  // As build(), leaving out particles whose code is >= skip_from: they sort to the end of the
  // order and no search finds them. With two segments, codes in [split_from, skip_from) form
  // the second.
  void build(const core::Vec3<T>* pos, int n, const int* code, int skip_from, int split_from = 0) {
    using backend::parallelFor;
    using backend::sortByKey;
    if (static_cast<int>(m_keys.size()) != n) {
      m_keys.resize(n);
      m_order.resize(n);
    }
    const int split = m_segments > 1 ? split_from : skip_from;
    const int out_key = m_segments * m_grid.cellCount();
    parallelFor(Space{}, n,
                CellKeyFunctor<T>{m_grid, pos, code, skip_from, split, out_key, m_keys.data(), m_order.data()});
    sortByKey(Space{}, m_keys.data(), m_order.data(), n, out_key + 1, m_scratch);
    cellOffsets(Space{}, m_keys.data(), n, out_key, m_offsets.data());
    m_in_order = false;
  }

  // After the caller renumbered its particles by the sorted order of the last build(), the
  // cells stay valid and slot s now holds particle s.
  void renumberedInOrder() {
    backend::parallelFor(Space{}, static_cast<int>(m_order.size()), IdentityFunctor{m_order.data()});
    m_in_order = true;
  }

  // Cell k of segment g holds slots [offsets[g cells + k], offsets[g cells + k + 1]): the view's
  // cell_end is its cell_start shifted by one.
  CellListView<T> view(int segment = 0) const {
    const int* start = m_offsets.data() + static_cast<std::size_t>(segment) * m_grid.cellCount();
    return {m_grid, m_order.data(), start, start + 1, m_in_order};
  }
  std::size_t bytes() const { return m_keys.bytes() + m_order.bytes() + m_offsets.bytes(); }

 private:
  CellGrid<T> m_grid{};
  int m_segments = 1;
  bool m_in_order = false;  // order is the identity (renumberedInOrder since the last build)
  backend::Array<Space, int> m_keys, m_order, m_offsets;
  std::vector<int> m_scratch;
};

}  // namespace millsim::neighbors
