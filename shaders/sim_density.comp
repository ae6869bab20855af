// WCSPH pass 1: density (poly6) from fluid neighbours and Akinci 2012 boundary samples (psi W), then
// pressure from the equation of state. Also reduces the largest density for the health check.
#include "sph_params.glsl"
#include "sph_kernels.glsl"
layout(local_size_x = SIM_WG) in;
layout(std430, binding = SPHFX_SSBO_SIM_POS) readonly buffer SimPos { vec4 pos[]; };
layout(std430, binding = SPHFX_SSBO_SIM_CELL_START) readonly buffer SimCellStart { uint cellStart[]; };
layout(std430, binding = SPHFX_SSBO_SIM_BOUNDARY_POS) readonly buffer SimBoundaryPos { vec4 bpos[]; };
layout(std430, binding = SPHFX_SSBO_SIM_BOUNDARY_CELL_START) readonly buffer SimBoundaryStart {
  uint bStart[];
};
layout(std430, binding = SPHFX_SSBO_SIM_DENSITY) writeonly buffer SimDensity { vec2 densityPressure[]; };
shared uint groupMaxDensity;

void main() {
  uint i = sphfxGlobalIndex();
  bool live = i < simCounts.x;
  if (gl_LocalInvocationIndex == 0u) groupMaxDensity = 0u;
  barrier();
  if (live) {
    vec3 xi = pos[i].xyz;
    ivec3 cell = sphCell(xi);
    float fluid = 0.0, wall = 0.0;
    for (int dz = -1; dz <= 1; ++dz)
      for (int dy = -1; dy <= 1; ++dy) {
        uint first, last;
        if (!sphRow(cell, dy, dz, first, last)) continue;
        for (uint j = cellStart[first], e = cellStart[last]; j < e; ++j) {
          vec3 d = xi - pos[j].xyz;
          fluid += sphPoly6(dot(d, d));
        }
        for (uint j = bStart[first], e = bStart[last]; j < e; ++j) {
          vec4 b = bpos[j];
          vec3 d = xi - b.xyz;
          wall += b.w * sphPoly6(dot(d, d));
        }
      }
    float rho = simGravity.w * fluid + wall;
    densityPressure[i] = vec2(rho, sphPressure(rho) / (rho * rho));
    atomicMax(groupMaxDensity, floatBitsToUint(rho));  // positive floats order as their bits; NaN is largest
  }
  barrier();
  if (gl_LocalInvocationIndex == 0u) atomicMax(stateMaxDensity, groupMaxDensity);
}
