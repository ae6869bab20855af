// Neighbour grid, pass 4, one invocation per cell: sorts the cell's run of source indices (insertion
// sort; a cell holds about (h / spacing)^3 items), so the order is that of the previous step, i.e. a
// stable counting sort and deterministic; then gathers the items into the sorted arrays. With
// SIM_GRID_SPLIT_X the keys carry the item's slab in x in their top two bits (sim_grid_cells.comp), so a
// cell is ordered by slab first, and the pass writes where each slab starts: the row starts that
// sphRow() indexes (cell c's slab q at c * split + q, the same layout as a grid of h / split cells).
layout(local_size_x = 64) in;
layout(std430, binding = SPHFX_SSBO_SIM_GRID_SRC_POS) readonly buffer GridSrcPos { vec4 srcPos[]; };
layout(std430, binding = SPHFX_SSBO_SIM_GRID_SRC_VEL) readonly buffer GridSrcVel { vec4 srcVel[]; };
layout(std430, binding = SPHFX_SSBO_SIM_GRID_DST_POS) writeonly buffer GridDstPos { vec4 dstPos[]; };
layout(std430, binding = SPHFX_SSBO_SIM_GRID_DST_VEL) writeonly buffer GridDstVel { vec4 dstVel[]; };
layout(std430, binding = SPHFX_SSBO_SIM_CELL_START) readonly buffer GridCellStart { uint cellStart[]; };
layout(std430, binding = SPHFX_SSBO_SIM_GRID_SORTED) buffer GridSorted { uint sortedIndex[]; };
#if defined(SIM_GRID_SPLIT_X)
layout(std430, binding = SPHFX_SSBO_SIM_GRID_ROW_START) writeonly buffer GridRowStart { uint rowStart[]; };
#endif
uniform uint uCellCount;  // cells in the grid, without the out-of-reach cell (never visited)

void main() {
  uint c = sphfxGlobalIndex();
  if (c >= uCellCount) return;
  uint b = cellStart[c], e = cellStart[c + 1u];
  for (uint k = b + 1u; k < e; ++k) {
    uint key = sortedIndex[k];
    uint m = k;
    for (; m > b && sortedIndex[m - 1u] > key; --m) sortedIndex[m] = sortedIndex[m - 1u];
    sortedIndex[m] = key;
  }
#if defined(SIM_GRID_SPLIT_X)
  uint slab = 0u, row = c * uint(SIM_GRID_SPLIT_X);
  for (uint k = b; k < e; ++k) {
    uint key = sortedIndex[k];
    for (; slab <= (key >> 30); ++slab) rowStart[row + slab] = k;
    uint s = key & 0x3FFFFFFFu;
    sortedIndex[k] = s;
    dstPos[k] = srcPos[s];
    dstVel[k] = srcVel[s];
  }
  for (; slab < uint(SIM_GRID_SPLIT_X); ++slab) rowStart[row + slab] = e;
  // The ends: the out-of-reach cell's start and the item count, as in cellStart.
  if (c + 1u == uCellCount) {
    rowStart[uCellCount * uint(SIM_GRID_SPLIT_X)] = e;
    rowStart[uCellCount * uint(SIM_GRID_SPLIT_X) + 1u] = cellStart[c + 2u];
  }
#else
  for (uint k = b; k < e; ++k) {
    uint s = sortedIndex[k];
    dstPos[k] = srcPos[s];
    dstVel[k] = srcVel[s];
  }
#endif
}
