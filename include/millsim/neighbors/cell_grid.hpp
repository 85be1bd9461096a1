#pragma once
// Uniform cell grid for cell-linked neighbour search (2D: nz = 1 and z ignored). Particles are
// sorted by cell key so the particles of one cell are contiguous; a query visits the block of
// (2 reach + 1)^dim cells around a point: reach 1 with cells of the interaction distance (DEM),
// reach 2 with cells of half of it (SPH: 125 h^3 searched instead of 216 h^3 in 3D). Points outside the grid are
// clamped into the border cells, which keeps every pair within one cell size in adjacent cells (the distance test
// decides the rest).
#include "millsim/core/hd.hpp"
#include "millsim/core/vec3.hpp"
#include "millsim/neighbors/slot_filter.hpp"

namespace millsim::neighbors {

template <class T>
struct CellGrid {
  core::Vec3<T> origin;
  T inv_cell;  // 1 / cell size
  int nx, ny, nz;
  int reach = 1;  // cells searched on each side of a point's own cell

  MILLSIM_HD int cellCount() const { return nx * ny * nz; }

  // Clamped in floating point before the conversion: a point far outside (a diverging run,
  // before the NaN check stops it) would overflow int, which is undefined and gave negative
  // cell keys (a crash instead of the run's error message). NaN goes to cell 0.
  MILLSIM_HD static int clampIndex(T v, int n) {
    if (!(v >= T(0))) return 0;
    if (v >= T(n)) return n - 1;
    return static_cast<int>(v);  // v >= 0: truncation is floor
  }
  MILLSIM_HD void cellCoords(core::Vec3<T> p, int& cx, int& cy, int& cz) const {
    cx = clampIndex((p.x - origin.x) * inv_cell, nx);
    cy = clampIndex((p.y - origin.y) * inv_cell, ny);
    cz = nz == 1 ? 0 : clampIndex((p.z - origin.z) * inv_cell, nz);
  }
  MILLSIM_HD int key(int cx, int cy, int cz) const { return (cz * ny + cy) * nx + cx; }
  MILLSIM_HD int cellOf(core::Vec3<T> p) const {
    int cx, cy, cz;
    cellCoords(p, cx, cy, cz);
    return key(cx, cy, cz);
  }
};

// Read-only view of a built cell list: `order` holds particle indices sorted by cell,
// cell_start/cell_end delimit each cell's range in `order` (start == end: empty).
template <class T>
struct CellListView {
  CellGrid<T> grid;
  const int* order;
  const int* cell_start;
  const int* cell_end;
  // order[s] == s (the particles were renumbered in cell order): on the host the distance test
  // then reads consecutive positions in vectors (slot_filter.hpp).
  bool in_order = false;

  // Calls f(j) for every particle j in the cells adjacent to p (including p's own cell).
  template <class F>
  MILLSIM_HD void forEachCandidate(core::Vec3<T> p, F&& f) const {
    const Block b = blockAround(p);
    for (int z = b.z0; z <= b.z1; ++z)
      for (int y = b.y0; y <= b.y1; ++y) {
        // Cells x0..x1 of a row are contiguous in key order, and so are their particles: the
        // row is one range of slots (empty cells have offsets too, cell_list.hpp).
        const int end = cell_end[grid.key(b.x1, y, z)];
        for (int s = cell_start[grid.key(b.x0, y, z)]; s < end; ++s) f(order[s]);
      }
  }

  // Calls f(j, d, r2) for every particle j in the cells adjacent to p with r2 = |d|^2 < radius2,
  // d = p - pos[j] (the point itself included, at r2 = 0), in the order of forEachCandidate.
  template <class F>
  MILLSIM_HD void forEachWithin(core::Vec3<T> p, T radius2, const core::Vec3<T>* pos, F&& f) const {
    const Block b = blockAround(p);
#ifndef __CUDA_ARCH__
    if (in_order && grid.reach <= kMaxReachInOrder) {
      Rows rows;
      for (int z = b.z0; z <= b.z1; ++z)
        for (int y = b.y0; y <= b.y1; ++y) rows.add(rowBegin(b, y, z), rowEnd(b, y, z));
      return scanRows(rows, p, radius2, pos, f);
    }
#endif
    for (int z = b.z0; z <= b.z1; ++z)
      for (int y = b.y0; y <= b.y1; ++y) scanSlots(rowBegin(b, y, z), rowEnd(b, y, z), p, radius2, pos, f);
  }

  // The same for the particles numbered after `self`, the slot of p in a renumbered list
  // (order = identity): each pair of the list is then found once, from its lower-numbered side.
  // Only the rows from p's own onwards are visited (the rows before hold lower numbers only),
  // p's own row from self + 1: about half the block.
  template <class F>
  MILLSIM_HD void forEachWithinAfter(int self, core::Vec3<T> p, T radius2, const core::Vec3<T>* pos, F&& f) const {
    const Block b = blockAround(p);
#ifndef __CUDA_ARCH__
    if (in_order && grid.reach <= kMaxReachInOrder) {
      Rows rows;
      rows.add(self + 1, rowEnd(b, b.cy, b.cz));
      for (int y = b.cy + 1; y <= b.y1; ++y) rows.add(rowBegin(b, y, b.cz), rowEnd(b, y, b.cz));
      for (int z = b.cz + 1; z <= b.z1; ++z)
        for (int y = b.y0; y <= b.y1; ++y) rows.add(rowBegin(b, y, z), rowEnd(b, y, z));
      return scanRows(rows, p, radius2, pos, f);
    }
#endif
    scanSlots(self + 1, rowEnd(b, b.cy, b.cz), p, radius2, pos, f);
    for (int y = b.cy + 1; y <= b.y1; ++y) scanSlots(rowBegin(b, y, b.cz), rowEnd(b, y, b.cz), p, radius2, pos, f);
    for (int z = b.cz + 1; z <= b.z1; ++z)
      for (int y = b.y0; y <= b.y1; ++y) scanSlots(rowBegin(b, y, z), rowEnd(b, y, z), p, radius2, pos, f);
  }

  // The block of cells searched around p: its own cell (cx, cy, cz) and reach cells each way,
  // cut at the grid's faces.
  struct Block {
    int cx, cy, cz, x0, x1, y0, y1, z0, z1;
  };
  MILLSIM_HD Block blockAround(core::Vec3<T> p) const {
    Block b;
    grid.cellCoords(p, b.cx, b.cy, b.cz);
    const int r = grid.reach;
    b.z0 = b.cz > r ? b.cz - r : 0, b.z1 = b.cz + r < grid.nz ? b.cz + r : grid.nz - 1;
    b.y0 = b.cy > r ? b.cy - r : 0, b.y1 = b.cy + r < grid.ny ? b.cy + r : grid.ny - 1;
    b.x0 = b.cx > r ? b.cx - r : 0, b.x1 = b.cx + r < grid.nx ? b.cx + r : grid.nx - 1;
    return b;
  }

  // Row (y, z) of the block: its cells x0..x1 are one range of slots.
  MILLSIM_HD int rowBegin(const Block& b, int y, int z) const { return cell_start[grid.key(b.x0, y, z)]; }
  MILLSIM_HD int rowEnd(const Block& b, int y, int z) const { return cell_end[grid.key(b.x1, y, z)]; }

#ifndef __CUDA_ARCH__
  // A renumbered search's rows, gathered for one call of the vectorised filter.
  static constexpr int kMaxReachInOrder = 2;
  struct Rows {
    static constexpr int kMax = (2 * kMaxReachInOrder + 1) * (2 * kMaxReachInOrder + 1);
    int begin[kMax], end[kMax];
    int count = 0, total = 0;
    void add(int b, int e) {
      begin[count] = b, end[count] = e;
      ++count;
      total += e > b ? e - b : 0;
    }
  };
  // Host, renumbered: all the rows' candidates filtered in one call (filterRangesInOrder), then
  // f on the hits, in row order. A block with more candidates than the buffer (a dense cluster)
  // goes row by row through scanSlots.
  template <class F>
  void scanRows(const Rows& rows, core::Vec3<T> p, T radius2, const core::Vec3<T>* pos, F& f) const {
    constexpr int kBuf = 512;
    if (rows.total > kBuf) {
      for (int k = 0; k < rows.count; ++k) scanSlots(rows.begin[k], rows.end[k], p, radius2, pos, f);
      return;
    }
    int hit[kBuf + kSlotFilterPad];
    T hit_r2[kBuf + kSlotFilterPad];
    const int n = filterRangesInOrder(rows.begin, rows.end, rows.count, p, radius2, pos, hit, hit_r2);
    for (int q = 0; q < n; ++q) f(hit[q], p - pos[hit[q]], hit_r2[q]);
  }
#endif

  // The candidates in slots [begin, end) within the radius. On the host they are first filtered
  // into a small buffer without a branch, then f runs on the hits: in an SPH search about a
  // quarter of the candidates are hits, in random order within their cells, so a branch per
  // candidate mispredicts often (filtered, the search loop over a 3D lattice ran ~30% faster;
  // trimming the rows to the support sphere's chord was slower, its per-row square root costing
  // more than the candidates it saved). Renumbered in order, the filter is vectorised
  // (filterRangesInOrder). On a GPU each thread tests and calls directly.
  template <class F>
  MILLSIM_HD MILLSIM_FORCE_INLINE void scanSlots(int begin, int end, core::Vec3<T> p, T radius2,
                                                 const core::Vec3<T>* pos, F& f) const {
#ifdef __CUDA_ARCH__
    for (int s = begin; s < end; ++s) {
      const int j = order[s];
      const core::Vec3<T> d = p - pos[j];
      const T r2 = core::norm2(d);
      if (r2 < radius2) f(j, d, r2);
    }
#else
    constexpr int kBuf = 64;
    int hit[kBuf + kSlotFilterPad];
    T hit_r2[kBuf + kSlotFilterPad];
    for (int s0 = begin; s0 < end; s0 += kBuf) {
      const int s1 = end - s0 < kBuf ? end : s0 + kBuf;
      int n = 0;
      if (in_order) {
        n = filterRangesInOrder(&s0, &s1, 1, p, radius2, pos, hit, hit_r2);
      } else {
        for (int s = s0; s < s1; ++s) {
          const int j = order[s];
          const T r2 = core::norm2(p - pos[j]);
          hit[n] = j;
          hit_r2[n] = r2;
          n += r2 < radius2 ? 1 : 0;
        }
      }
      for (int q = 0; q < n; ++q) f(hit[q], p - pos[hit[q]], hit_r2[q]);
    }
#endif
  }
};

}  // namespace millsim::neighbors
