// WCSPH pass 3: accelerations. Symmetric pressure force with the scene kernel's gradient (sphGradW),
// Akinci 2012 boundary samples of volume psi_b with their own pressure (sim_boundary_pressure.comp: the
// same pair term as between particles, so the walls conserve energy) and their viscosity
// (SIM_WALL_VISCOSITY; SIM_WALL_FRICTION: its normal push and a skin friction, sph_kernels.glsl),
// viscosity (VISCOSITY_LAPLACIAN: Mueller et al. 2003; VISCOSITY_ARTIFICIAL: Monaghan), gravity.
// Reduces max |v|^2 and |a|^2 for the CFL step.
#include "sph_params.glsl"
#include "sph_group_max.glsl"
#include "sph_neighbors.glsl"
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
layout(std430, binding = SPHFX_SSBO_SIM_BOUNDARY_PRESSURE) readonly buffer SimBoundaryPressure {
  float boundaryPressure[];  // p_b / rho_b^2 per sorted boundary sample
};
#if defined(SIM_NEIGHBOR_MASKS)
// Neighbour masks per row of cells from sim_density.comp.
layout(std430, binding = SPHFX_SSBO_SIM_NEIGHBORS) readonly buffer SimNeighbors { uint neighbors[]; };
#endif

#if defined(VISCOSITY_ARTIFICIAL)
// Monaghan's Pi_ij * rho-free factor: nu (v_ij . x_ij) / (|x_ij|^2 + 0.01 h^2) when approaching.
float artificialViscosity(vec3 vij, vec3 xij, float r2, float rhoSum) {
  float vx = dot(vij, xij);
  if (vx >= 0.0) return 0.0;
  float nu = 2.0 * simViscosity.y * simDomainMin.w * simFluid.w / rhoSum;
  return -nu * vx / (r2 + 0.01 * simKernel.w);
}
#endif

#if defined(SIM_WALL_CONTACT)
// This invocation's neighbours within h (fluid and samples), for the wall contact: the neighbour masks'
// bit counts, and fluidTerms() and boundaryTerms() for the distance-tested ranges.
float contactNeighbours = 0.0;
#endif

#if defined(SIM_WALL_FRICTION)
WallDragSums wallDrag;  // this invocation's samples within h (sph_kernels.glsl)
#endif

// Fluid neighbour j (within h, not i) of particle i: acceleration / particle mass.
vec3 fluidTerm(uint j, vec3 xi, vec3 vi, float rhoi, float dpi) {
  vec3 a = vec3(0.0);
  {
    vec3 d = sphDelta(xi, pos[j].xyz);
    float r2 = dot(d, d);
    float r = sqrt(r2);
    vec3 grad = sphGradW(d, r);
    vec2 dpj = densityPressure[j];
    float coef = dpi + dpj.y;
#if defined(VISCOSITY_ARTIFICIAL)
    coef += artificialViscosity(vi - vel[j].xyz, d, r2, rhoi + dpj.x);
#elif defined(VISCOSITY_LAPLACIAN)
    a += (simViscosity.x / dpj.x * sphViscosityLaplacian(r)) * (vel[j].xyz - vi);
#endif
    a -= coef * grad;
  }
  return a;
}

vec3 fluidTerms(uint i, vec3 xi, vec3 vi, float rhoi, float dpi, uint first, uint last) {
  vec3 a = vec3(0.0);
  for (uint j = first; j < last; ++j) {
    vec3 d = sphDelta(xi, pos[j].xyz);
    if (dot(d, d) >= simKernel.w || j == i) continue;
    a += fluidTerm(j, xi, vi, rhoi, dpi);
#if defined(SIM_WALL_CONTACT)
    contactNeighbours += 1.0;
#endif
  }
  return a * simGravity.w;
}

// Boundary sample j (within h) of particle i: acceleration.
vec3 boundaryTerm(uint j, vec3 xi, vec3 vi, float rhoi, float dpi) {
  vec3 a = vec3(0.0);
  {
    vec4 b = bpos[j];
    vec3 d = sphDelta(xi, b.xyz);
    float r2 = dot(d, d);
    float r = sqrt(r2);
    vec3 grad = sphGradW(d, r);
    // The wall sample's own p_b / rho_b^2 (never negative: no wall suction).
    float coef = dpi + boundaryPressure[j];
#if defined(SIM_WALL_FRICTION)
    wallDragAdd(wallDrag, b.w, grad, r2, bvel[j].xyz,
                -(b.w * simViscosity.w * artificialViscosity(vi - bvel[j].xyz, d, r2, 2.0 * rhoi)) * grad);
#elif defined(SIM_WALL_VISCOSITY) && defined(VISCOSITY_ARTIFICIAL)
    // Monaghan's term with fluid.wall_viscosity_speed times wall_viscosity_factor in place of alpha c.
    coef += simViscosity.w * artificialViscosity(vi - bvel[j].xyz, d, r2, 2.0 * rhoi);
#elif defined(SIM_WALL_VISCOSITY) && defined(VISCOSITY_LAPLACIAN)
    // As a fluid neighbour of mass psi_b and density rho_b = rho_i at the wall's velocity (no slip), times
    // fluid.wall_viscosity_factor.
    a += (simViscosity.w * b.w * simViscosity.x / rhoi * sphViscosityLaplacian(r)) * (bvel[j].xyz - vi);
#endif
    a -= (b.w * coef) * grad;
  }
  return a;
}

vec3 boundaryTerms(vec3 xi, vec3 vi, float rhoi, float dpi, uint first, uint last) {
  vec3 a = vec3(0.0);
  for (uint j = first; j < last; ++j) {
    vec3 d = sphDelta(xi, bpos[j].xyz);
    if (dot(d, d) >= simKernel.w) continue;
    a += boundaryTerm(j, xi, vi, rhoi, dpi);
#if defined(SIM_WALL_CONTACT)
    contactNeighbours += 1.0;
#endif
  }
  return a;
}

#if defined(SIM_WALL_CONTACT)
// The contact's velocity for a particle with few neighbours (sphWallContact(), sph_kernels.glsl): the
// sums over the samples within h, psi W, psi grad W and psi v_b . grad W, in a loop of their own, since
// only such particles (spray, sheets, drops) need them.
vec3 wallContactVelocity(vec3 xi, vec3 v, float dt) {
  float sum = 0.0, rate = 0.0;
  vec3 grad = vec3(0.0);
  SPH_FOR_EACH_CELL_RANGE(xi, row, seam, first, last)
    for (uint j = bStart[first]; j < bStart[last]; ++j) {
      vec4 b = bpos[j];
      vec3 d = sphDelta(xi, b.xyz);
      float r2 = dot(d, d);
      if (r2 >= simKernel.w) continue;
      vec3 g = sphGradW(d, sqrt(r2));
      sum += b.w * sphW(r2);
      grad += b.w * g;
#if defined(HAS_COLLIDERS)
      rate += b.w * dot(bvel[j].xyz, g);
#endif
    }
  SPH_END_FOR_EACH_CELL_RANGE
  return sphWallContact(v, grad, sum - SIM_WALL_CONTACT_REST, rate, dt);
}
#endif

void main() {
  uint i = sphfxGlobalIndex();
  bool live = i < simCounts.x;
  SIM_GROUP_MAX_BEGIN();
  if (live) {
    vec3 xi = pos[i].xyz, vi = vel[i].xyz;
    vec2 dpi = densityPressure[i];
    vec3 a = simGravity.xyz;
#if defined(SIM_WALL_FRICTION)
    wallDrag = wallDragZero();
#endif
#if defined(SIM_NEIGHBOR_MASKS)
    uint n = simCounts.x;
#endif
    SPH_FOR_EACH_CELL_RANGE(xi, row, seam, first, last)
#if defined(SIM_NEIGHBOR_MASKS)
      // The masked slots, then whatever lies past the row's 32nd slot with the distance test. The cell
      // across a periodic seam has no mask: distance-tested below.
      if (!seam) {
        uint f0 = cellStart[first], fe = cellStart[last], b0 = bStart[first], be = bStart[last];
        vec3 af = vec3(0.0);
        uint fluidMask = neighbors[row * n + i], wallMask = neighbors[(9u + row) * n + i];
#if defined(SIM_WALL_CONTACT)
        contactNeighbours += float(bitCount(fluidMask) + bitCount(wallMask));
#endif
        for (uint m = fluidMask; m != 0u; m &= m - 1u)
          af += fluidTerm(f0 + uint(findLSB(m)), xi, vi, dpi.x, dpi.y);
        a += af * simGravity.w;
        for (uint m = wallMask; m != 0u; m &= m - 1u)
          a += boundaryTerm(b0 + uint(findLSB(m)), xi, vi, dpi.x, dpi.y);
        if (fe > f0 + 32u) a += fluidTerms(i, xi, vi, dpi.x, dpi.y, f0 + 32u, fe);
        if (be > b0 + 32u) a += boundaryTerms(xi, vi, dpi.x, dpi.y, b0 + 32u, be);
        continue;
      }
#endif
      a += fluidTerms(i, xi, vi, dpi.x, dpi.y, cellStart[first], cellStart[last]);
      a += boundaryTerms(xi, vi, dpi.x, dpi.y, bStart[first], bStart[last]);
    SPH_END_FOR_EACH_CELL_RANGE
#if defined(SIM_WALL_FRICTION)
    a += wallDragAcceleration(wallDrag, vi, stateDt);  // the last step's dt, as the wall contact
#endif
#if defined(SIM_WALL_CONTACT)
    // The step's dt is set after this pass (sim_timestep.comp) from its reductions: the contact takes the
    // last step's, which the CFL rule changes little from step to step; it is checked again every step.
    if (contactNeighbours < SIM_WALL_CONTACT && stateDt > 0.0) {
      vec3 v = vi + stateDt * a;
      a += (wallContactVelocity(xi, v, stateDt) - v) / stateDt;
    }
#endif
    accel[i] = vec4(a, 0.0);
    SIM_GROUP_MAX(0, stateMaxSpeed2, floatBitsToUint(dot(vi, vi)));
    SIM_GROUP_MAX(1, stateMaxAccel2, floatBitsToUint(dot(a, a)));
  }
  SIM_GROUP_MAX_END();
  SIM_GROUP_MAX_FLUSH(0, stateMaxSpeed2);
  SIM_GROUP_MAX_FLUSH(1, stateMaxAccel2);
}
