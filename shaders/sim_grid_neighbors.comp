// Diagnostics and tests: the ids (pos.w bits) of every item within h of each sorted item, found
// through the grid exactly as the solver passes find them (periodic scenes: compiled with the scene's
// defines, minimum-image distances and the row cells across the seam).
#include "sph_params.glsl"
#include "sph_kernels.glsl"
layout(local_size_x = 64) in;
layout(std430, binding = SPHFX_SSBO_SIM_POS) readonly buffer SimPos { vec4 pos[]; };
layout(std430, binding = SPHFX_SSBO_SIM_CELL_START) readonly buffer SimCellStart { uint cellStart[]; };
// Per item: count, then up to uMaxNeighbors ids.
layout(std430, binding = SPHFX_SSBO_SIM_GRID_NEIGHBORS) writeonly buffer GridNeighbors { uint neighbors[]; };
uniform uint uMaxNeighbors;

// Appends the items of cells [first, last) within h of xi; returns the new count.
uint collect(vec3 xi, uint first, uint last, uint base, uint n) {
  for (uint j = cellStart[first], e = cellStart[last]; j < e; ++j) {
    vec3 d = sphDelta(xi, pos[j].xyz);
    if (dot(d, d) < simKernel.w) {
      if (n < uMaxNeighbors) neighbors[base + 1u + n] = floatBitsToUint(pos[j].w);
      ++n;
    }
  }
  return n;
}

void main() {
  uint i = sphfxGlobalIndex();
  if (i >= simCounts.x) return;
  vec3 xi = pos[i].xyz;
  ivec3 cell = sphCell(xi);
  uint base = i * (uMaxNeighbors + 1u), n = 0u;
  for (int dz = -1; dz <= 1; ++dz)
    for (int dy = -1; dy <= 1; ++dy) {
      uint first, last;
#if defined(SIM_PERIODIC_X)
      if (sphRowWrap(cell, dy, dz, first, last)) n = collect(xi, first, last, base, n);
#endif
      if (sphRow(xi, cell, dy, dz, first, last)) n = collect(xi, first, last, base, n);
    }
  neighbors[base] = n;
}
