#pragma once
// Builds a CellListView on any execution space: key per particle -> sort (key, index) by key ->
// cell ranges. All steps are functors run through the backend, so OpenMP and CUDA share them.
#include <cmath>
#include <vector>

#include "millsim/backend/omp.hpp"
#include "millsim/neighbors/cell_grid.hpp"

namespace millsim::neighbors {

// Key of each particle: its cell, or `out_key` (one past the last cell, never searched) when
// its code is >= skip_from (particles excluded from a run, which sort to the end).
template <class T>
struct CellKeyFunctor {
  CellGrid<T> grid;
  const core::Vec3<T>* pos;
  const int* code;  // nullptr: every particle takes part
  int skip_from;
  int out_key;
  int* keys;
  int* order;
  MILLSIM_HD void operator()(int i) const {
    keys[i] = code && code[i] >= skip_from ? out_key : grid.cellOf(pos[i]);
    order[i] = i;
  }
};

struct CellRangeFunctor {
  const int* sorted_keys;
  int n;
  int* cell_start;
  int* cell_end;
  int out_key;
  MILLSIM_HD void operator()(int s) const {
    const int k = sorted_keys[s];
    if (k == out_key) return;
    if (s == 0 || sorted_keys[s - 1] != k) cell_start[k] = s;
    if (s == n - 1 || sorted_keys[s + 1] != k) cell_end[k] = s + 1;
  }
};

struct IdentityFunctor {
  int* order;
  MILLSIM_HD void operator()(int s) const { order[s] = s; }
};

struct ClearCellsFunctor {
  int* cell_start;
  int* cell_end;
  MILLSIM_HD void operator()(int k) const {
    cell_start[k] = 0;
    cell_end[k] = 0;
  }
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

template <class Space, class T>
class CellList {
 public:
  void setGrid(const CellGrid<T>& grid) {
    m_grid = grid;
    m_start.resize(static_cast<std::size_t>(grid.cellCount()));
    m_end.resize(static_cast<std::size_t>(grid.cellCount()));
  }
  const CellGrid<T>& grid() const { return m_grid; }

  void build(const core::Vec3<T>* pos, int n) { build(pos, n, nullptr, 0); }

  // As build(), leaving out particles whose code is >= skip_from: they sort to the end of the
  // order and no search finds them.
  void build(const core::Vec3<T>* pos, int n, const int* code, int skip_from) {
    using backend::parallelFor;
    using backend::sortByKey;
    if (static_cast<int>(m_keys.size()) != n) {
      m_keys.resize(n);
      m_order.resize(n);
    }
    const int out_key = m_grid.cellCount();
    parallelFor(Space{}, n, CellKeyFunctor<T>{m_grid, pos, code, skip_from, out_key, m_keys.data(), m_order.data()});
    sortByKey(Space{}, m_keys.data(), m_order.data(), n, out_key + 1, m_scratch);
    parallelFor(Space{}, m_grid.cellCount(), ClearCellsFunctor{m_start.data(), m_end.data()});
    parallelFor(Space{}, n, CellRangeFunctor{m_keys.data(), n, m_start.data(), m_end.data(), out_key});
  }

  // After the caller renumbered its particles by the sorted order of the last build(), the
  // cells stay valid and slot s now holds particle s.
  void renumberedInOrder() { backend::parallelFor(Space{}, static_cast<int>(m_order.size()), IdentityFunctor{m_order.data()}); }

  CellListView<T> view() const { return {m_grid, m_order.data(), m_start.data(), m_end.data()}; }
  std::size_t bytes() const { return m_keys.bytes() + m_order.bytes() + m_start.bytes() + m_end.bytes(); }

 private:
  CellGrid<T> m_grid{};
  backend::Array<Space, int> m_keys, m_order, m_start, m_end;
  std::vector<int> m_scratch;
};

}  // namespace millsim::neighbors
