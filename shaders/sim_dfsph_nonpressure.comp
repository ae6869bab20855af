// DFSPH non-pressure accelerations: gravity and viscosity (the WCSPH force pass's models without its
// pressure term, SIM_WALL_FRICTION's walls included), evaluated on the divergence-free velocities, plus
// the constant-density solve's warm start as a pressure acceleration (sim_dfsph_source.comp) and the
// walls' hydrostatic push the factor pass left in accel. Reduces max |v|^2 and max |a|^2 of the
// non-pressure accelerations for the displacement-bounded CFL step (sim_timestep.comp).
#define DFSPH_LIST_READ
#include "sph_params.glsl"
#include "sph_group_max.glsl"
#include "sph_neighbors.glsl"
#include "sph_dfsph.glsl"
layout(local_size_x = SIM_WG) in;
layout(std430, binding = SPHFX_SSBO_SIM_ACCEL) buffer SimAccel { vec4 accel[]; };

#if defined(VISCOSITY_ARTIFICIAL)
// Monaghan's viscosity as in sim_force.comp: nu (v_ij . x_ij) / (|x_ij|^2 + 0.01 h^2) when approaching.
float artificialViscosity(vec3 vij, vec3 xij, float r2, float rhoSum) {
  float vx = dot(vij, xij);
  if (vx >= 0.0) return 0.0;
  float nu = 2.0 * simViscosity.y * simDomainMin.w * simFluid.w / rhoSum;
  return -nu * vx / (r2 + 0.01 * simKernel.w);
}
#endif

// Viscosity and the warm-started pressure acceleration of particle i. Fluid neighbours come from the
// substep's list (its entries hold m grad W), boundary samples from the grid (only rows near walls and
// colliders hold any). `pressure` is the constant-density solve's warm start as an acceleration,
// -sum_j (P_i + P_j) m grad W_ij - c P_i sum_b psi_b grad W_ib (c = DFSPH_DENSITY_WALL_PUSH) with
// P = DFSPH_DENSITY_WARM_BEFORE_STEP times the last substep's total (vel.w), and with constraint walls
// -sum_b P_b psi_b grad W_ib (P_b already shared, sim_dfsph_boundary_factor.comp), so that the solve's warm
// pass needs no list pass of its own (sim_dfsph_source.comp only predicts v* = v + dt a).
void viscosityAndWarmPressure(uint i, vec3 xi, vec3 vi, float rhoi, float pi, out vec3 visc,
                              out vec3 pressure) {
  vec3 fluid = vec3(0.0), wall = vec3(0.0), push = -(DFSPH_DENSITY_WALL_PUSH * pi) * dfsphBoundary(i).xyz;
  uint count = dfsphCount(i);
#if defined(DFSPH_BOUNDARY_CONSTRAINTS)
  uint walls = dfsphBoundaryCount(i);
  for (uint k = 0u; k < walls; ++k) {
    vec4 e = dfsphBoundaryEntry(i, k);
    push -= dfsphParticle(DFSPH_CAPACITY + floatBitsToUint(e.w)).z * e.xyz;
  }
#endif
  for (uint k = 0u; k < count; ++k) {
    vec4 e = dfsphEntry(i, k);
    uint j = floatBitsToUint(e.w);
    vec4 vj = sphFetchVel(j);
    push -= (pi + DFSPH_DENSITY_WARM_BEFORE_STEP * vj.w) * e.xyz;
#if defined(VISCOSITY_ARTIFICIAL) || defined(VISCOSITY_LAPLACIAN)
    vec3 d = sphDelta(xi, sphFetchPos(j).xyz);
#if defined(VISCOSITY_ARTIFICIAL)
    fluid -= artificialViscosity(vi - vj.xyz, d, dot(d, d), rhoi + sphFetchDensity(j).x) * e.xyz;
#else
    fluid += (simViscosity.x / sphFetchDensity(j).x * simGravity.w * sphViscosityLaplacian(length(d))) *
             (vj.xyz - vi);
#endif
#endif
  }
#if defined(DFSPH_WALL_LAPLACIAN_SUM)
  wall = -(simViscosity.w * simViscosity.x / rhoi * dfsphBoundary(i).w) * vi;
#elif defined(SIM_WALL_VISCOSITY) || defined(SIM_WALL_FRICTION)
#if defined(SIM_WALL_FRICTION)
  WallDragSums drag = wallDragZero();
#endif
  SPH_FOR_EACH_CELL_RANGE(xi, row, seam, first, last)
    SPH_FOR_EACH_BOUNDARY(j, first, last) {
      vec4 b = sphFetchBoundaryPos(j);
      vec3 d = sphDelta(xi, b.xyz);
      float r2 = dot(d, d);
      if (r2 >= simKernel.w) continue;
      float r = sqrt(r2);
#if defined(HAS_COLLIDERS)
      vec3 vb = sphFetchBoundaryVel(j).xyz;
#else
      const vec3 vb = vec3(0.0);  // walls are at rest; only colliders move
#endif
#if defined(SIM_WALL_FRICTION)
      vec3 grad = dfsphGradAt(d, r);
      wallDragAdd(drag, b.w, grad, r2, vb,
                  -(b.w * simViscosity.w * artificialViscosity(vi - vb, d, r2, 2.0 * rhoi)) * grad);
#elif defined(VISCOSITY_ARTIFICIAL)
      wall -= b.w * artificialViscosity(vi - vb, d, r2, 2.0 * rhoi) * dfsphGradAt(d, r);
#else
      // As a fluid neighbour of mass psi_b and density rho_i at the wall's velocity (no slip), as in
      // sim_force.comp.
      wall += (b.w * simViscosity.x / rhoi * sphViscosityLaplacian(r)) * (vb - vi);
#endif
    }
  SPH_END_FOR_EACH_CELL_RANGE
#if defined(SIM_WALL_FRICTION)
  wall = wallDragAcceleration(drag, vi, stateDt);  // the last step's dt (this pass's sets the next)
#else
  wall *= simViscosity.w;  // the walls' term over the fluid's (Scene::wallViscosityMultiple)
#endif
#endif
  visc = fluid + wall;
  pressure = push;
}

void main() {
  uint i = sphfxGlobalIndex();
  bool live = i < simCounts.x;
  SIM_GROUP_MAX_BEGIN();
  if (live) {
    vec4 v = sphFetchVel(i);
    vec3 xi = sphFetchPos(i).xyz, vi = v.xyz, visc, pressure;
    viscosityAndWarmPressure(i, xi, vi, sphFetchDensity(i).x, DFSPH_DENSITY_WARM_BEFORE_STEP * v.w, visc,
                             pressure);
    // The time step bounds the non-pressure acceleration only (the solve decides the pressure).
    vec3 a = simGravity.xyz + visc;
    accel[i] = vec4(a + pressure + accel[i].xyz, 0.0);  // accel: the walls' hydrostatic push
    SIM_GROUP_MAX(0, stateMaxSpeed2, floatBitsToUint(dot(vi, vi)));
    SIM_GROUP_MAX(1, stateMaxAccel2, floatBitsToUint(dot(a, a)));
  }
  SIM_GROUP_MAX_END();
  SIM_GROUP_MAX_FLUSH(0, stateMaxSpeed2);
  SIM_GROUP_MAX_FLUSH(1, stateMaxAccel2);
}
