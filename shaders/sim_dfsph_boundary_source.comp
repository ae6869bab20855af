// DFSPH boundary constraints, one constant-density iteration (sim_dfsph_boundary_factor.comp), over the
// wall samples with fluid near them (the wet list, sph_dfsph.glsl):
// default: the predicted share S_b + dt D S_b / Dt - T_b of each wall sample and its projected Jacobi
//   increment (stiffness total >= 0), read by sim_dfsph_apply.comp at N + b. Runs beside
//   sim_dfsph_source.comp (both read the same velocities), dispatched over the list: a closed solve
//   (dfOpen 0) skips it. The rate sums over the sample's list (sph_dfsph.glsl);
// DFSPH_BOUNDARY_APPLY: adds the increment to the sample's total, while the solve is open (the
//   iteration that closes it applies nothing).
#define DFSPH_LIST_READ
#define DFSPH_WET_LIST
#include "sph_params.glsl"
#include "sph_neighbors.glsl"
#include "sph_dfsph.glsl"
layout(local_size_x = SIM_WG) in;
layout(std430, binding = SPHFX_SSBO_SIM_DFSPH_INCREMENT) buffer DfsphIncrement { float increment[]; };

void main() {
  uint w = sphfxGlobalIndex();
  if (w >= dfWetCount || dfOpen == 0u) return;
  uint b = dfWet[w], at = DFSPH_CAPACITY + b;
#if defined(DFSPH_BOUNDARY_APPLY)
  dfsph[at].z += increment[at];
#else
  vec4 f = dfsph[at];
  float inc = 0.0;
  if (f.x > 0.0) {
    float rate = 0.0;
#if defined(HAS_COLLIDERS)
    vec3 vb = sphFetchBoundaryVel(b).xyz;  // the body's velocity (walls: 0)
#else
    const vec3 vb = vec3(0.0);
#endif
    uint count = dfsphSampleCount(b);
    for (uint k = 0u; k < count; ++k) {
      vec4 e = dfsphSampleEntry(b, k);  // psi_b grad W(x_f - x_b), f
      rate += dot(sphFetchVel(floatBitsToUint(e.w)).xyz - vb, e.xyz);
    }
    // D S_b / Dt = sum_f psi_b (v_f - v_b) . grad W(x_f - x_b) (the samples keep their place and
    // velocity through the substep); the diagonal is in f.x.
    float dt = stateDt, residual = f.y + dt * rate;
    inc = max(f.z + DFSPH_OMEGA * residual * f.x / (dt * dt), 0.0) - f.z;
  }
  increment[at] = inc;
#endif
}
