// DFSPH solver iteration, part 1 (Bender & Koschier 2017, algorithms 2 and 3): the residual of every
// particle and its stiffness increment, and the residuals for sim_dfsph_reduce.comp's average (fixed
// order, so the average is deterministic): SIM_WORKGROUP_REDUCE, each work group's sum (a tree in
// shared memory) in partial[group]; otherwise each particle's in partial[i], no barrier
// (sph_group_max.glsl says why).
//   DFSPH_DIVERGENCE: residual D rho / Dt of the current velocities; increment residual * factor.
//   otherwise: predicted density rho* = rho + dt D rho / Dt of the predicted velocities v*, residual
//   rho* - rho0; increment residual * factor / dt^2.
// uWarm: the first pass of a solve, the warm start from a share (DFSPH_WARM_SHARE) of the last substep's
// stiffness total. Divergence solve: the share is the increment, applied by an apply pass. Density
// solve: the non-pressure pass has already added the share's pressure acceleration to a; the warm pass
// predicts v* = v + dt a into vel, zeroes a (its iterations then read one velocity per neighbour, and
// sim_integrate.comp's v + dt a is v*) and records the share as the total; no apply pass follows.
#define DFSPH_LIST_READ
#include "sph_params.glsl"
#include "sph_kernels.glsl"
#include "sph_dfsph.glsl"
layout(local_size_x = SIM_WG) in;
#if !defined(DFSPH_DIVERGENCE)
// Written by the density solve's warm pass only (reads go through sph_textures.glsl).
layout(std430, binding = SPHFX_SSBO_SIM_VEL) buffer SimVel { vec4 vel[]; };
layout(std430, binding = SPHFX_SSBO_SIM_ACCEL) buffer SimAccel { vec4 accel[]; };
layout(std430, binding = SPHFX_SSBO_SIM_DENSITY) writeonly buffer SimDensity { vec2 densityPressure[]; };
#endif
layout(std430, binding = SPHFX_SSBO_SIM_DFSPH_INCREMENT) writeonly buffer DfsphIncrement { float increment[]; };
layout(std430, binding = SPHFX_SSBO_SIM_DFSPH_PARTIAL) writeonly buffer DfsphPartial { float partial[]; };
#if defined(DFSPH_DIVERGENCE)
layout(std430, binding = SPHFX_SSBO_SIM_DFSPH_WARM) readonly buffer DfsphWarm { float warm[]; };
#endif
uniform uint uWarm;
#if defined(DFSPH_MOMENTUM)
// solver.jacobi_momentum from the solve's second iteration on, 0 in its first (the increment buffer then
// holds the warm start, not an iteration's increment). Compiled in only when the scene's momentum > 0.
uniform float uMomentum;
#endif
#if defined(SIM_WORKGROUP_REDUCE)
shared float groupSum[SIM_WG];
#endif

// D rho_i / Dt = sum_j m (v_i - v_j) . grad W_ij + sum_b psi_b (v_i - v_b) . grad W_ib, from the list.
float densityChange(uint i) {
  vec3 vi = sphFetchVel(i).xyz;
  uint count = dfsphCount(i);
  float fluid = 0.0;
  for (uint k = 0u; k < count; ++k) {
    vec4 e = dfsphEntry(i, k);
    fluid += dot(vi - sphFetchVel(floatBitsToUint(e.w)).xyz, e.xyz);
  }
  vec4 b = dfsphBoundary(i);
#if defined(HAS_COLLIDERS)
  return fluid + dot(vi, b.xyz) - b.w;
#else
  return fluid + dot(vi, b.xyz);  // walls at rest (w may hold the walls' Laplacian sum)
#endif
}

// Projected Jacobi (the stiffness total stays >= 0, as pressure in IISPH): the signed residual moves the
// total up or down; the increment is the change of the clamped total. The step adds the share uMomentum
// of the particle's previous increment (heavy ball, Polyak 1964: the smooth, slowly converging modes of
// a tall column keep their speed). Returns the increment; `error` is the
// residual where the constraint is active (compressed, or still carrying stiffness), else 0.
float projectedIncrement(uint i, float residual, float scale, float total, out float error) {
  float step = DFSPH_OMEGA * residual * scale;
#if defined(DFSPH_MOMENTUM)
  step += uMomentum * dfsphIncrement(i);
#endif
  float next = max(total + step, 0.0);
  error = (residual > 0.0 || total > 0.0) ? abs(residual) : 0.0;
  return next - total;
}

void main() {
  uint i = sphfxGlobalIndex();
  float error = 0.0;
  if (i < simCounts.x) {
    vec4 f = dfsphParticle(i);
    float inc;
#if defined(DFSPH_DIVERGENCE)
    // Warm start (no residual: the warm pass is not reduced): a share of the last substep's total. The
    // first substep of a frame starts cold, so that a restart file (positions, velocities) resumes
    // bit-identically.
    if (uWarm != 0u) {
      inc = stateSubsteps > 0u ? DFSPH_WARM_SHARE * warm[floatBitsToUint(sphFetchPos(i).w)] : 0.0;
    } else {
      // Too few neighbours (free surface, splashes; factor 0): the divergence estimate is meaningless.
      float residual = f.y > 0.0 ? densityChange(i) : 0.0;
      inc = projectedIncrement(i, residual, f.y, f.w, error);
    }
#else
    // Warm start: a share of the last substep's pressure total, carried in vel.w. The non-pressure pass
    // already added its pressure acceleration to a, so v* = v + dt a is the warm-started prediction and
    // no apply pass follows (only particle i is touched: the warm pass reads no neighbour).
    if (uWarm != 0u) {
      vec4 v = vel[i];
      float total = DFSPH_DENSITY_WARM_AFTER_STEP * v.w;  // the share, or 0 (sph_dfsph.glsl)
      vel[i] = vec4(v.xyz + stateDt * accel[i].xyz, total);
      accel[i] = vec4(0.0);
      dfsph[i].z = total;
      densityPressure[i].y = total + f.w / stateDt;
      inc = 0.0;
    } else {
      float dt = stateDt;
#if defined(DFSPH_CLOSED_PERIODIC)
      float rest = simFluid.x + dfMeanExcess;  // sph_dfsph.glsl
#else
      float rest = simFluid.x;
#endif
      float residual = sphFetchDensity(i).x + dt * densityChange(i) - rest;
      inc = projectedIncrement(i, residual, f.x / (dt * dt), f.z, error);
    }
#endif
    increment[i] = inc;
  }
#if defined(SIM_WORKGROUP_REDUCE)
  uint l = gl_LocalInvocationIndex;
  groupSum[l] = error / simFluid.x;
  for (uint s = SIM_WG / 2u; s > 0u; s >>= 1u) {
    barrier();
    if (l < s) groupSum[l] += groupSum[l + s];
  }
  if (l == 0u) partial[gl_WorkGroupID.x] = groupSum[0];
#else
  if (i < uint(DFSPH_RESIDUAL_SLOTS)) partial[i] = error / simFluid.x;
#endif
}
