// DFSPH solver iteration, part 2: applies the stiffness increments (symmetric, Bender & Koschier 2017
// eq. 10/12 in dt-free form): dv_i = -sum_j m (k_i + k_j) grad W_ij - sum_b psi_b k_i grad W_ib, and adds
// k_i to the particle's total (the warm start of the next step).
//   DFSPH_DIVERGENCE: corrects the velocities; the total goes to the per-id warm-start buffer.
//   otherwise: adds to the acceleration (v* = v + dt a); the total, p / rho^2, goes to vel.w (carried
//   by the state between steps); the cache's pressure adds the divergence solve's share.
#include "sph_params.glsl"
#include "sph_kernels.glsl"
#include "sph_dfsph.glsl"
layout(local_size_x = SIM_WG) in;
layout(std430, binding = SPHFX_SSBO_SIM_POS) readonly buffer SimPos { vec4 pos[]; };
layout(std430, binding = SPHFX_SSBO_SIM_VEL) buffer SimVel { vec4 vel[]; };
layout(std430, binding = SPHFX_SSBO_SIM_CELL_START) readonly buffer SimCellStart { uint cellStart[]; };
layout(std430, binding = SPHFX_SSBO_SIM_BOUNDARY_POS) readonly buffer SimBoundaryPos { vec4 bpos[]; };
layout(std430, binding = SPHFX_SSBO_SIM_BOUNDARY_CELL_START) readonly buffer SimBoundaryStart {
  uint bStart[];
};
layout(std430, binding = SPHFX_SSBO_SIM_DFSPH_INCREMENT) readonly buffer DfsphIncrement { float increment[]; };
#if defined(DFSPH_DIVERGENCE)
layout(std430, binding = SPHFX_SSBO_SIM_DFSPH_WARM) writeonly buffer DfsphWarm { float warm[]; };
#else
layout(std430, binding = SPHFX_SSBO_SIM_ACCEL) buffer SimAccel { vec4 accel[]; };
layout(std430, binding = SPHFX_SSBO_SIM_DENSITY) buffer SimDensity { vec2 densityPressure[]; };
#endif

vec3 velocityChange(uint i, float ki) {
  vec3 xi = pos[i].xyz;
  ivec3 cell = sphCell(xi);
  vec3 fluid = vec3(0.0), wall = vec3(0.0);
  for (int dz = -1; dz <= 1; ++dz)
    for (int dy = -1; dy <= 1; ++dy) {
      uint first, last;
      if (!sphRow(cell, dy, dz, first, last)) continue;
      for (uint j = cellStart[first], e = cellStart[last]; j < e; ++j) {
        vec3 d = xi - pos[j].xyz;
        if (dot(d, d) < simKernel.w && j != i) fluid -= (ki + increment[j]) * dfsphForceGrad(d);
      }
      if (ki != 0.0)
        for (uint j = bStart[first], e = bStart[last]; j < e; ++j) {
          vec4 b = bpos[j];
          vec3 d = xi - b.xyz;
          if (dot(d, d) < simKernel.w) wall -= b.w * dfsphForceGrad(d);
        }
    }
  return simGravity.w * fluid + ki * wall;
}

void main() {
  uint i = sphfxGlobalIndex();
  if (i >= simCounts.x) return;
  float ki = increment[i];
  vec3 dv = velocityChange(i, ki);
#if defined(DFSPH_DIVERGENCE)
  vel[i] = vec4(vel[i].xyz + dv, vel[i].w);
  float total = dfsph[i].w + ki;
  dfsph[i].w = total;
  warm[floatBitsToUint(pos[i].w)] = total;
#else
  accel[i] = vec4(accel[i].xyz + dv, 0.0);
  float total = dfsph[i].z + ki;
  dfsph[i].z = total;
  vel[i].w = total;
  // The cache's pressure (p / rho^2): both solves support the fluid, the divergence solve by a velocity
  // impulse K per step, i.e. the pressure acceleration K / dt.
  densityPressure[i].y = total + dfsph[i].w / stateDt;
#endif
}
