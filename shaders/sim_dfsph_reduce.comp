// DFSPH solver iteration, between source and apply: sums the source pass's DFSPH_RESIDUAL_SLOTS residual
// sums (its work groups' or particles', sim_dfsph_source.comp) in a fixed order (deterministic), and ends
// the solve on the GPU once the average error is within tolerance after DFSPH_MIN_ITER corrections, or
// after DFSPH_MAX_ITER: it empties the solve's indirect dispatches, so the CPU queues iterations without
// reading back each one. Records the solve in the frame statistics, and counts it as unconverged when
// DFSPH_MAX_ITER stopped it above the tolerance.
#include "sph_params.glsl"
#include "sph_dfsph.glsl"
layout(local_size_x = 256) in;
layout(std430, binding = SPHFX_SSBO_SIM_DFSPH_PARTIAL) readonly buffer DfsphPartial { float partial[]; };
shared float sums[256];

void main() {
  uint l = gl_LocalInvocationIndex;
  float s = 0.0;
  for (uint k = l; k < uint(DFSPH_RESIDUAL_SLOTS); k += 256u) s += partial[k];
  sums[l] = s;
  for (uint w = 128u; w > 0u; w >>= 1u) {
    barrier();
    if (l < w) sums[l] += sums[l + w];
  }
  if (l != 0u) return;
  float error = sums[0] / float(max(simCounts.x, 1u));  // (a varying count may be 0)
#if defined(DFSPH_DIVERGENCE)
  // The divergence error as the relative density change it causes over one time step (SPlisHSPlasH's
  // criterion): mean |D rho/Dt| / rho0 * dt. dt is the last substep's (this substep's is chosen after the
  // solve); a frame's first substep uses dt_max (the strictest choice), or the fixed dt.
  error *= simStep.w > 0.0 ? simStep.w : (stateSubsteps > 0u ? stateDt : simLimits.y);
#endif
#if defined(DFSPH_CAPPED_TOLERANCE) && !defined(DFSPH_DIVERGENCE)
  // A step that dt_max or the viscosity's bound set below the depth cap (not the flow) takes the tolerance
  // scaled to its fall (gpu_types: dfsphCappedDensityTolerance()).
  float tolerance = stateFlowLimited != 0u ? DFSPH_TOLERANCE : DFSPH_CAPPED_TOLERANCE;
#else
  float tolerance = DFSPH_TOLERANCE;
#endif
  uint it = dfIteration;
  dfLastError = error;
  if ((it >= uint(DFSPH_MIN_ITER) && error <= tolerance) || it >= uint(DFSPH_MAX_ITER)) {
    dfOpen = 0u;
    for (uint k = 0u; k < 9u; ++k) dfArgs[k] = 0u;
    uint S = uint(DFSPH_SOLVE);
    dfSolves[S] += 1u;
    dfIterSum[S] += it;
    dfIterMax[S] = max(dfIterMax[S], it);
    dfErrorSum[S] += error;
    dfErrorMax[S] = max(dfErrorMax[S], error);
    if (error > tolerance) dfUnconverged[S] += 1u;  // stopped by DFSPH_MAX_ITER
  } else {
    dfIteration = it + 1u;
  }
}
