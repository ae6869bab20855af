// DFSPH with the pressure cached (DFSPH_PRESSURE_MEAN): after a substep's constant-density solve, adds the
// substep's pressure impulse per particle id, DFSPH_PRESSURE_SCALE (P dt + K) with P the constant-density
// solve's total (vel.w, applied as an acceleration over the step) and K the divergence solve's (applied as
// a velocity change). The factor pass at the frame's end (sim_dfsph_factor.comp, uFrameEnd) caches the sum
// over the frame's time and clears it. A substep's constant-density pressure alone depends on how the
// frame's steps were cut (it is larger after a shortened step, which the divergence solves' impulses
// offset); the frame's sum does not (DFSPH.CachedPressureDoesNotDependOnHowTheFramesStepsWereCut).
#define DFSPH_LIST_READ
#include "sph_params.glsl"
#include "sph_kernels.glsl"
#include "sph_dfsph.glsl"
layout(local_size_x = SIM_WG) in;
layout(std430, binding = SPHFX_SSBO_SIM_DFSPH_PRESSURE_IMPULSE) buffer DfsphPressureImpulse { float impulse[]; };

void main() {
  uint i = sphfxGlobalIndex();
  if (i >= simCounts.x) return;
  uint id = floatBitsToUint(sphFetchPos(i).w);
  impulse[id] += DFSPH_PRESSURE_SCALE * (sphFetchVel(i).w * stateDt + dfsphParticle(i).w);
}
