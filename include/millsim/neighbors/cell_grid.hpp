#pragma once
// Uniform cell grid for cell-linked neighbour search (2D: nz = 1 and z ignored). Particles are
// sorted by cell key so the particles of one cell are contiguous; a query visits the 3x3(x3)
// block of cells around a point. Points outside the grid are clamped into the border cells, which
// keeps every pair within one cell size in adjacent cells (the distance test decides the rest).
#include "millsim/core/hd.hpp"
#include "millsim/core/vec3.hpp"

namespace millsim::neighbors {

template <class T>
struct CellGrid {
  core::Vec3<T> origin;
  T inv_cell;  // 1 / cell size
  int nx, ny, nz;

  MILLSIM_HD int cellCount() const { return nx * ny * nz; }

  MILLSIM_HD static int clampIndex(T v, int n) {
    int c = static_cast<int>(v);  // v >= 0 here truncates like floor; negatives clamp below
    if (v < T(0)) c = 0;
    return c >= n ? n - 1 : c;
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
    const int z0 = cz > 0 ? cz - 1 : 0, z1 = cz + 1 < grid.nz ? cz + 1 : grid.nz - 1;
    const int y0 = cy > 0 ? cy - 1 : 0, y1 = cy + 1 < grid.ny ? cy + 1 : grid.ny - 1;
    const int x0 = cx > 0 ? cx - 1 : 0, x1 = cx + 1 < grid.nx ? cx + 1 : grid.nx - 1;
    for (int z = z0; z <= z1; ++z)
      for (int y = y0; y <= y1; ++y) {
        // Cells x0..x1 of a row are contiguous in key order, so one range covers the row.
        const int k0 = grid.key(x0, y, z), k1 = grid.key(x1, y, z);
        for (int k = k0; k <= k1; ++k)
          for (int s = cell_start[k]; s < cell_end[k]; ++s) f(order[s]);
      }
  }
};

}  // namespace millsim::neighbors
