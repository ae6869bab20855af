// The neighbour walk, the one loop over the grid cells near a particle and the items in them that every
// pass summing over neighbours uses, so that they all visit the same candidates in the same order.
//
//   SPH_FOR_EACH_CELL_RANGE(xi, row, seam, first, last) { ... } SPH_END_FOR_EACH_CELL_RANGE
// runs its body once per range [first, last) of cells that the kernel sphere of xi may reach: the rows
// (dy, dz) of the 3x3x3 cells around xi, z outer (row = 3 (dz + 1) + dy + 1), each as sphRow() trims
// it, and with SIM_PERIODIC_X, before the row, its cell across the seam (sphRowWrap(), `seam` true).
// SPH_FOR_EACH_CELL_RANGE_SEAM_LAST visits the seam cell after the row (sim_density.comp: floating-point
// sums depend on their order, so each pass keeps its own). `continue` in the body skips to the next range.
//
//   SPH_FOR_EACH_FLUID(j, first, last) { ... }, SPH_FOR_EACH_BOUNDARY(j, first, last) { ... }
// loop over the sorted indices j of the fluid particles / boundary samples in cells [first, last) (one
// range: items are sorted by cell). The cell starts are read through SPH_FLUID_START(c) and
// SPH_BOUNDARY_START(c), the buffer-texture views (sph_textures.glsl) unless the pass defines them before
// including this file.
#include "sph_kernels.glsl"

#ifndef SPH_FLUID_START
#define SPH_FLUID_START(c) sphFetchCellStart(c)
#endif
#ifndef SPH_BOUNDARY_START
#define SPH_BOUNDARY_START(c) sphFetchBoundaryCellStart(c)
#endif

#if defined(SIM_PERIODIC_X)
#define SPH_WALK_PARTS 2
#else
#define SPH_WALK_PARTS 1
#endif

// The cells of row (dy, dz) of `cell`: the row itself, or (seam, SIM_PERIODIC_X) the cell across the seam.
bool sphWalkRange(vec3 xi, ivec3 cell, int dy, int dz, bool seam, out uint first, out uint last) {
#if defined(SIM_PERIODIC_X)
  if (seam) return sphRowWrap(cell, dy, dz, first, last);
#endif
  return sphRow(xi, cell, dy, dz, first, last);
}

#define SPH_WALK_CELL_RANGES(xi, row, seam, first, last, seamPart)                          \
  {                                                                                          \
    ivec3 sphWalkCell = sphCell(xi);                                                         \
    for (int sphWalkDz = -1; sphWalkDz <= 1; ++sphWalkDz)                                    \
      for (int sphWalkDy = -1; sphWalkDy <= 1; ++sphWalkDy)                                  \
        for (int sphWalkPart = 0; sphWalkPart < SPH_WALK_PARTS; ++sphWalkPart) {             \
          uint row = uint(3 * (sphWalkDz + 1) + sphWalkDy + 1);                              \
          bool seam = SPH_WALK_PARTS > 1 && sphWalkPart == (seamPart);                       \
          uint first, last;                                                                  \
          if (!sphWalkRange(xi, sphWalkCell, sphWalkDy, sphWalkDz, seam, first, last)) continue;

#define SPH_FOR_EACH_CELL_RANGE(xi, row, seam, first, last) \
  SPH_WALK_CELL_RANGES(xi, row, seam, first, last, 0)
#define SPH_FOR_EACH_CELL_RANGE_SEAM_LAST(xi, row, seam, first, last) \
  SPH_WALK_CELL_RANGES(xi, row, seam, first, last, 1)
#define SPH_END_FOR_EACH_CELL_RANGE \
  }                                 \
  }

#define SPH_FOR_EACH_FLUID(j, first, last) \
  for (uint j = SPH_FLUID_START(first), sphItemsEnd = SPH_FLUID_START(last); j < sphItemsEnd; ++j)
#define SPH_FOR_EACH_BOUNDARY(j, first, last) \
  for (uint j = SPH_BOUNDARY_START(first), sphItemsEnd = SPH_BOUNDARY_START(last); j < sphItemsEnd; ++j)
