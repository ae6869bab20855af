// DFSPH step start: density (fluid: poly6, or the DFSPH kernel with DFSPH_KERNEL_DENSITY; Akinci 2012
// boundary samples: psi W with the DFSPH kernel, spiky or Wendland C2, dfsphWallScale() in
// sph_dfsph.glsl), the factors alpha_i / rho_i of both solves (Bender & Koschier 2017, eq. 9, boundary in
// the first sum only; gW the DFSPH kernel's gradient; the constant-density solve's walls push
// DFSPH_DENSITY_WALL_PUSH times: sph_dfsph.glsl), and the neighbour list every solver iteration of this
// substep reads. The walls'
// hydrostatic push, -sum_b psi_b (g . (x_b - x_i) / rho_i) grad W_ib (push walls only), goes to accel, to which the
// non-pressure pass adds the rest of the step's acceleration. The cache's pressure: with
// DFSPH_PRESSURE_MEAN, the pass at the frame's end (uFrameEnd 1) writes the frame's mean, the summed
// impulse (sim_dfsph_pressure_mean.comp) over DFSPH_FRAME_SECONDS, and clears the sum; otherwise the last
// step's density stiffness, carried in vel.w, times DFSPH_PRESSURE_SCALE (sph_dfsph.glsl).
// Reduces the largest density (health).
#define DFSPH_LIST_WRITE
#include "sph_params.glsl"
#include "sph_group_max.glsl"
#include "sph_neighbors.glsl"
#include "sph_dfsph.glsl"
#if defined(SIM_COLLIDER_CONTACT)
#include "sph_colliders.glsl"
#endif
layout(local_size_x = SIM_WG) in;
layout(std430, binding = SPHFX_SSBO_SIM_DENSITY) writeonly buffer SimDensity { vec2 densityPressure[]; };
layout(std430, binding = SPHFX_SSBO_SIM_ACCEL) writeonly buffer SimAccel { vec4 accel[]; };
#if defined(DFSPH_PRESSURE_MEAN)
layout(std430, binding = SPHFX_SSBO_SIM_DFSPH_PRESSURE_IMPULSE) buffer DfsphPressureImpulse { float impulse[]; };
uniform uint uFrameEnd;
#endif
#if defined(DFSPH_CLOSED_PERIODIC)
layout(std430, binding = SPHFX_SSBO_SIM_DFSPH_PARTIAL) writeonly buffer DfsphPartial { float partial[]; };
shared float groupDensity[SIM_WG];  // a fixed-order tree, so the mean is deterministic
#endif

void main() {
  uint i = sphfxGlobalIndex();
  bool live = i < simCounts.x;
  SIM_GROUP_MAX_BEGIN();
#if defined(DFSPH_CLOSED_PERIODIC)
  float liveDensity = 0.0;  // this invocation's share of the group's density sum
#endif
  if (live) {
    vec3 xi = sphFetchPos(i).xyz;
    uint n = DFSPH_CAPACITY, listed = 0u, blisted = 0u;
#if defined(DFSPH_KERNEL_DENSITY)
    const float m = simGravity.w * DFSPH_KERNEL_DENSITY;
#else
    const float m = simGravity.w;
#endif
    float fluid = 0.0, wall = 0.0, squares = 0.0, boundaryNeighbours = 0.0;
    float boundaryW = 0.0;  // dfBoundary.w (sph_dfsph.glsl)
    vec3 gradSum = vec3(0.0), wallGrad = vec3(0.0), hydrostatic = vec3(0.0);
    // No branch per candidate: the kernels are 0 beyond h (and the gradient at r = 0), and every
    // candidate is written to the next free slot, which only a neighbour advances (the slot after the
    // last neighbour holds a stale candidate; the list has one spare slot for it). On llvmpipe a
    // per-lane branch on whether a candidate is a neighbour (unpredictable) costs more than it skips.
    SPH_FOR_EACH_CELL_RANGE(xi, row, seam, first, last)
      SPH_FOR_EACH_FLUID(j, first, last) {
        vec3 d = sphDelta(xi, sphFetchPos(j).xyz);
        float r2 = dot(d, d);
#if defined(DFSPH_KERNEL_DENSITY)
        fluid += dfsphW(sqrt(r2));
#else
        fluid += sphPoly6(r2);
#endif
        vec3 g = m * dfsphGrad(d);
        gradSum += g;
        squares += dot(g, g);
        dfNbr[min(listed, uint(DFSPH_MAX_NEIGHBORS)) * n + i] = vec4(g, uintBitsToFloat(j));
        listed += (r2 < simKernel.w && j != i) ? 1u : 0u;
      }
      SPH_FOR_EACH_BOUNDARY(j, first, last) {
        vec4 b = sphFetchBoundaryPos(j);
        vec3 d = sphDelta(xi, b.xyz);
        float r2 = dot(d, d);
        float psi = b.w * dfsphWallScale(b.xyz), r = sqrt(r2);
#if defined(DFSPH_KERNEL_WENDLAND)
        wall += psi * dfsphW(r);
#else
        float q = max(simDomainMin.w - r, 0.0);
        wall += psi * (-simKernel.y / 3.0) * q * q * q;  // psi dfsphW(r), in this order
#endif
        vec3 g = psi * dfsphGradAt(d, r);
        wallGrad += g;
        hydrostatic -= dot(simGravity.xyz, d) * g;  // g . (x_b - x_i) psi_b grad W_ib
#if defined(HAS_COLLIDERS)
        boundaryW += dot(sphFetchBoundaryVel(j).xyz, g);  // walls are at rest, colliders move
#elif defined(DFSPH_WALL_LAPLACIAN_SUM)
        boundaryW += b.w * sphViscosityLaplacian(sqrt(r2));
#endif
        boundaryNeighbours += r2 < simKernel.w ? 1.0 : 0.0;
#if defined(DFSPH_BOUNDARY_CONSTRAINTS)
        // Wall entries fill the list from its last slot down (sph_dfsph.glsl), the same way.
        dfNbr[(uint(DFSPH_MAX_NEIGHBORS) - 1u - min(blisted, uint(DFSPH_MAX_NEIGHBORS) - 1u)) * n + i] =
            vec4(g, uintBitsToFloat(j));
        blisted += r2 < simKernel.w ? 1u : 0u;
#endif
#if defined(DFSPH_SAMPLES_MARKED)
        dfCount[n + j] = 1u;  // every visiting invocation writes the same value
#endif
      }
    SPH_END_FOR_EACH_CELL_RANGE
#if defined(DFSPH_BOUNDARY_CONSTRAINTS)
    if (listed + blisted >= uint(DFSPH_MAX_NEIGHBORS)) atomicOr(stateFailure, SIM_FAIL_NEIGHBORS);
    dfCount[i] = min(listed, uint(DFSPH_MAX_NEIGHBORS)) | (min(blisted, uint(DFSPH_MAX_NEIGHBORS)) << 16u);
#else
    if (listed > uint(DFSPH_MAX_NEIGHBORS)) atomicOr(stateFailure, SIM_FAIL_NEIGHBORS);
    dfCount[i] = min(listed, uint(DFSPH_MAX_NEIGHBORS));
#endif
    dfBoundary[i] = vec4(wallGrad, boundaryW);
#if defined(SIM_WALL_CONTACT)
    bool sparse = float(listed) + boundaryNeighbours < SIM_WALL_CONTACT;
#if defined(SIM_COLLIDER_CONTACT)
    float colliderRate;
    dfBoundary[2u * n + i] = sphColliderContact(xi, float(stateTime), colliderRate);
#else
    const float colliderRate = 0.0;
#endif
    dfBoundary[n + i] = vec4(sparse ? wall - SIM_WALL_CONTACT_REST : -1e30, colliderRate, 0.0, 0.0);
#endif
    float rho = m * fluid + wall;
    vec3 g = gradSum + wallGrad;
    // The diagonal of each solve: what its own increment does to its residual. With the walls pushing
    // c times, g . (g + (c - 1) sum_b psi_b grad W_ib); floored at 0 where the walls' share opposes g.
    float divergence = dot(g, g) + squares;
    float density = max(dot(g, g + (DFSPH_DENSITY_WALL_PUSH - 1.0) * wallGrad), 0.0) + squares;
    bool surface = float(listed) + boundaryNeighbours < DFSPH_MIN_NEIGHBOURS;
    dfsph[i] = vec4(density > 1e-6 ? 1.0 / density : 0.0,
                    surface || divergence <= 1e-6 ? 0.0 : 1.0 / divergence, 0.0, 0.0);
    float pressure = DFSPH_PRESSURE_SCALE * sphFetchVel(i).w;
#if defined(DFSPH_PRESSURE_MEAN)
    if (uFrameEnd != 0u) {
      uint id = floatBitsToUint(sphFetchPos(i).w);
      pressure = impulse[id] / DFSPH_FRAME_SECONDS;
      impulse[id] = 0.0;
    }
#endif
    densityPressure[i] = vec2(rho, pressure);
#if defined(DFSPH_BOUNDARY_CONSTRAINTS)
    accel[i] = vec4(0.0);  // the samples' own stiffness holds the fluid up (no hydrostatic push)
#else
    accel[i] = vec4(-hydrostatic / rho, 0.0);
#endif
    SIM_GROUP_MAX(0, stateMaxDensity, floatBitsToUint(rho));
#if defined(DFSPH_CLOSED_PERIODIC)
    liveDensity = rho;
#endif
  }
#if defined(DFSPH_CLOSED_PERIODIC)
  uint l = gl_LocalInvocationIndex;
  groupDensity[l] = liveDensity;
  for (uint s = SIM_WG / 2u; s > 0u; s >>= 1u) {
    barrier();
    if (l < s) groupDensity[l] += groupDensity[l + s];
  }
  if (l == 0u) partial[uint(DFSPH_RESIDUAL_SLOTS) + gl_WorkGroupID.x] = groupDensity[0];
#endif
  SIM_GROUP_MAX_END();
  SIM_GROUP_MAX_FLUSH(0, stateMaxDensity);
}
