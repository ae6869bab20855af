// Neighbour grid, pass 1: cell of each item and its rank among the items of that cell (atomic count).
// The rank's order is arbitrary; sim_grid_sort.comp makes the final order deterministic. With
// SIM_GRID_SPLIT_X the rank's top two bits hold the item's slab in x within its cell (0 to split - 1),
// by which sim_grid_sort.comp orders the cell first.
layout(local_size_x = 64) in;
layout(std430, binding = SPHFX_SSBO_SIM_GRID_SRC_POS) readonly buffer GridSrcPos { vec4 srcPos[]; };
layout(std430, binding = SPHFX_SSBO_SIM_CELL_START) buffer GridCellCount { uint cellCount[]; };
layout(std430, binding = SPHFX_SSBO_SIM_GRID_CELL_RANK) writeonly buffer GridCellRank { uvec2 cellRank[]; };
#if defined(SIM_DYNAMIC_COUNT)
// The fluid grid of a scene whose count changes: the items are the live particles (sph_dynamic.glsl).
#include "sph_dynamic.glsl"
#define uItemCount dynLive
#else
uniform uint uItemCount;
#endif
uniform vec3 uGridMin;
uniform float uInvCellSize;
uniform ivec3 uDims;

void main() {
  uint i = sphfxGlobalIndex();
  if (i >= uItemCount) return;
  vec3 g = (srcPos[i].xyz - uGridMin) * uInvCellSize;
  // Items more than one cell outside the grid (collider samples below the floor, NaN) can never be
  // within h of a particle: they go to the extra cell at index dims.x*dims.y*dims.z, never visited.
  uint outside = uint(uDims.x * uDims.y * uDims.z);
  bool inReach = all(greaterThanEqual(g, vec3(-1.0))) && all(lessThan(g, vec3(uDims) + 1.0));
  uint cell = inReach ? sphfxCellIndex(ivec3(floor(g)), uDims) : outside;
  uint slab = 0u;
#if defined(SIM_GRID_SPLIT_X)
  // The same floor as sphRow()'s range ends (a power-of-two split scales g exactly), clamped into the
  // cell as the cell is into the grid.
  int cx = clamp(int(floor(g.x)), 0, uDims.x - 1);
  if (inReach) slab = uint(clamp(int(floor(g.x * float(SIM_GRID_SPLIT_X))) - cx * SIM_GRID_SPLIT_X, 0,
                                 SIM_GRID_SPLIT_X - 1));
#endif
  cellRank[i] = uvec2(cell, atomicAdd(cellCount[cell], 1u) | (slab << 30));
}
