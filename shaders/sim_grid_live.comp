// Neighbour grid of a scene whose particle count changes (SIM_DYNAMIC_COUNT), one invocation after the
// sort: the live particles are those sorted into the grid's cells, the slots before the out-of-reach
// cell's start. Removed particles (SIM_REMOVED_POSITION) sorted into that cell and drop out here, so the
// sorted buffers are compacted and keep every survivor's id.
#include "sph_dynamic.glsl"
layout(local_size_x = 1) in;
layout(std430, binding = SPHFX_SSBO_SIM_CELL_START) readonly buffer GridCellStart { uint cellStart[]; };
uniform uint uCellCount;

void main() { dynLive = cellStart[uCellCount]; }
