// WCSPH pass 1 (then sim_boundary_pressure.comp, sim_force.comp): density (the scene kernel, sphW) from fluid neighbours and Akinci 2012 boundary samples (psi W), then
// pressure from the equation of state. Also reduces the largest density for the health check.
#include "sph_params.glsl"
#include "sph_group_max.glsl"
#define SPH_FLUID_START(c) cellStart[c]
#define SPH_BOUNDARY_START(c) bStart[c]
#include "sph_neighbors.glsl"
layout(local_size_x = SIM_WG) in;
layout(std430, binding = SPHFX_SSBO_SIM_POS) readonly buffer SimPos { vec4 pos[]; };
layout(std430, binding = SPHFX_SSBO_SIM_CELL_START) readonly buffer SimCellStart { uint cellStart[]; };
layout(std430, binding = SPHFX_SSBO_SIM_BOUNDARY_POS) readonly buffer SimBoundaryPos { vec4 bpos[]; };
layout(std430, binding = SPHFX_SSBO_SIM_BOUNDARY_CELL_START) readonly buffer SimBoundaryStart {
  uint bStart[];
};
layout(std430, binding = SPHFX_SSBO_SIM_DENSITY) writeonly buffer SimDensity { vec2 densityPressure[]; };
// Marks each boundary sample the walk visits (a superset of those within h) for sim_boundary_pressure.comp
// with -1 in its pressure slot: a pressure is never negative (sphPressure() clamps at 0), so the mark is
// not a value, and that pass overwrites every slot it finds non-zero.
#if !defined(SIM_VISIT_EVERY_SAMPLE)
#define SIM_MARK_SAMPLES
layout(std430, binding = SPHFX_SSBO_SIM_BOUNDARY_PRESSURE) writeonly buffer SimBoundaryPressure {
  float boundaryPressure[];
};
#endif
#if defined(SIM_NEIGHBOR_MASKS)
// Which candidates are within h, for the force pass (which otherwise tests ~7x more candidates than it
// uses): per row of cells (9 rows), a bit mask over the row's first 32 sorted slots, fluid in words 0-8
// (without i itself), boundary samples in words 9-17. Word k of particle i is at k * N + i, so adjacent
// invocations write adjacent words, once per row the kernel reaches (sim_force.comp reads no other).
// sim_force tests slots past the 32nd and the cell across a periodic seam itself.
layout(std430, binding = SPHFX_SSBO_SIM_NEIGHBORS) writeonly buffer SimNeighbors { uint neighbors[]; };
#endif

void main() {
  uint i = sphfxGlobalIndex();
  bool live = i < simCounts.x;
  SIM_GROUP_MAX_BEGIN();
  if (live) {
    vec3 xi = pos[i].xyz;
    float fluid = 0.0, wall = 0.0;
#if defined(SIM_NEIGHBOR_MASKS)
    uint n = simCounts.x;
#endif
    SPH_FOR_EACH_CELL_RANGE_SEAM_LAST(xi, row, seam, first, last)
      uint f0 = cellStart[first], b0 = bStart[first], fluidMask = 0u, wallMask = 0u;
      SPH_FOR_EACH_FLUID(j, first, last) {
        vec3 d = sphDelta(xi, pos[j].xyz);
        float r2 = dot(d, d);
        fluid += sphW(r2);
#if defined(SIM_NEIGHBOR_MASKS)
        if (r2 < simKernel.w && j != i && j - f0 < 32u) fluidMask |= 1u << (j - f0);
#endif
      }
      SPH_FOR_EACH_BOUNDARY(j, first, last) {
        vec4 b = bpos[j];
        vec3 d = sphDelta(xi, b.xyz);
        float r2 = dot(d, d);
        wall += b.w * sphW(r2);
#if defined(SIM_MARK_SAMPLES)
        boundaryPressure[j] = -1.0;  // every visiting invocation writes the same value
#endif
#if defined(SIM_NEIGHBOR_MASKS)
        if (r2 < simKernel.w && j - b0 < 32u) wallMask |= 1u << (j - b0);
#endif
      }
#if defined(SIM_NEIGHBOR_MASKS)
      if (!seam) {
        neighbors[row * n + i] = fluidMask;
        neighbors[(9u + row) * n + i] = wallMask;
      }
#endif
    SPH_END_FOR_EACH_CELL_RANGE
    float rho = simGravity.w * fluid + wall;
    densityPressure[i] = vec2(rho, sphPressure(rho) / (rho * rho));
    SIM_GROUP_MAX(0, stateMaxDensity, floatBitsToUint(rho));
  }
  SIM_GROUP_MAX_END();
  SIM_GROUP_MAX_FLUSH(0, stateMaxDensity);
}
