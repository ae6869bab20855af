// WCSPH pass 2: accelerations. Symmetric pressure force with the spiky gradient, Akinci 2012 boundary
// pressure (mirrored: p_b = p_i, rho_b = rho_i) and friction, viscosity (VISCOSITY_LAPLACIAN: the seed's
// Mueller form; VISCOSITY_ARTIFICIAL: Monaghan), gravity. Reduces max |v|^2 and |a|^2 for the CFL step.
#include "sph_params.glsl"
#include "sph_kernels.glsl"
layout(local_size_x = SIM_WG) in;
layout(std430, binding = SPHFX_SSBO_SIM_POS) readonly buffer SimPos { vec4 pos[]; };
layout(std430, binding = SPHFX_SSBO_SIM_VEL) readonly buffer SimVel { vec4 vel[]; };
layout(std430, binding = SPHFX_SSBO_SIM_DENSITY) readonly buffer SimDensity { vec2 densityPressure[]; };
layout(std430, binding = SPHFX_SSBO_SIM_ACCEL) writeonly buffer SimAccel { vec4 accel[]; };
layout(std430, binding = SPHFX_SSBO_SIM_CELL_START) readonly buffer SimCellStart { uint cellStart[]; };
layout(std430, binding = SPHFX_SSBO_SIM_BOUNDARY_POS) readonly buffer SimBoundaryPos { vec4 bpos[]; };
layout(std430, binding = SPHFX_SSBO_SIM_BOUNDARY_VEL) readonly buffer SimBoundaryVel { vec4 bvel[]; };
layout(std430, binding = SPHFX_SSBO_SIM_BOUNDARY_CELL_START) readonly buffer SimBoundaryStart {
  uint bStart[];
};
shared uint groupMaxSpeed2, groupMaxAccel2;

#if defined(VISCOSITY_ARTIFICIAL)
// Monaghan's Pi_ij * rho-free factor: nu (v_ij . x_ij) / (|x_ij|^2 + 0.01 h^2) when approaching.
float artificialViscosity(vec3 vij, vec3 xij, float r2, float rhoSum) {
  float vx = dot(vij, xij);
  if (vx >= 0.0) return 0.0;
  float nu = 2.0 * simViscosity.y * simDomainMin.w * simFluid.w / rhoSum;
  return -nu * vx / (r2 + 0.01 * simKernel.w);
}
#endif

vec3 fluidTerms(uint i, vec3 xi, vec3 vi, float rhoi, float dpi, uint first, uint last) {
  vec3 a = vec3(0.0);
  for (uint j = first; j < last; ++j) {
    vec3 d = xi - pos[j].xyz;
    float r2 = dot(d, d);
    if (r2 >= simKernel.w || j == i) continue;
    float r = sqrt(r2);
    vec3 grad = sphSpikyGrad(d, r);
    vec2 dpj = densityPressure[j];
    float coef = dpi + dpj.y;
#if defined(VISCOSITY_ARTIFICIAL)
    coef += artificialViscosity(vi - vel[j].xyz, d, r2, rhoi + dpj.x);
#elif defined(VISCOSITY_LAPLACIAN)
    a += (simViscosity.x / dpj.x * sphViscosityLaplacian(r)) * (vel[j].xyz - vi);
#endif
    a -= coef * grad;
  }
  return a * simGravity.w;
}

vec3 boundaryTerms(vec3 xi, vec3 vi, float rhoi, float dpi, uint first, uint last) {
  vec3 a = vec3(0.0);
  for (uint j = first; j < last; ++j) {
    vec4 b = bpos[j];
    vec3 d = xi - b.xyz;
    float r2 = dot(d, d);
    if (r2 >= simKernel.w) continue;
    float r = sqrt(r2);
    vec3 grad = sphSpikyGrad(d, r);
    float coef = 2.0 * dpi;
#if defined(VISCOSITY_ARTIFICIAL)
    coef += artificialViscosity(vi - bvel[j].xyz, d, r2, 2.0 * rhoi);
#elif defined(VISCOSITY_LAPLACIAN)
    a += (b.w * simViscosity.x / (rhoi * rhoi) * sphViscosityLaplacian(r)) * (bvel[j].xyz - vi);
#endif
    a -= (b.w * coef) * grad;
  }
  return a;
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
    vec2 dpi = densityPressure[i];
    ivec3 cell = sphCell(xi);
    vec3 a = simGravity.xyz;
    for (int dz = -1; dz <= 1; ++dz)
      for (int dy = -1; dy <= 1; ++dy) {
        uint first, last;
        if (!sphRow(cell, dy, dz, first, last)) continue;
        a += fluidTerms(i, xi, vi, dpi.x, dpi.y, cellStart[first], cellStart[last]);
        a += boundaryTerms(xi, vi, dpi.x, dpi.y, bStart[first], bStart[last]);
      }
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
