// DFSPH non-pressure accelerations: gravity and viscosity (the WCSPH force pass's models without its
// pressure term), evaluated on the divergence-free velocities. Reduces max |v|^2 and max |a|^2 of these
// accelerations for the displacement-bounded CFL step (sim_timestep.comp).
#define DFSPH_LIST_READ
#include "sph_params.glsl"
#include "sph_kernels.glsl"
#include "sph_dfsph.glsl"
layout(local_size_x = SIM_WG) in;
layout(std430, binding = SPHFX_SSBO_SIM_POS) readonly buffer SimPos { vec4 pos[]; };
layout(std430, binding = SPHFX_SSBO_SIM_VEL) readonly buffer SimVel { vec4 vel[]; };
layout(std430, binding = SPHFX_SSBO_SIM_DENSITY) readonly buffer SimDensity { vec2 densityPressure[]; };
layout(std430, binding = SPHFX_SSBO_SIM_ACCEL) writeonly buffer SimAccel { vec4 accel[]; };
layout(std430, binding = SPHFX_SSBO_SIM_BOUNDARY_POS) readonly buffer SimBoundaryPos { vec4 bpos[]; };
layout(std430, binding = SPHFX_SSBO_SIM_BOUNDARY_VEL) readonly buffer SimBoundaryVel { vec4 bvel[]; };
layout(std430, binding = SPHFX_SSBO_SIM_BOUNDARY_CELL_START) readonly buffer SimBoundaryStart {
  uint bStart[];
};
shared uint groupMaxSpeed2, groupMaxAccel2;

#if defined(VISCOSITY_ARTIFICIAL)
// Monaghan's viscosity as in sim_force.comp: nu (v_ij . x_ij) / (|x_ij|^2 + 0.01 h^2) when approaching.
float artificialViscosity(vec3 vij, vec3 xij, float r2, float rhoSum) {
  float vx = dot(vij, xij);
  if (vx >= 0.0) return 0.0;
  float nu = 2.0 * simViscosity.y * simDomainMin.w * simFluid.w / rhoSum;
  return -nu * vx / (r2 + 0.01 * simKernel.w);
}
#endif

// Fluid neighbours from the substep's list (its entries hold m grad W), boundary samples from the grid
// (only rows near walls and colliders hold any).
vec3 viscosity(uint i, vec3 xi, vec3 vi, float rhoi) {
  vec3 fluid = vec3(0.0), wall = vec3(0.0);
#if defined(VISCOSITY_ARTIFICIAL) || defined(VISCOSITY_LAPLACIAN)
  uint n = simCounts.x, count = dfCount[i];
  for (uint k = 0u; k < count; ++k) {
    vec4 e = dfNbr[k * n + i];
    uint j = floatBitsToUint(e.w);
    vec3 d = xi - pos[j].xyz;
#if defined(VISCOSITY_ARTIFICIAL)
    fluid -= artificialViscosity(vi - vel[j].xyz, d, dot(d, d), rhoi + densityPressure[j].x) * e.xyz;
#else
    fluid += (simViscosity.x / densityPressure[j].x * simGravity.w * sphViscosityLaplacian(length(d))) *
             (vel[j].xyz - vi);
#endif
  }
  ivec3 cell = sphCell(xi);
  for (int dz = -1; dz <= 1; ++dz)
    for (int dy = -1; dy <= 1; ++dy) {
      uint first, last;
      if (!sphRow(cell, dy, dz, first, last)) continue;
      for (uint j = bStart[first], e = bStart[last]; j < e; ++j) {
        vec4 b = bpos[j];
        vec3 d = xi - b.xyz;
        float r2 = dot(d, d);
        if (r2 >= simKernel.w) continue;
        float r = sqrt(r2);
#if defined(VISCOSITY_ARTIFICIAL)
        wall -= b.w * artificialViscosity(vi - bvel[j].xyz, d, r2, 2.0 * rhoi) * sphSpikyGrad(d, r);
#else
        // As a fluid neighbour of mass psi_b and density rho_i at the wall's velocity (no slip), as in
        // sim_force.comp.
        wall += (b.w * simViscosity.x / rhoi * sphViscosityLaplacian(r)) * (bvel[j].xyz - vi);
#endif
      }
    }
#endif
  return fluid + wall;
}

void main() {
  uint i = sphfxGlobalIndex();
  bool live = i < simCounts.x;
  if (gl_LocalInvocationIndex == 0u) {
    groupMaxSpeed2 = 0u;
    groupMaxAccel2 = 0u;
  }
  barrier();
  if (live) {
    vec3 xi = pos[i].xyz, vi = vel[i].xyz;
    vec3 a = simGravity.xyz + viscosity(i, xi, vi, densityPressure[i].x);
    accel[i] = vec4(a, 0.0);
    atomicMax(groupMaxSpeed2, floatBitsToUint(dot(vi, vi)));
    atomicMax(groupMaxAccel2, floatBitsToUint(dot(a, a)));
  }
  barrier();
  if (gl_LocalInvocationIndex == 0u) {
    atomicMax(stateMaxSpeed2, groupMaxSpeed2);
    atomicMax(stateMaxAccel2, groupMaxAccel2);
  }
}
