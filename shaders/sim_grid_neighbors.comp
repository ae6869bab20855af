// Diagnostics and tests: the ids (pos.w bits) of every item within h of each sorted item, found
// through the grid exactly as the solver passes find them (periodic scenes: compiled with the scene's
// defines, minimum-image distances and the row cells across the seam).
#include "sph_params.glsl"
#define SPH_FLUID_START(c) cellStart[c]
#include "sph_neighbors.glsl"
layout(local_size_x = 64) in;
layout(std430, binding = SPHFX_SSBO_SIM_POS) readonly buffer SimPos { vec4 pos[]; };
layout(std430, binding = SPHFX_SSBO_SIM_CELL_START) readonly buffer SimCellStart { uint cellStart[]; };
// Per item: count, then up to uMaxNeighbors ids.
layout(std430, binding = SPHFX_SSBO_SIM_GRID_NEIGHBORS) writeonly buffer GridNeighbors { uint neighbors[]; };
uniform uint uMaxNeighbors;

void main() {
  uint i = sphfxGlobalIndex();
  if (i >= simCounts.x) return;
  vec3 xi = pos[i].xyz;
  uint base = i * (uMaxNeighbors + 1u), n = 0u;
  SPH_FOR_EACH_CELL_RANGE(xi, row, seam, first, last)
    SPH_FOR_EACH_FLUID(j, first, last) {
      vec3 d = sphDelta(xi, pos[j].xyz);
      if (dot(d, d) < simKernel.w) {
        if (n < uMaxNeighbors) neighbors[base + 1u + n] = floatBitsToUint(pos[j].w);
        ++n;
      }
    }
  SPH_END_FOR_EACH_CELL_RANGE
  neighbors[base] = n;
}
