#pragma once
// Uniform cell grid for cell-linked neighbour search (2D: nz = 1 and z ignored). Particles are
// sorted by cell key so the particles of one cell are contiguous; a query visits the block of
// (2 reach + 1)^dim cells around a point: reach 1 with cells of the interaction distance (DEM),
// reach 2 with cells of half of it (SPH: 125 h^3 searched instead of 216 h^3 in 3D). Points outside the grid are
// clamped into the border cells, which keeps every pair within one cell size in adjacent cells (the distance test
// decides the rest).
#include "millsim/core/hd.hpp"
#include "millsim/core/vec3.hpp"

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

  // Calls f(j) for every particle j in the cells adjacent to p (including p's own cell).
  template <class F>
  MILLSIM_HD void forEachCandidate(core::Vec3<T> p, F&& f) const {
    int cx, cy, cz;
    grid.cellCoords(p, cx, cy, cz);
    const int r = grid.reach;
    const int z0 = cz > r ? cz - r : 0, z1 = cz + r < grid.nz ? cz + r : grid.nz - 1;
    const int y0 = cy > r ? cy - r : 0, y1 = cy + r < grid.ny ? cy + r : grid.ny - 1;
    const int x0 = cx > r ? cx - r : 0, x1 = cx + r < grid.nx ? cx + r : grid.nx - 1;
    for (int z = z0; z <= z1; ++z)
      for (int y = y0; y <= y1; ++y) {
        // Cells x0..x1 of a row are contiguous in key order, and so are their particles: the
        // row is one range from the first non-empty cell's start to the last one's end.
        const int k0 = grid.key(x0, y, z), k1 = grid.key(x1, y, z);
        int begin = -1, end = -1;
        for (int k = k0; k <= k1; ++k)
          if (cell_start[k] < cell_end[k]) {
            if (begin < 0) begin = cell_start[k];
            end = cell_end[k];
          }
        for (int s = begin; s < end; ++s) f(order[s]);
      }
  }
};

}  // namespace millsim::neighbors
