// DFSPH solver iteration, part 2: applies the stiffness increments (symmetric, Bender & Koschier 2017
// eq. 10/12 in dt-free form): dv_i = -sum_j m (k_i + k_j) grad W_ij - c sum_b psi_b k_i grad W_ib (c = 1
// in the divergence solve, DFSPH_DENSITY_WALL_PUSH in the constant-density solve: sph_dfsph.glsl), and
// adds k_i to the particle's total (the warm start of the next step). Constraint walls: the
// constant-density solve adds each wall sample's increment, -sum_b k_b psi_b grad W_ib.
//   DFSPH_DIVERGENCE: corrects the velocities; the total goes to the per-id warm-start buffer.
//   otherwise: corrects the predicted velocities v* (in vel since the warm pass, sim_dfsph_source.comp)
//   by dt dv; the total, p / rho^2, goes to vel.w (carried by the state between steps); the cache's
//   pressure adds the divergence solve's share.
#define DFSPH_LIST_READ
#include "sph_params.glsl"
#include "sph_kernels.glsl"
#include "sph_dfsph.glsl"
layout(local_size_x = SIM_WG) in;
layout(std430, binding = SPHFX_SSBO_SIM_VEL) writeonly buffer SimVel { vec4 vel[]; };
layout(std430, binding = SPHFX_SSBO_SIM_DFSPH_INCREMENT) readonly buffer DfsphIncrement { float increment[]; };
#if defined(DFSPH_DIVERGENCE)
layout(std430, binding = SPHFX_SSBO_SIM_DFSPH_WARM) writeonly buffer DfsphWarm { float warm[]; };
#else
layout(std430, binding = SPHFX_SSBO_SIM_DENSITY) writeonly buffer SimDensity { vec2 densityPressure[]; };
#endif

#if defined(DFSPH_DIVERGENCE)
const float kWallPush = 1.0;
#else
const float kWallPush = DFSPH_DENSITY_WALL_PUSH;
#endif

// -sum_j (k_i + k_j) m grad W_ij - c k_i sum_b psi_b grad W_ib, from the list.
vec3 velocityChange(uint i, float ki) {
  uint count = dfsphCount(i);
  vec3 dv = -(kWallPush * ki) * dfsphBoundary(i).xyz;
  for (uint k = 0u; k < count; ++k) {
    vec4 e = dfsphEntry(i, k);
    dv -= (ki + dfsphIncrement(floatBitsToUint(e.w))) * e.xyz;
  }
#if defined(DFSPH_BOUNDARY_CONSTRAINTS) && !defined(DFSPH_DIVERGENCE)
  uint walls = dfsphBoundaryCount(i);
  for (uint k = 0u; k < walls; ++k) {
    vec4 e = dfsphBoundaryEntry(i, k);
    dv -= dfsphIncrement(DFSPH_CAPACITY + floatBitsToUint(e.w)) * e.xyz;
  }
#endif
  return dv;
}

void main() {
  uint i = sphfxGlobalIndex();
  if (i >= simCounts.x) return;
  float ki = dfsphIncrement(i);
  vec3 dv = velocityChange(i, ki);
  vec4 v = sphFetchVel(i), f = dfsphParticle(i);
#if defined(DFSPH_DIVERGENCE)
  vel[i] = vec4(v.xyz + dv, v.w);
  float total = f.w + ki;
  dfsph[i].w = total;
  warm[floatBitsToUint(sphFetchPos(i).w)] = total;
#else
  float total = f.z + ki;
  dfsph[i].z = total;
  vec3 next = v.xyz + stateDt * dv;
#if defined(SIM_WALL_CONTACT)
  // fluid.wall_contact (sph_kernels.glsl): in every iteration, so that the next one's residual sees it.
  vec4 b = dfsphBoundary(i);
#if defined(HAS_COLLIDERS)
  float rate = b.w;  // sum_b psi_b v_b . grad W_ib
#else
  float rate = 0.0;  // walls at rest (w may hold the walls' Laplacian sum)
#endif
  next = sphWallContact(next, b.xyz, dfsphWallContactExcess(i), rate, stateDt);
#if defined(SIM_COLLIDER_CONTACT)
  vec4 collider = dfsphColliderContact(i);
  next = sphWallContact(next, collider.xyz, collider.w, dfsphColliderContactRate(i), stateDt);
#endif
#endif
  vel[i] = vec4(next, total);
  // The cache's pressure (p / rho^2): both solves support the fluid, the divergence solve by a velocity
  // impulse K per step, i.e. the pressure acceleration K / dt.
  densityPressure[i].y = DFSPH_PRESSURE_SCALE * (total + f.w / stateDt);
#endif
}
