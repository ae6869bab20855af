// Symplectic (semi-implicit) Euler: v += dt a, then x += dt v. Then the last-resort guarantees: clamp
// into the domain (wrap along periodic axes) and project out of colliders (the boundary samples do the
// physical work; this only ensures that no particle tunnels or escapes). Writes the unsorted state the
// next step sorts.
#include "sph_params.glsl"
#if defined(HAS_COLLIDERS)
#include "sph_colliders.glsl"
#endif
#if defined(SIM_PERIODIC_X) || defined(SIM_PERIODIC_Y) || defined(SIM_PERIODIC_Z)
#include "sph_kernels.glsl"
#endif
layout(local_size_x = SIM_WG) in;
layout(std430, binding = SPHFX_SSBO_SIM_POS) readonly buffer SimPos { vec4 pos[]; };
layout(std430, binding = SPHFX_SSBO_SIM_VEL) readonly buffer SimVel { vec4 vel[]; };
layout(std430, binding = SPHFX_SSBO_SIM_ACCEL) readonly buffer SimAccel { vec4 accel[]; };
layout(std430, binding = SPHFX_SSBO_SIM_UNSORTED_POS) writeonly buffer SimOutPos { vec4 outPos[]; };
layout(std430, binding = SPHFX_SSBO_SIM_UNSORTED_VEL) writeonly buffer SimOutVel { vec4 outVel[]; };

void main() {
  uint i = sphfxGlobalIndex();
  if (i >= simCounts.x) return;
  float dt = stateDt;
  vec3 v = vel[i].xyz + dt * accel[i].xyz;
  vec3 x = pos[i].xyz + dt * v;
  vec3 lo = simDomainMin.xyz + simViscosity.z, hi = simDomainMax.xyz - simViscosity.z;
  for (int k = 0; k < 3; ++k) {
#if defined(SIM_PERIODIC_X)
    if (k == 0) continue;  // no wall: wrapped below
#endif
#if defined(SIM_PERIODIC_Y)
    if (k == 1) continue;
#endif
#if defined(SIM_PERIODIC_Z)
    if (k == 2) continue;
#endif
    if (x[k] < lo[k]) { x[k] = lo[k]; v[k] = max(v[k], 0.0); }
    if (x[k] > hi[k]) { x[k] = hi[k]; v[k] = min(v[k], 0.0); }
  }
#if defined(SIM_PERIODIC_X) || defined(SIM_PERIODIC_Y) || defined(SIM_PERIODIC_Z)
  x = sphWrapPosition(x);  // into [min, max): the grid, the health check and the caches see one image
#endif
#if defined(HAS_COLLIDERS)
  for (uint c = 0u; c < simCounts.z; ++c) sphProjectOutOfCollider(c, float(stateTime), simViscosity.z, x, v);
  // A collider pushing a particle into a wall: the wall wins (the domain guarantee is absolute).
  x = clamp(x, lo, hi);
#endif
  outPos[i] = vec4(x, pos[i].w);
  outVel[i] = vec4(v, vel[i].w);  // w: solver data carried between steps (DFSPH warm start)
}
