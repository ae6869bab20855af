// WCSPH: density and pressure of every boundary sample, as if it were a particle of mass psi_b that
// does not move (summation over fluid particles of mass m and boundary samples of volume psi): the wall
// pushes back with its own pressure, sim_force.comp's pair term psi_b (p_i / rho_i^2 + p_b / rho_b^2).
// The pair force is then the gradient of the fluid's and the walls' internal energy together, so
// particles bouncing off a wall cannot gain energy (a pressure mirrored or extrapolated from each
// particle, p_b = p_i + rho_i g . (x_b - x_i), pumps energy into them: hydrostatic tank, 1,500
// particles, +2.2 % of g H in 0.5 s); samples away from the fluid get p_b = 0.
// The samples' share of each other's density is summed only for samples with fluid within h. Without
// colliders the samples never move, so it is summed once: BOUNDARY_WALL_SHARE is the variant that
// writes it (WCSPHSolver, at the first substep), and every substep's variant reads it. (Each sum keeps
// its order, so the pressures are bit-identical to summing both over every sample every substep.)
// The samples with fluid within h are among those sim_density.comp marked (-1) this substep; a sample
// neither marked nor holding a pressure (its slot's last sample had no fluid near, so 0) would write 0
// again and is skipped, so a domain far larger than its fluid costs little more than its wet walls. With
// colliders the slots' samples change as they re-sort, but every unmarked sample's pressure is 0.
// SIM_VISIT_EVERY_SAMPLE (sim::visitEverySample()) visits them all.
#include "sph_params.glsl"
#include "sph_textures.glsl"
#include "sph_neighbors.glsl"
layout(local_size_x = SIM_WG) in;
#if !defined(HAS_COLLIDERS)
layout(std430, binding = SPHFX_SSBO_SIM_BOUNDARY_WALL_SHARE) buffer SimBoundaryWallShare {
  float wallShare[];  // sum_s psi_s W_bs over the samples, per sorted boundary sample
};
#endif
#if !defined(BOUNDARY_WALL_SHARE)
layout(std430, binding = SPHFX_SSBO_SIM_BOUNDARY_PRESSURE) buffer SimBoundaryPressure {
  float boundaryPressure[];  // p_b / rho_b^2 per sorted boundary sample (-1: marked, sim_density.comp)
};
#endif

void main() {
  uint b = sphfxGlobalIndex();
  if (b >= simCounts.y) return;
#if !defined(BOUNDARY_WALL_SHARE) && !defined(SIM_VISIT_EVERY_SAMPLE)
  if (boundaryPressure[b] == 0.0) return;  // no fluid near, now or at its last pass
#endif
  vec3 xb = sphFetchBoundaryPos(b).xyz;
  float fluid = 0.0, wall = 0.0;
#if !defined(BOUNDARY_WALL_SHARE)
  SPH_FOR_EACH_CELL_RANGE(xb, row, seam, first, last)
    SPH_FOR_EACH_FLUID(j, first, last) {
      vec3 d = sphDelta(xb, sphFetchPos(j).xyz);
      fluid += sphW(dot(d, d));
    }
  SPH_END_FOR_EACH_CELL_RANGE
  if (fluid == 0.0) {  // no fluid within h: most samples of a wall
    boundaryPressure[b] = 0.0;
    return;
  }
#endif
#if defined(HAS_COLLIDERS) || defined(BOUNDARY_WALL_SHARE)
  SPH_FOR_EACH_CELL_RANGE(xb, row, seam, first, last)
    SPH_FOR_EACH_BOUNDARY(j, first, last) {
      vec4 s = sphFetchBoundaryPos(j);
      vec3 d = sphDelta(xb, s.xyz);
      wall += s.w * sphW(dot(d, d));
    }
  SPH_END_FOR_EACH_CELL_RANGE
#else
  wall = wallShare[b];
#endif
#if defined(BOUNDARY_WALL_SHARE)
  wallShare[b] = wall;
#else
  float rho = simGravity.w * fluid + wall;
  boundaryPressure[b] = sphPressure(rho) / (rho * rho);
#endif
}
