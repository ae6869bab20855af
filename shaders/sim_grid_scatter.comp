// Neighbour grid, pass 3 (after the scan turned counts into starts): slot of each item.
layout(local_size_x = 64) in;
layout(std430, binding = SPHFX_SSBO_SIM_CELL_START) readonly buffer GridCellStart { uint cellStart[]; };
layout(std430, binding = SPHFX_SSBO_SIM_GRID_CELL_RANK) readonly buffer GridCellRank { uvec2 cellRank[]; };
layout(std430, binding = SPHFX_SSBO_SIM_GRID_SORTED) writeonly buffer GridSorted { uint sortedIndex[]; };
#if defined(SIM_DYNAMIC_COUNT)
// The fluid grid of a scene whose count changes: the items are the live particles (sph_dynamic.glsl).
#include "sph_dynamic.glsl"
#define uItemCount dynLive
#else
uniform uint uItemCount;
#endif

void main() {
  uint i = sphfxGlobalIndex();
  if (i >= uItemCount) return;
  uvec2 cr = cellRank[i];
  // The slab bits (sim_grid_cells.comp) travel with the index into the sort key.
  sortedIndex[cellStart[cr.x] + (cr.y & 0x3FFFFFFFu)] = i | (cr.y & 0xC0000000u);
}
