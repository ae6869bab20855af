// Per-frame health check over every particle: non-finite state, outside the domain, too fast, too
// dense. Counts per cause and the smallest offending id, for the error message.
#include "sph_params.glsl"
layout(local_size_x = SIM_WG) in;
layout(std430, binding = SPHFX_SSBO_SIM_UNSORTED_POS) readonly buffer SimUnsortedPos { vec4 pos[]; };
layout(std430, binding = SPHFX_SSBO_SIM_UNSORTED_VEL) readonly buffer SimUnsortedVel { vec4 vel[]; };
layout(std430, binding = SPHFX_SSBO_SIM_DENSITY) readonly buffer SimDensity { vec2 densityPressure[]; };

void flag(uint cause, uint id) {
  atomicAdd(stateHealthCount[cause], 1u);
  atomicMin(stateHealthFirst[cause], id);
}

void main() {
  uint i = sphfxGlobalIndex();
  if (i >= simCounts.x) return;
  vec4 p = pos[i];
  vec3 x = p.xyz, v = vel[i].xyz;
  uint id = floatBitsToUint(p.w);
  float rho = densityPressure[i].x;
  if (any(isnan(x)) || any(isinf(x)) || any(isnan(v)) || any(isinf(v)) || isnan(rho)) flag(0u, id);
  bool outside = any(lessThan(x, simDomainMin.xyz)) || any(greaterThan(x, simDomainMax.xyz));
#if defined(SIM_PERIODIC_X)
  outside = outside || x.x >= simDomainMax.x;  // periodic: [min, max), max is min's image
#endif
#if defined(SIM_PERIODIC_Y)
  outside = outside || x.y >= simDomainMax.y;
#endif
#if defined(SIM_PERIODIC_Z)
  outside = outside || x.z >= simDomainMax.z;
#endif
  if (outside) flag(1u, id);
  if (dot(v, v) > simLimits.w * simLimits.w) flag(2u, id);
  if (rho > simLimits.z) flag(3u, id);
}
