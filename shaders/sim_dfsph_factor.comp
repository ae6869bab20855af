// DFSPH step start: density (poly6, fluid and Akinci 2012 boundary samples psi W), the factor
// alpha_i / rho_i = 1 / ((sum_j m gW_ij + sum_b psi_b gW_ib) . (sum_j m gS_ij + sum_b psi_b gS_ib)
//                        + sum_j m^2 gW_ij . gS_ij)
// (Bender & Koschier 2017, eq. 9, boundary in the first sums only; gW: gradient of the density change,
// gS: gradient of the pressure correction, both spiky, see sph_dfsph.glsl) and the neighbour count. The cache's
// pressure is the last step's density stiffness, carried in vel.w. Reduces the largest density (health).
#include "sph_params.glsl"
#include "sph_kernels.glsl"
#include "sph_dfsph.glsl"
layout(local_size_x = SIM_WG) in;
layout(std430, binding = SPHFX_SSBO_SIM_POS) readonly buffer SimPos { vec4 pos[]; };
layout(std430, binding = SPHFX_SSBO_SIM_VEL) readonly buffer SimVel { vec4 vel[]; };
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
    float m = simGravity.w, fluid = 0.0, wall = 0.0, squares = 0.0, neighbours = 0.0;
    vec3 gradSum = vec3(0.0), forceSum = vec3(0.0);
    for (int dz = -1; dz <= 1; ++dz)
      for (int dy = -1; dy <= 1; ++dy) {
        uint first, last;
        if (!sphRow(cell, dy, dz, first, last)) continue;
        for (uint j = cellStart[first], e = cellStart[last]; j < e; ++j) {
          vec3 d = xi - pos[j].xyz;
          float r2 = dot(d, d);
          if (r2 >= simKernel.w) continue;
          fluid += sphPoly6(r2);
          if (j == i) continue;
          vec3 g = m * dfsphDensityGrad(d), gs = m * dfsphForceGrad(d);
          gradSum += g;
          forceSum += gs;
          squares += dot(g, gs);
          neighbours += 1.0;
        }
        for (uint j = bStart[first], e = bStart[last]; j < e; ++j) {
          vec4 b = bpos[j];
          vec3 d = xi - b.xyz;
          float r2 = dot(d, d);
          if (r2 >= simKernel.w) continue;
          wall += b.w * sphPoly6(r2);
          gradSum += b.w * dfsphDensityGrad(d);
          forceSum += b.w * dfsphForceGrad(d);
          neighbours += 1.0;
        }
      }
    float rho = m * fluid + wall;
    float denom = dot(gradSum, forceSum) + squares;
    dfsph[i] = vec4(denom > 1e-6 ? 1.0 / denom : 0.0, neighbours, 0.0, 0.0);
    densityPressure[i] = vec2(rho, vel[i].w);
    atomicMax(groupMaxDensity, floatBitsToUint(rho));
  }
  barrier();
  if (gl_LocalInvocationIndex == 0u) atomicMax(stateMaxDensity, groupMaxDensity);
}
